//! Parameters that come once per thruster: the `per_thruster` forms of `thrust_gain` and
//! `thruster_lag` (real motors differ one by one — different batches, a nicked propeller, a
//! worn bearing — where the family's standard form acts on every thruster alike).
//!
//! A per-thruster form has one parameter per thruster of the vehicle, in the order of the
//! vehicle file, named `<stem>_<index>` (`k_0`, `k_1`, …; the report's parameter table lists
//! them in that order). Up to [`MAX_THRUSTERS`] thrusters; a vehicle with more cannot use
//! these forms (the form says so and the search skips it).

use super::effect::ParamInfo;
use crate::vehicle_params::VehicleParams;

/// Most thrusters a per-thruster form can describe.
pub const MAX_THRUSTERS: usize = 12;

/// Parameter names of the per-thruster gains, thruster by thruster.
pub(crate) const GAIN_NAMES: [&str; MAX_THRUSTERS] = [
    "k_0", "k_1", "k_2", "k_3", "k_4", "k_5", "k_6", "k_7", "k_8", "k_9", "k_10", "k_11",
];

/// Parameter names of the per-thruster lags, thruster by thruster.
pub(crate) const LAG_NAMES: [&str; MAX_THRUSTERS] = [
    "tau_0_s", "tau_1_s", "tau_2_s", "tau_3_s", "tau_4_s", "tau_5_s", "tau_6_s", "tau_7_s",
    "tau_8_s", "tau_9_s", "tau_10_s", "tau_11_s",
];

/// `template` once for every thruster of `vehicle`, named by `names` (an empty list for a
/// vehicle with more than [`MAX_THRUSTERS`]; [`not_applicable`] says why).
pub(crate) fn params(
    vehicle: &VehicleParams,
    names: &[&'static str; MAX_THRUSTERS],
    template: ParamInfo,
) -> Vec<ParamInfo> {
    if vehicle.thrusters.len() > MAX_THRUSTERS {
        return Vec::new();
    }
    names[..vehicle.thrusters.len()]
        .iter()
        .map(|&name| ParamInfo {
            name,
            ..template.clone()
        })
        .collect()
}

/// Why a per-thruster form cannot describe `vehicle`, if it cannot.
pub(crate) fn not_applicable(vehicle: &VehicleParams) -> Option<String> {
    match vehicle.thrusters.len() {
        0 => Some("the vehicle has no thrusters".into()),
        n if n > MAX_THRUSTERS => Some(format!(
            "{n} thrusters: a per-thruster form describes at most {MAX_THRUSTERS}"
        )),
        _ => None,
    }
}
