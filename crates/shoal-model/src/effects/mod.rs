//! Model extensions ("effects"): parametric additions to a vehicle model that explain where a
//! baseline model disagrees with the real vehicle — a thrust lag, a sagging battery, a trim that
//! is not neutral, a delayed sensor, …
//!
//! Every effect is one type implementing [`Effect`], in its own file of this module, listed
//! once in [`families`] with its facts ([`FamilyFacts`]). The trait, its parameters and what its hooks see are in `effect.rs`,
//! the laws in time that several effects share in `laws.rs`, the parameters that come once
//! per thruster in `per_thruster.rs`; the effects build on those three,
//! and this file on the effects. An effect declares its parameters ([`ParamInfo`]: unit, bounds, the
//! *null* value at which it vanishes) and overrides only the hooks it needs:
//!
//! | hook | when | used by |
//! |---|---|---|
//! | [`Effect::configure`] | once, when the model is built | lag, per-thruster gain, damping, added mass, pump flow |
//! | [`Effect::current`] | kinematics | water current |
//! | [`Effect::command`] | each thruster, before the thrust curve | dead band |
//! | [`Effect::thrust`] | each thruster, after the thrust curve | gain, asymmetry, sag, inflow, saturation |
//! | [`Effect::force`] | each step, added to the thrusters' force | buoyancy offset, restoring moment, thrust coupling, tether |
//! | [`Effect::depth_offset`] | each depth reading | depth-sensor bias |
//! | [`Effect::delay`] | each sensor sample | sensor delay |
//!
//! The same effects drive `shoal run` (a vehicle model built with them,
//! `VehicleModel::with_effects`) and the model search of `shoal validate`, so a fitted
//! extension runs unchanged in a world. Adding an effect family means adding a file here (its
//! forms and its required facts) and a line to [`families`]; nothing in the search changes.

mod added_mass_error;
mod ballast_mass;
mod battery_sag;
mod buoyancy_offset;
mod damping_error;
mod depth_sensor_bias;
mod effect;
mod family;
mod inflow_thrust_loss;
mod laws;
mod per_thruster;
mod restoring_moment;
mod sensor_delay;
mod tether_drag;
mod thrust_asymmetry;
mod thrust_coupling;
mod thrust_gain;
mod thrust_map;
mod thrust_saturation;
mod thruster_deadband;
mod thruster_lag;
mod water_current;

pub use added_mass_error::AddedMassError;
pub use ballast_mass::BallastMass;
pub use battery_sag::{BatterySag, BatterySagExponential, BatterySagPower};
pub use buoyancy_offset::{
    BuoyancyOffset, BuoyancyOffsetDepth, BuoyancyOffsetDrift, BuoyancyOffsetSettling,
};
pub use damping_error::{DampingError, DampingErrorDirection, DampingErrorPower, NU_REF};
pub use depth_sensor_bias::{
    DepthSensorBias, DepthSensorBiasPower, DepthSensorBiasSCurve, DepthSensorBiasSettling,
};
pub use inflow_thrust_loss::{
    InflowThrustLoss, InflowThrustLossLinear, InflowThrustLossPower, reduced as inflow_reduced,
};
pub use per_thruster::MAX_THRUSTERS;
pub use restoring_moment::{RestoringMoment, RestoringMomentDrift, RestoringMomentSettling};
pub use sensor_delay::SensorDelay;
pub use tether_drag::{TetherDrag, TetherTaut};
pub use thrust_asymmetry::{ThrustAsymmetry, ThrustAsymmetryCurve, ThrustAsymmetrySided};
pub use thrust_coupling::{ThrustCoupling, ThrustCouplingDirection};
pub use thrust_gain::{ThrustGain, ThrustGainCurve, ThrustGainKnee, ThrustGainPerThruster};
pub use thrust_map::ThrustMap;
pub use thrust_saturation::{ThrustSaturation, ThrustSaturationAsymmetric, ThrustSaturationSmooth};
pub use thruster_deadband::{
    ThrusterDeadband, ThrusterDeadbandAsymmetric, ThrusterDeadbandGate, ThrusterDeadbandSoft,
    ThrusterDeadbandSoftAsymmetric,
};
pub use thruster_lag::{
    ThrusterLag, ThrusterLagPerThruster, ThrusterLagSecondOrder, ThrusterLagSlew, ThrusterLagUpDown,
};
pub use water_current::WaterCurrent;

pub use effect::{Effect, ForceContext, ParamInfo, Stage, ThrustContext};
pub use family::{DirectChannels, Family, FamilyFacts, Regressor};

use crate::math::{Vec3, Vec6};
use crate::thruster::ThrusterParams;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The built-in effect families in catalogue order (see `../shared/spec/validation.md`), each
/// with its forms and its facts: adding a family means adding its file and a line here.
pub fn families() -> Vec<Family> {
    vec![
        thruster_lag::family(),
        thrust_gain::family(),
        thrust_asymmetry::family(),
        thruster_deadband::family(),
        battery_sag::family(),
        inflow_thrust_loss::family(),
        buoyancy_offset::family(),
        ballast_mass::family(),
        damping_error::family(),
        added_mass_error::family(),
        restoring_moment::family(),
        water_current::family(),
        depth_sensor_bias::family(),
        sensor_delay::family(),
        thrust_coupling::family(),
        thrust_saturation::family(),
        tether_drag::family(),
    ]
}

