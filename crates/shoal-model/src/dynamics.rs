//! Fixed-step integrators (classic RK4, and a cheaper semi-implicit
//! Euler) for the equation of motion of [`crate::rigid_body`], which also holds the state
//! they advance ([`RigidState`], re-exported here).
//!
//! The state holds the velocity **relative to the water** ν_r (body frame); the kinematics add
//! the current: ṗ = R(q) v_r + v_c, q̇ = ½ q ⊗ (0, ω). With no current ν_r is the ordinary body
//! velocity.

use crate::lanes::{DynConsts, Lanes, rk4};
use crate::math::{Quat, Vec6, split6};
pub use crate::rigid_body::RigidState;
use crate::rigid_body::{BodyParams, Environment, MassProperties, acceleration};

/// Which fixed-step integrator to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Integrator {
    /// Classic 4th-order Runge–Kutta (4 force evaluations per step).
    #[default]
    Rk4,
    /// Semi-implicit (symplectic) Euler: velocity first, then pose with the new velocity
    /// (1 force evaluation per step).
    SemiImplicitEuler,
}

/// Advances `state` by `dt` \[s\] with the force `tau` held constant over the step.
pub fn integrate(
    integrator: Integrator,
    body: &BodyParams,
    mp: &MassProperties,
    env: &Environment,
    state: &mut RigidState,
    tau: &Vec6,
    dt: f64,
) {
    match integrator {
        Integrator::Rk4 => rk4_with(&DynConsts::new(body, mp, env), state, tau, dt),
        Integrator::SemiImplicitEuler => {
            let a = acceleration(
                body,
                mp,
                env,
                &state.position,
                &state.attitude,
                &state.nu,
                tau,
            );
            state.nu += a * dt;
            let (v, w) = split6(&state.nu);
            state.position += (state.attitude * v + env.current) * dt;
            state.attitude *= Quat::from_scaled_axis(w * dt);
        }
    }
}

/// One classic RK4 step of `dt` \[s\] with the force `tau` held, given the constants of the
/// equation of motion (`DynConsts::new(body, mp, env)`, which a caller stepping one hull many
/// times keeps while they do not change). It is the swarm's lane kernel with one lane, so that
/// a hull integrated alone and one in a swarm give the same result.
pub fn rk4_with(c: &DynConsts, state: &mut RigidState, tau: &Vec6, dt: f64) {
    let mut x = Lanes::<1>::default();
    x.load(0, state, tau);
    rk4(c, &mut x, dt);
    x.store(0, state);
}
