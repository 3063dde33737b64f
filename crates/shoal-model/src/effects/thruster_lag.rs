//! `thruster_lag`: thrust follows the command through a first-order lag.
//!
//! A propeller cannot change its speed instantly: the motor and propeller inertia and the
//! water the propeller drags along make the thrust settle with a time constant τ after a step
//! of the command (Yoerger's one-state thruster model, linearised:
//! τ ḟ = f_static(n) − f). The μAUV² paper neglects thruster dynamics (Sec. 4.2); a lag shows
//! as measured motion trailing the replay after every command step.
//!
//! Modelled by adding τ to every thruster's lag time constant ([`ThrusterParams::lag`]), which
//! the actuator model integrates exactly over each step.
//!
//! [`ThrusterParams::lag`]: crate::thruster::ThrusterParams::lag

//!
//! Four more forms of the family compete with the first-order lag: `second_order` (two equal
//! stages in series, an S-shaped spin-up), `up_down` (different time constants spinning up
//! and down), `slew` (the motor command ramps at a limited rate: a step becomes a ramp
//! whose length grows with the step — an ESC with a soft start or a current limit) and
//! `per_thruster` (each thruster its own first-order lag τ_i: motors that differ one by one).
use super::effect::{Effect, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use super::per_thruster;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// A time constant τ of the first-order, up/down and per-thruster forms, 0 … 2 s.
fn tau_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "tau_s",
        unit: "s",
        lo: 0.0,
        hi: 2.0,
        null: 0.0,
        typical: 0.3,
        doc,
        shape: false,
    }
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLag;

impl Effect for ThrusterLag {
    fn form(&self) -> &'static str {
        "first_order"
    }
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn summary(&self) -> &'static str {
        "thrust follows the command through a first-order lag τ"
    }
    fn explanation(&self) -> &'static str {
        "Motor and propeller inertia: after a command step the thrust settles with a time \
         constant τ instead of jumping (one-state thruster model, linearised)."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![tau_param("time constant added to each thruster's lag")]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for th in &mut vehicle.thrusters {
            th.lag += p[0];
        }
    }
}

/// The `second_order` form: two equal first-order stages in series (critically damped), as a
/// motor whose current and speed both lag: the thrust starts slowly and then catches up.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLagSecondOrder;

impl Effect for ThrusterLagSecondOrder {
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn form(&self) -> &'static str {
        "second_order"
    }
    fn summary(&self) -> &'static str {
        "thrust follows the command through two equal first-order lags τ (second order)"
    }
    fn explanation(&self) -> &'static str {
        "Motor and propeller inertia with a lagging motor current: after a command step the \
         thrust rises S-shaped, through two lags of time constant τ in series."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "tau_s",
            unit: "s",
            lo: 0.0,
            hi: 1.0,
            null: 0.0,
            typical: 0.15,
            doc: "time constant of each of the two stages",
            shape: false,
        }]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        if p[0] <= 0.0 {
            return; // null: the vehicle's own lag, unchanged
        }
        for th in &mut vehicle.thrusters {
            th.lag += p[0];
            th.lag_stages = 2;
        }
    }
}

/// The `up_down` form: a first-order lag whose time constant differs between spin-up (the
/// thrust magnitude grows) and spin-down (it falls) — a motor driven up but left to coast down.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLagUpDown;

impl Effect for ThrusterLagUpDown {
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn form(&self) -> &'static str {
        "up_down"
    }
    fn summary(&self) -> &'static str {
        "thrust follows the command through a first-order lag, τ_up spinning up, τ_down down"
    }
    fn explanation(&self) -> &'static str {
        "Motor and propeller inertia with a driven spin-up and a coasting spin-down: the \
         thrust settles with τ_up when its magnitude grows and with τ_down when it falls."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let p = |name, doc| ParamInfo {
            name,
            ..tau_param(doc)
        };
        vec![
            p("tau_up_s", "time constant while the thrust magnitude grows"),
            p(
                "tau_down_s",
                "time constant while the thrust magnitude falls",
            ),
        ]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for th in &mut vehicle.thrusters {
            let base = th.lag;
            th.lag = base + p[0];
            th.lag_down = base + p[1];
        }
    }
}

/// The `slew` form: the command reaching the motor changes by at most 100/T %/s (T: the time
/// to ramp through 100 % of command), so a command step becomes a ramp whose length grows
/// with the step — unlike a lag, whose settling time does not depend on the step's size.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLagSlew;

impl Effect for ThrusterLagSlew {
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn form(&self) -> &'static str {
        "slew"
    }
    fn summary(&self) -> &'static str {
        "the motor command ramps at most 100 % per T seconds (slew-rate limit)"
    }
    fn explanation(&self) -> &'static str {
        "An ESC with a soft start or a current limit: the motor's command follows a step as a \
         ramp of limited slope, so large steps take longer to reach than small ones."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "ramp_s",
            unit: "s",
            lo: 0.0,
            hi: 5.0,
            null: 0.0,
            typical: 0.5,
            doc: "time the motor command takes to ramp through 100 % (0: no limit)",
            shape: false,
        }]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for th in &mut vehicle.thrusters {
            th.ramp += p[0];
        }
    }
}

/// The `per_thruster` form: every thruster has its own first-order lag τ_i — motors that
/// differ one by one (a worn bearing, a heavier propeller, an ESC with another filter). On a
/// vehicle that turns by differential thrust, unequal lags show as a turn after every step of
/// a command that should only have moved it straight.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterLagPerThruster;

impl Effect for ThrusterLagPerThruster {
    fn name(&self) -> &'static str {
        "thruster_lag"
    }
    fn form(&self) -> &'static str {
        "per_thruster"
    }
    fn summary(&self) -> &'static str {
        "each thruster's thrust follows its command through its own first-order lag τ_i"
    }
    fn explanation(&self) -> &'static str {
        "Motor and propeller inertia that differ one by one (a worn bearing, a heavier \
         propeller, another ESC): after a command step each thruster's force settles with \
         its own time constant."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        per_thruster::params(
            vehicle,
            &per_thruster::LAG_NAMES,
            tau_param("time constant added to thruster i's lag (vehicle file order)"),
        )
    }
    fn not_applicable(&self, vehicle: &VehicleParams) -> Option<String> {
        per_thruster::not_applicable(vehicle)
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for (th, tau) in vehicle.thrusters.iter_mut().zip(p) {
            th.lag += tau;
        }
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(ThrusterLag),
            Arc::new(ThrusterLagSecondOrder),
            Arc::new(ThrusterLagUpDown),
            Arc::new(ThrusterLagSlew),
            Arc::new(ThrusterLagPerThruster),
        ],
        facts: FamilyFacts {
            excitation: "short command steps (0.5–2 s) up and down",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: false,
            separations: &[],
        },
    }
}