/// The built-in effects in catalogue order, every form of a family after its first (default)
/// form.
pub fn catalogue() -> Vec<Arc<dyn Effect>> {
    families().into_iter().flat_map(|f| f.forms).collect()
}

/// The facts of the built-in family `name` (`None`: no such family).
pub fn facts(name: &str) -> Option<FamilyFacts> {
    families()
        .into_iter()
        .find(|f| f.name() == name)
        .map(|f| f.facts)
}

/// The built-in effect of that family name, in its default (first) form.
pub fn by_name(name: &str) -> Option<Arc<dyn Effect>> {
    catalogue().into_iter().find(|e| e.name() == name)
}

/// The built-in effect of that family name and form (`None`: the default form).
pub fn by_name_form(name: &str, form: Option<&str>) -> Option<Arc<dyn Effect>> {
    match form {
        None => by_name(name),
        Some(f) => catalogue()
            .into_iter()
            .find(|e| e.name() == name && e.form() == f),
    }
}

/// The forms of the family `name`, default first.
pub fn forms(name: &str) -> Vec<&'static str> {
    catalogue()
        .iter()
        .filter(|e| e.name() == name)
        .map(|e| e.form())
        .collect()
}

/// Names of the built-in effect families in catalogue order (each once).
pub fn names() -> Vec<&'static str> {
    families().iter().map(Family::name).collect()
}

/// One effect with its parameter values.
#[derive(Clone, Debug)]
pub struct EffectInstance {
    /// The effect.
    pub effect: Arc<dyn Effect>,
    /// Parameter values in the order of [`Effect::params`] (units as declared there).
    pub params: Vec<f64>,
}

impl PartialEq for EffectInstance {
    fn eq(&self, other: &Self) -> bool {
        self.effect.name() == other.effect.name()
            && self.effect.form() == other.effect.form()
            && self.params == other.params
    }
}

impl EffectInstance {
    /// The effect at its null parameters (no influence) for `vehicle`.
    pub fn null(effect: Arc<dyn Effect>, vehicle: &VehicleParams) -> Self {
        let params = effect.params(vehicle).iter().map(|p| p.null).collect();
        Self { effect, params }
    }
}

/// The effects active on one vehicle kind, with the hooks combined.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Effects {
    list: Vec<EffectInstance>,
    current: Vec3,
    delay: f64,
}

impl Effects {
    /// Combines `list` (thrust hooks run in [`Stage`] order, stable within a stage).
    pub fn new(mut list: Vec<EffectInstance>) -> Self {
        let current = list
            .iter()
            .map(|e| e.effect.current(&e.params))
            .fold(Vec3::zeros(), |a, b| a + b);
        let delay = list.iter().map(|e| e.effect.delay(&e.params)).sum();
        list.sort_by_key(|e| e.effect.stage());
        Self {
            list,
            current,
            delay,
        }
    }

    /// No effects.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The effects (thrust-hook order).
    pub fn list(&self) -> &[EffectInstance] {
        &self.list
    }

    /// Applies every [`Effect::configure`] hook to `vehicle`.
    pub fn configure(&self, vehicle: &mut VehicleParams) {
        for e in &self.list {
            e.effect.configure(&e.params, vehicle);
        }
    }

    /// Extra water current, world frame [m/s].
    pub fn current(&self) -> Vec3 {
        self.current
    }

    /// Total measurement delay \[s\].
    pub fn delay(&self) -> f64 {
        self.delay
    }

    /// Static thrust \[N\] of `thruster` for the clamped command `n` [%] with the effects.
    pub fn thrust(&self, thruster: &ThrusterParams, n: f64, t: f64, inflow: f64) -> f64 {
        let mut cmd = n;
        for e in &self.list {
            cmd = e.effect.command(&e.params, thruster, cmd);
        }
        let mut f = thruster.curve.thrust(cmd);
        let ctx = ThrustContext {
            t,
            thruster,
            command: n,
            inflow,
        };
        for e in &self.list {
            f = e.effect.thrust(&e.params, &ctx, f);
        }
        f
    }

    /// Sum of the effects' additional forces, body frame [N, N·m].
    pub fn force(&self, ctx: &ForceContext<'_>) -> Vec6 {
        let mut f = Vec6::zeros();
        for e in &self.list {
            f += e.effect.force(&e.params, ctx);
        }
        f
    }

    /// Sum of the depth-reading offsets at time `t` \[s\] \[m\].
    pub fn depth_offset(&self, t: f64) -> f64 {
        self.list
            .iter()
            .map(|e| e.effect.depth_offset(&e.params, t))
            .sum()
    }
}
