//! A whole vehicle: the derived constants shared by all vehicles of one kind
//! ([`VehicleModel`], built from a [`VehicleParams`] with any model extensions from
//! [`crate::effects`]), the per-vehicle state ([`VehicleState`]), one physics step ([`step`])
//! and one sensor sample ([`sense`]).

use crate::control::{
    ActuatorCommands, ControllerState, SensorReadings, Uauv2Control, Uauv2Layout,
};
use crate::dynamics::{Integrator, RigidState, integrate, rk4_with};
use crate::effects::{Effects, ForceContext};
use crate::lanes::DynConsts;
use crate::math::{PerActuator, Vec3, Vec6, split6};
use crate::rigid_body::{Environment, MassProperties};
use crate::thruster::{ActuatorState, actuate, actuate_with};
use rand::Rng;
use std::collections::VecDeque;
use std::sync::Arc;

/// The parameters a vehicle model is built from, described in [`crate::vehicle_params`]
/// (also reachable here, where users of the whole vehicle look for them).
pub use crate::vehicle_params::VehicleParams;

/// Immutable, shareable description of a vehicle kind with derived constants.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleModel {
    /// The parameters in effect: the given ones with the effects' [`configure`] hooks
    /// applied.
    ///
    /// [`configure`]: crate::effects::Effect::configure
    pub params: VehicleParams,
    /// Model extensions (empty for a plain model).
    pub effects: Effects,
    /// Gains and limits of the paper's modes, if the vehicle has the μAUV² layout. Designed
    /// on the parameters as given, before effects: the controller is built for the model its
    /// designer believes in.
    pub uauv2: Option<Uauv2Control>,
    /// Effective heave mass m + A₃₃ at the initial ballast, before effects \[kg\].
    pub heave_mass: f64,
    /// Effective yaw inertia I_zz + A₆₆ at the initial ballast, before effects [kg·m²].
    pub yaw_inertia: f64,
    /// Water density the derived constants are for [kg/m³].
    pub density: f64,
    /// Mass properties at the initial ballast in water of [`Self::density`], shared by every
    /// vehicle of the kind until its pump changes its ballast.
    pub rest_mass: Arc<MassProperties>,
}

impl VehicleModel {
    /// Derives the constants for water of `density` [kg/m³].
    pub fn new(params: VehicleParams, density: f64) -> Self {
        Self::with_effects(params, Effects::default(), density)
    }

    /// A model with extensions: `params` is the baseline, `effects` what is added to it.
    pub fn with_effects(params: VehicleParams, effects: Effects, density: f64) -> Self {
        let mp = params.mass_properties(params.initial_ballast(), density);
        let heave_mass = mp.m_total[(2, 2)];
        let yaw_inertia = mp.m_total[(5, 5)];
        let uauv2 = Uauv2Layout::find(&params.thrusters, &params.tilts).map(|l| {
            Uauv2Control::new(
                l,
                &params.control,
                &params.thrusters,
                heave_mass,
                yaw_inertia,
            )
        });
        let mut params = params;
        effects.configure(&mut params);
        let rest_mass = Arc::new(params.mass_properties(params.initial_ballast(), density));
        Self {
            params,
            effects,
            uauv2,
            heave_mass,
            yaw_inertia,
            density,
            rest_mass,
        }
    }

    /// The water as this vehicle's dynamics see it (the world's plus any current from the
    /// effects).
    #[inline]
    pub fn environment(&self, env: &Environment) -> Environment {
        if self.effects.is_empty() {
            *env
        } else {
            Environment {
                current: env.current + self.effects.current(),
                ..*env
            }
        }
    }

    /// A fresh controller state for this vehicle.
    pub fn controller(&self) -> ControllerState {
        ControllerState::new(
            &self.params.control,
            self.params.thrusters.len(),
            self.params.tilts.len(),
        )
    }

    /// All-zero actuator commands for this vehicle.
    pub fn zero_commands(&self) -> ActuatorCommands {
        ActuatorCommands::zeros(self.params.thrusters.len(), self.params.tilts.len())
    }
}

