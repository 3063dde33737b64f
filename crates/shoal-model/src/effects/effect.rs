//! What an effect is: the trait every effect implements ([`Effect`]), the parameters it
//! declares ([`ParamInfo`]), the order of its thrust hooks ([`Stage`]) and what its hooks may
//! look at ([`ThrustContext`], [`ForceContext`]). The effects of this module implement it; the
//! catalogue and the combined hooks of a vehicle build on it.

use crate::math::{Vec3, Vec6};
use crate::rigid_body::RigidState;
use crate::thruster::ThrusterParams;
use crate::vehicle_params::VehicleParams;
use std::fmt;

/// One parameter of an effect.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamInfo {
    /// Name, unique within the effect, with its unit as a suffix where it has one
    /// (e.g. `tau_s`, `delta_f_n`).
    pub name: &'static str,
    /// Unit in words (e.g. `s`, `N`, `-`).
    pub unit: &'static str,
    /// Smallest allowed value (in [`ParamInfo::unit`]).
    pub lo: f64,
    /// Largest allowed value (in [`ParamInfo::unit`]).
    pub hi: f64,
    /// The value at which the effect has no influence (in [`ParamInfo::unit`]).
    pub null: f64,
    /// A typical non-null value, used as a second starting point by fits (in
    /// [`ParamInfo::unit`]).
    pub typical: f64,
    /// What the parameter means.
    pub doc: &'static str,
    /// A shape parameter: it changes how the effect acts, not whether it acts (a time
    /// constant of an exponential, a softness). It has no null value of its own — `null`
    /// holds a neutral default — and is never tested against it; the effect vanishes when its
    /// other parameters are at their nulls.
    pub shape: bool,
}

/// In which order thrust hooks run: every `Command` hook, then the thrust curve, then every
/// `Scale` hook, then every `Limit` hook (each group in the order the effects were given).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// Changes the command or scales the thrust.
    Scale,
    /// Limits the thrust (applied last).
    Limit,
}

/// What a thrust hook may look at.
#[derive(Clone, Copy, Debug)]
pub struct ThrustContext<'a> {
    /// Time since the start of the run \[s\].
    pub t: f64,
    /// The thruster.
    pub thruster: &'a ThrusterParams,
    /// The command after clamping to ±`max_command` [%].
    pub command: f64,
    /// Axial inflow: the water's speed into the propeller along its thrust direction, i.e.
    /// the thruster's velocity through the water projected on its thrust direction [m/s].
    pub inflow: f64,
}

/// What a force hook may look at.
#[derive(Clone, Copy, Debug)]
pub struct ForceContext<'a> {
    /// Time since the start of the run \[s\].
    pub t: f64,
    /// The hull's pose and velocity.
    pub rigid: &'a RigidState,
    /// Force of all thrusters together, body frame \[N\].
    pub thrust_force: Vec3,
    /// Moment of all thrusters together about the body origin, body frame [N·m].
    pub thrust_moment: Vec3,
    /// The vehicle.
    pub vehicle: &'a VehicleParams,
    /// Gravitational acceleration [m/s²].
    pub gravity: f64,
    /// Water density [kg/m³].
    pub density: f64,
}

impl<'a> ForceContext<'a> {
    /// What a force hook sees of the hull `rigid` of `vehicle` at time `t` \[s\] with the
    /// thrusters idle, in water of `env` — for evaluating a force law on its own.
    pub fn idle(
        t: f64,
        rigid: &'a RigidState,
        vehicle: &'a VehicleParams,
        env: &crate::rigid_body::Environment,
    ) -> Self {
        Self {
            t,
            rigid,
            thrust_force: Vec3::zeros(),
            thrust_moment: Vec3::zeros(),
            vehicle,
            gravity: env.gravity,
            density: env.density,
        }
    }
}

/// A parametric model extension. Parameters arrive as a slice in the order of
/// [`Effect::params`], already checked against their bounds.
pub trait Effect: Send + Sync + fmt::Debug {
    /// Stable name (snake case), as used in files and reports.
    fn name(&self) -> &'static str;
    /// Which form of its family this is (e.g. `hard` or `soft` for a dead band). An effect
    /// family is every catalogue entry with the same [`Effect::name`]; its forms compete as
    /// alternative shapes of one physical cause and are never named together.
    fn form(&self) -> &'static str {
        "standard"
    }
    /// What the effect is, in one sentence.
    fn summary(&self) -> &'static str;
    /// The physical cause it stands for and how it is modelled (shown in reports).
    fn explanation(&self) -> &'static str;
    /// The parameters, with bounds that may depend on the vehicle (e.g. a force bound scaled
    /// by its weight).
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo>;
    /// Why the effect cannot apply to this vehicle, if it cannot (e.g. no buoyancy tank).
    fn not_applicable(&self, _vehicle: &VehicleParams) -> Option<String> {
        None
    }
    /// Which group of thrust hooks this effect's [`Effect::thrust`] belongs to.
    fn stage(&self) -> Stage {
        Stage::Scale
    }
    /// Changes the vehicle's parameters once, when the model is built.
    fn configure(&self, _p: &[f64], _vehicle: &mut VehicleParams) {}
    /// A constant water current added to the world's, world frame [m/s].
    fn current(&self, _p: &[f64]) -> Vec3 {
        Vec3::zeros()
    }
    /// The command [%] that reaches the thrust curve, given the clamped command `n` [%].
    fn command(&self, _p: &[f64], _thruster: &ThrusterParams, n: f64) -> f64 {
        n
    }
    /// The thrust \[N\] after this effect, given the thrust `f` \[N\] so far.
    fn thrust(&self, _p: &[f64], _ctx: &ThrustContext<'_>, f: f64) -> f64 {
        f
    }
    /// An additional generalised force on the hull, body frame [N, N·m], held over a step.
    fn force(&self, _p: &[f64], _ctx: &ForceContext<'_>) -> Vec6 {
        Vec6::zeros()
    }
    /// An offset added to the true depth before the pressure sensor reads it \[m\], at time
    /// `t` \[s\] since the start.
    fn depth_offset(&self, _p: &[f64], _t: f64) -> f64 {
        0.0
    }
    /// How much every measurement lags the truth \[s\].
    fn delay(&self, _p: &[f64]) -> f64 {
        0.0
    }
}
