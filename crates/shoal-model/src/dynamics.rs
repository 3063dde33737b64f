//! Rigid-body state and fixed-step integrators (classic RK4, and a cheaper semi-implicit
//! Euler) for the equation of motion of [`crate::rigid_body`].
//!
//! The state holds the velocity **relative to the water** ν_r (body frame); the kinematics add
//! the current: ṗ = R(q) v_r + v_c, q̇ = ½ q ⊗ (0, ω). With no current ν_r is the ordinary body
//! velocity.

use crate::math::{Quat, Vec3, Vec6, split6};
use crate::rigid_body::{BodyParams, Environment, MassProperties};
use nalgebra::Quaternion;

/// Position, attitude and velocity of one hull.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidState {
    /// Position of the body origin in the world (NED) frame \[m\]; `z` is depth.
    pub position: Vec3,
    /// Attitude (body → world).
    pub attitude: Quat,
    /// Velocity relative to the water, body frame: (u, v, w) [m/s], (p, q, r) [rad/s].
    pub nu: Vec6,
}

impl RigidState {
    /// Whether every component (position, attitude, velocities) is a finite number.
    pub fn is_finite(&self) -> bool {
        self.position.iter().all(|x| x.is_finite())
            && self.attitude.coords.iter().all(|x| x.is_finite())
            && self.nu.iter().all(|x| x.is_finite())
    }

    /// At rest at `position` \[m\] with attitude `attitude`.
    pub fn at_rest(position: Vec3, attitude: Quat) -> Self {
        Self {
            position,
            attitude,
            nu: Vec6::zeros(),
        }
    }

    /// Velocity over ground in the world frame [m/s].
    pub fn world_velocity(&self, env: &Environment) -> Vec3 {
        let (v, _) = split6(&self.nu);
        self.attitude * v + env.current
    }
}

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

/// Body acceleration ν̇_r [m/s², rad/s²] for the given state and applied force τ.
#[inline]
pub fn acceleration(
    body: &BodyParams,
    mp: &MassProperties,
    env: &Environment,
    position: &Vec3,
    attitude: &Quat,
    nu: &Vec6,
    tau: &Vec6,
) -> Vec6 {
    let rhs = tau
        - mp.coriolis_rb(nu)
        - body.coriolis_added(nu)
        - body.damping(nu)
        - body.restoring(mp, env, position.z, attitude);
    mp.m_inv * rhs
}

#[inline]
fn quat_rate(q: &Quaternion<f64>, omega: &Vec3) -> Quaternion<f64> {
    q * Quaternion::from_parts(0.0, *omega) * 0.5
}

struct Deriv {
    p: Vec3,
    q: Quaternion<f64>,
    nu: Vec6,
}

#[inline]
fn deriv(
    body: &BodyParams,
    mp: &MassProperties,
    env: &Environment,
    p: &Vec3,
    q: &Quaternion<f64>,
    nu: &Vec6,
    tau: &Vec6,
) -> Deriv {
    let att = Quat::new_normalize(*q);
    let (v, w) = split6(nu);
    Deriv {
        p: att * v + env.current,
        q: quat_rate(q, &w),
        nu: acceleration(body, mp, env, p, &att, nu, tau),
    }
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
        Integrator::Rk4 => {
            let p0 = state.position;
            let q0 = *state.attitude.quaternion();
            let n0 = state.nu;
            let k1 = deriv(body, mp, env, &p0, &q0, &n0, tau);
            let h = 0.5 * dt;
            let k2 = deriv(
                body,
                mp,
                env,
                &(p0 + k1.p * h),
                &(q0 + k1.q * h),
                &(n0 + k1.nu * h),
                tau,
            );
            let k3 = deriv(
                body,
                mp,
                env,
                &(p0 + k2.p * h),
                &(q0 + k2.q * h),
                &(n0 + k2.nu * h),
                tau,
            );
            let k4 = deriv(
                body,
                mp,
                env,
                &(p0 + k3.p * dt),
                &(q0 + k3.q * dt),
                &(n0 + k3.nu * dt),
                tau,
            );
            let s = dt / 6.0;
            state.position = p0 + (k1.p + (k2.p + k3.p) * 2.0 + k4.p) * s;
            state.attitude = Quat::new_normalize(q0 + (k1.q + (k2.q + k3.q) * 2.0 + k4.q) * s);
            state.nu = n0 + (k1.nu + (k2.nu + k3.nu) * 2.0 + k4.nu) * s;
        }
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