/// Dynamic state of one vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleState {
    /// Pose and velocity.
    pub rigid: RigidState,
    /// Tilt angles and actual thrusts.
    pub actuators: ActuatorState,
    /// Water in the buoyancy tank \[m³\].
    pub ballast_volume: f64,
    /// Mass properties for the current ballast (cache; shared with the kind's
    /// [`VehicleModel::rest_mass`] while the ballast is the initial one, so a swarm of quiet
    /// vehicles keeps one copy). Change it with [`VehicleState::set_mass`].
    pub mass: Arc<MassProperties>,
    /// Mean body acceleration over the last step, ν̇ [m/s², rad/s²].
    pub accel: Vec6,
    /// Thruster force applied during the last step, body frame [N, N·m] (including the
    /// effects' forces).
    pub tau: Vec6,
    /// Time since the vehicle started \[s\].
    pub time: f64,
    /// Readings waiting to be released by a sensor delay, oldest first, with the time each
    /// was taken \[s\].
    ///
    /// Boxed: only vehicles whose model has a sensor delay use it, and the rest should not
    /// carry an empty queue inline.
    pub delayed: Option<Box<VecDeque<(f64, SensorReadings)>>>,
}

impl VehicleState {
    /// A vehicle at rest in the given pose with its initial ballast.
    pub fn new(model: &VehicleModel, rigid: RigidState, env: &Environment) -> Self {
        let p = &model.params;
        let vol = p.initial_ballast();
        Self {
            rigid,
            actuators: ActuatorState {
                tilt: PerActuator::from_elem(0.0, p.tilts.len()),
                thrust: PerActuator::from_elem(0.0, p.thrusters.len()),
                // Both filled on the first step of a thruster that needs them.
                stage: Vec::new(),
                command: Vec::new(),
            },
            ballast_volume: vol,
            mass: if env.density == model.density {
                model.rest_mass.clone()
            } else {
                Arc::new(p.mass_properties(vol, env.density))
            },
            accel: Vec6::zeros(),
            tau: Vec6::zeros(),
            time: 0.0,
            delayed: None,
        }
    }

    /// Replaces the mass properties (in place when this vehicle already has its own copy).
    pub fn set_mass(&mut self, mass: MassProperties) {
        *Arc::make_mut(&mut self.mass) = mass;
    }

    /// Books a completed rigid-body step of `dt` \[s\] that started with velocity `nu0`:
    /// the mean acceleration over the step and the vehicle's clock.
    #[inline]
    pub fn finish_step(&mut self, nu0: &Vec6, dt: f64) {
        self.accel = (self.rigid.nu - nu0) / dt;
        self.time += dt;
    }

    /// Depth of a body-frame point \[m\].
    #[inline]
    pub fn depth_of(&self, body_point: &Vec3) -> f64 {
        self.rigid.position.z + self.rigid.attitude.transform_vector(body_point).z
    }
}

/// Actuation for one step of `dt` \[s\]: runs the pump, moves the tilt drives, updates the
/// thrust lags and stores the resulting generalised force in `state.tau`.
pub fn actuate_vehicle(
    model: &VehicleModel,
    state: &mut VehicleState,
    cmd: &ActuatorCommands,
    env: &Environment,
    dt: f64,
) {
    if let Some(v) = run_pump(model, state, cmd.pump, dt) {
        state.set_mass(model.params.mass_properties(v, env.density));
    }
    actuate_thrusters(model, state, cmd, env, dt);
}

/// The pump's part of [`actuate_vehicle`]: advances the ballast water by one step of `dt`
/// \[s\] and returns the new volume \[m³\] when it changed — the caller then owes the vehicle
/// its new [`VehicleState::mass`] (`mass_properties(volume, density)`, or the same values
/// kept from an earlier step).
pub fn run_pump(
    model: &VehicleModel,
    state: &mut VehicleState,
    pump: crate::ballast::Pump,
    dt: f64,
) -> Option<f64> {
    let b = model.params.ballast.as_ref()?;
    let v = b.advance(state.ballast_volume, pump, dt);
    (v != state.ballast_volume).then(|| {
        state.ballast_volume = v;
        v
    })
}

