//! `thrust_gain`: all thrust scaled by a factor k.
//!
//! The thrust curve was measured at one battery voltage and one set-up; a fuller battery, a
//! different propeller or a calibration error scale every thruster's force alike. Shows as
//! measured accelerations and speeds that are uniformly larger (k > 1) or smaller (k < 1)
//! than the replay's — unlike a damping error, also in the first instant after a step, when
//! the hull is still slow.
//!
//! Modelled as `f = k · f_static`.
//!
//! A `curve` form adds an exponent to the gain: `f = k·(|n|/50 %)^e · f_static`, a gain
//! that changes with the command — a thrust curve whose exponent is not the baseline's (an
//! ESC whose output is not linear in its input, a propeller that loads differently). A `knee`
//! form has the gain k up to a knee command n_k and changing linearly by s from there to full
//! command — a throttle map with a breakpoint (n_k = 0: a gain linear in the command).
//! A `per_thruster` form gives every thruster its own gain k_i (motors, propellers or ESCs
//! that differ one by one), applied to its thrust curve when the model is built.

use super::effect::{Effect, ParamInfo, ThrustContext};
use super::family::{Family, FamilyFacts, Regressor};
use super::per_thruster;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The gain k of both forms.
fn k_param(doc: &'static str) -> ParamInfo {
    ParamInfo {
        name: "k",
        unit: "-",
        lo: 0.1,
        hi: 3.0,
        null: 1.0,
        typical: 1.2,
        doc,
        shape: false,
    }
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustGain;

impl Effect for ThrustGain {
    fn name(&self) -> &'static str {
        "thrust_gain"
    }
    fn summary(&self) -> &'static str {
        "all thrust scaled by k"
    }
    fn explanation(&self) -> &'static str {
        "Battery above or below the voltage at which the thrust curve was measured, or a \
         calibration error: every thruster's force is scaled by the same factor."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![k_param("thrust scale factor")]
    }
    fn thrust(&self, p: &[f64], _ctx: &ThrustContext<'_>, f: f64) -> f64 {
        p[0] * f
    }
}

/// Command at which the `curve` form's gain is k [%].
const CURVE_N_REF: f64 = 50.0;

/// (|n|/50 %)^e for the command `n` [%]: how a gain that changes with the command scales the
/// thrust (the `curve` forms of `thrust_gain` and `thrust_asymmetry`).
pub(super) fn command_factor(n: f64, e: f64) -> f64 {
    // Below 1 % the thrust is negligible; the floor keeps a negative exponent finite.
    (n.abs().max(1.0) / CURVE_N_REF).powf(e)
}

/// The `curve` form: `f = k·(|n|/50 %)^e · f_static` — the gain k at half command, changing
/// with the command by the exponent e (0 is the standard form; both are tested against null).
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustGainCurve;

impl Effect for ThrustGainCurve {
    fn name(&self) -> &'static str {
        "thrust_gain"
    }
    fn form(&self) -> &'static str {
        "curve"
    }
    fn summary(&self) -> &'static str {
        "thrust scaled by k·(|n|/50 %)^e, a gain that changes with the command"
    }
    fn explanation(&self) -> &'static str {
        "The thrust curve's exponent differs from the baseline's (an ESC whose output is not \
         linear in its input, a different propeller): the thrust is off by a factor that \
         grows or shrinks with the command."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            k_param("thrust scale factor at half command"),
            ParamInfo {
                name: "e",
                unit: "-",
                lo: -0.5,
                hi: 0.5,
                null: 0.0,
                typical: 0.1,
                doc: "exponent of the gain's change with the command",
                // Not a shape: with e ≠ 0 the thrust differs from the baseline even at k = 1.
                shape: false,
            },
        ]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        p[0] * command_factor(ctx.command, p[1]) * f
    }
}

/// The `knee` form: `f = (k + s·max(0, |n| − n_k)/(n_max − n_k)) · f_static` — the gain k up
/// to the knee command n_k (the family's shape parameter), changing linearly by s from there
/// to full command n_max (n_k = 0: a gain linear in the command).
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustGainKnee;

impl ThrustGainKnee {
    /// The gain at command `n` [%] of a thruster whose largest command is `n_max` [%], for
    /// the parameters `p` = (k, s, n_k).
    fn gain(p: &[f64], n: f64, n_max: f64) -> f64 {
        let span = n_max - p[2];
        if span <= 0.0 {
            return p[0];
        }
        p[0] + p[1] * ((n.abs() - p[2]).max(0.0) / span).min(1.0)
    }
}

impl Effect for ThrustGainKnee {
    fn name(&self) -> &'static str {
        "thrust_gain"
    }
    fn form(&self) -> &'static str {
        "knee"
    }
    fn summary(&self) -> &'static str {
        "thrust scaled by k up to a knee command n_k, by a gain changing linearly by s above it"
    }
    fn explanation(&self) -> &'static str {
        "The throttle map has a breakpoint (an ESC or motor whose output changes slope at some \
         command): the thrust is off by a factor k up to the knee command n_k and by a factor \
         that changes linearly with the command above it, by s at full command."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            k_param("thrust scale factor up to the knee"),
            ParamInfo {
                name: "s",
                unit: "-",
                lo: -0.8,
                hi: 0.8,
                null: 0.0,
                typical: 0.15,
                doc: "change of the gain from the knee to full command",
                // Not a shape: with s ≠ 0 the thrust differs from the baseline even at k = 1.
                shape: false,
            },
            ParamInfo {
                name: "n_k_pct",
                unit: "%",
                lo: 0.0,
                hi: 80.0,
                null: 50.0,
                typical: 50.0,
                doc: "knee command: the gain is k below it",
                shape: true,
            },
        ]
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        Self::gain(p, ctx.command, ctx.thruster.max_command) * f
    }
}

/// The `per_thruster` form: every thruster has its own gain, `f_i = k_i · f_static,i` — motors
/// from different batches, a nicked or fouled propeller, ESCs calibrated one by one. On a
/// vehicle whose thrusters turn it (differential thrust for yaw, roll or pitch) unequal gains
/// show as a turn the commands do not ask for and as a response that differs by direction.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrustGainPerThruster;

impl Effect for ThrustGainPerThruster {
    fn name(&self) -> &'static str {
        "thrust_gain"
    }
    fn form(&self) -> &'static str {
        "per_thruster"
    }
    fn summary(&self) -> &'static str {
        "each thruster's thrust scaled by its own k_i"
    }
    fn explanation(&self) -> &'static str {
        "Motors, propellers or ESCs that differ one by one (different batches, a nicked \
         propeller, a separate calibration): each thruster's force is scaled by its own \
         factor, so differential thrust turns the hull more or less than the model expects."
    }
    fn params(&self, vehicle: &VehicleParams) -> Vec<ParamInfo> {
        per_thruster::params(
            vehicle,
            &per_thruster::GAIN_NAMES,
            k_param("thrust scale factor of thruster i (vehicle file order)"),
        )
    }
    fn not_applicable(&self, vehicle: &VehicleParams) -> Option<String> {
        per_thruster::not_applicable(vehicle)
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        for (th, k) in vehicle.thrusters.iter_mut().zip(p) {
            th.curve.scale(*k);
        }
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(ThrustGain),
            Arc::new(ThrustGainCurve),
            Arc::new(ThrustGainKnee),
            Arc::new(ThrustGainPerThruster),
        ],
        facts: FamilyFacts {
            excitation: "steps to several command levels in both directions",
            direct: None,
            regressor: Regressor::Command,
            thrust_map: true,
            separations: &[],
        },
    }
}