/// The rest of [`actuate_vehicle`] after the pump: moves the tilt drives, updates the thrust
/// lags and stores the resulting generalised force in `state.tau`.
pub fn actuate_thrusters(
    model: &VehicleModel,
    state: &mut VehicleState,
    cmd: &ActuatorCommands,
    env: &Environment,
    dt: f64,
) {
    let p = &model.params;
    let rigid = &state.rigid;
    // A point within |r| of a body origin deeper than |r| is under water whatever the
    // attitude; only vehicles near the surface need the rotation.
    let z = rigid.position.z;
    let submerged = |r: &Vec3| {
        (z > 0.0 && z * z > r.norm_squared()) || z + rigid.attitude.transform_vector(r).z > 0.0
    };
    if model.effects.is_empty() {
        state.tau = actuate(
            &p.thrusters,
            &p.tilts,
            &mut state.actuators,
            &cmd.thrusters,
            &cmd.tilts,
            submerged,
            dt,
        );
        return;
    }
    let fx = &model.effects;
    let t = state.time;
    let (v, w) = split6(&rigid.nu);
    let tau = actuate_with(
        &p.thrusters,
        &p.tilts,
        &mut state.actuators,
        &cmd.thrusters,
        &cmd.tilts,
        submerged,
        |th, n, dir| {
            let inflow = (v + w.cross(&th.position)).dot(dir);
            fx.thrust(th, n, t, inflow)
        },
        dt,
    );
    let (thrust_force, thrust_moment) = split6(&tau);
    let extra = fx.force(&ForceContext {
        t,
        rigid,
        thrust_force,
        thrust_moment,
        vehicle: p,
        gravity: env.gravity,
        density: env.density,
    });
    state.tau = tau + extra;
}

/// Rigid-body integration for one step of `dt` \[s\] with `state.tau` held constant.
pub fn integrate_vehicle(
    model: &VehicleModel,
    state: &mut VehicleState,
    env: &Environment,
    integrator: Integrator,
    dt: f64,
) {
    let nu0 = state.rigid.nu;
    integrate(
        integrator,
        &model.params.body,
        &state.mass,
        &model.environment(env),
        &mut state.rigid,
        &state.tau,
        dt,
    );
    state.finish_step(&nu0, dt);
}

/// [`integrate_vehicle`] with classic RK4 and the constants of its equation of motion
/// prepared by the caller: `consts` must be `DynConsts::new(&model.params.body, &state.mass,
/// &model.environment(env))` (a replay keeps them while the ballast does not change).
pub fn integrate_vehicle_rk4(state: &mut VehicleState, consts: &DynConsts, dt: f64) {
    let nu0 = state.rigid.nu;
    rk4_with(consts, &mut state.rigid, &state.tau, dt);
    state.finish_step(&nu0, dt);
}

/// Advances one vehicle by `dt` \[s\]: pump, tilt drives and thrusters (→ τ), then the rigid
/// body with τ held over the step.
pub fn step(
    model: &VehicleModel,
    state: &mut VehicleState,
    cmd: &ActuatorCommands,
    env: &Environment,
    integrator: Integrator,
    dt: f64,
) {
    actuate_vehicle(model, state, cmd, env, dt);
    integrate_vehicle(model, state, env, integrator, dt);
}

/// Samples the sensors into `out`, drawing noise from `rng`. With a sensor delay among the
/// model's effects, `out` receives the newest sample at least that old (a fresh sample while
/// no sample is that old yet: the vehicle is taken to have been as it is now before it
/// started), and `state` keeps the samples still in flight.
pub fn sense<R: Rng + ?Sized>(
    model: &VehicleModel,
    state: &mut VehicleState,
    env: &Environment,
    rng: &mut R,
    out: &mut SensorReadings,
) {
    sample(model, state, env, rng, out);
    let delay = model.effects.delay();
    if delay > 0.0 {
        let now = state.time;
        let delayed = state.delayed.get_or_insert_default();
        delayed.push_back((now, out.clone()));
        // Release the newest reading taken at or before now − delay; keep it at the front.
        while delayed.len() > 1 && delayed[1].0 <= now - delay + 1e-9 {
            delayed.pop_front();
        }
        if let Some((t, r)) = delayed.front()
            && *t <= now - delay + 1e-9
        {
            out.clone_from(r);
        }
    }
}

fn sample<R: Rng + ?Sized>(
    model: &VehicleModel,
    state: &VehicleState,
    env: &Environment,
    rng: &mut R,
    out: &mut SensorReadings,
) {
    let p = &model.params;
    let mut depth = state.depth_of(&p.pressure.position);
    if !model.effects.is_empty() {
        depth = depth.max(0.0) + model.effects.depth_offset(state.time);
    }
    out.depth = p.pressure.read(depth, rng);
    let (v, w) = split6(&state.rigid.nu);
    let (a_lin, _) = split6(&state.accel);
    let accel_body = a_lin + w.cross(&v);
    let imu = p
        .imu
        .read(&state.rigid.attitude, &w, &accel_body, env.gravity, rng);
    out.attitude = imu.attitude;
    out.gyro = imu.gyro;
    out.accel = imu.accel;
    out.tilts.clear();
    out.tilts.extend_from_slice(&state.actuators.tilt);
    out.tank_full = p
        .ballast
        .as_ref()
        .is_some_and(|b| b.is_full(state.ballast_volume));
}
