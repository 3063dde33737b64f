//! `inflow_thrust_loss` truth forms — a propeller advancing into its own thrust direction pushes
//! less, but not as f − κ√|f|·u_a (advance ratio) or f − k·|f|·u_a as the fitting side assumes:
//!
//! * `inflow_thrust_loss/saturating` — f − k·u₀·tanh(u_a/u₀)·|f|, u₀ = 0.05 m/s: the loss
//!   sets in with the first few cm/s of inflow and then hardly grows (a propeller whose tip
//!   vortex sheds as soon as it advances).
//! * `inflow_thrust_loss/quadratic` — f − c·u_a·|u_a|·|f|: the loss grows with the square of
//!   the inflow (a ducted propeller whose duct loses its suction at speed).
//! * `inflow_thrust_loss/forward_only` — f − k·max(u_a, 0)·|f|: the loss of advancing, but no
//!   gain while the propeller brakes the vehicle (a thrust coefficient flat for negative
//!   advance ratios).
//!
//! The `power` fitting form (exponent fitted) has since matched `quadratic`.
//!
//! u_a is the axial inflow: the thruster's speed through the water along its thrust direction.
//! The thrust never changes sign through the loss.

use super::effect_meta::truth_effect_meta;
use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ThrustContext, inflow_reduced as reduced};
use std::sync::Arc;

const PROPORTIONAL: &str = "inflow_thrust_loss/saturating";
const PROPORTIONAL_LAW: &str = "thrust f − k·u₀·tanh(u_a/u₀)·|f|, u₀ = 0.05 m/s";
const QUADRATIC: &str = "inflow_thrust_loss/quadratic";
const QUADRATIC_LAW: &str = "thrust f − c·u_a·|u_a|·|f|";
const FORWARD: &str = "inflow_thrust_loss/forward_only";
const FORWARD_LAW: &str = "thrust f − k·max(u_a, 0)·|f|";

/// Inflow speed at which the saturating loss levels off \[m/s\].
const SATURATION_SPEED: f64 = 0.05;

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: PROPORTIONAL,
            family: "inflow_thrust_loss",
            law: PROPORTIONAL_LAW,
            params: vec![FormParam::magnitude(
                "k_s_m",
                "s/m",
                4.0,
                9.0,
                "relative thrust lost per m/s of inflow at small inflow (20–45 % once moving)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(Loss { k: p[0], power: 1 })),
        },
        TruthForm {
            name: QUADRATIC,
            family: "inflow_thrust_loss",
            law: QUADRATIC_LAW,
            params: vec![FormParam::magnitude(
                "c_s2_m2",
                "s²/m²",
                10.0,
                20.0,
                "relative thrust lost per (m/s)² of inflow",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(Loss { k: p[0], power: 2 })),
        },
        TruthForm {
            name: FORWARD,
            family: "inflow_thrust_loss",
            law: FORWARD_LAW,
            params: vec![FormParam::magnitude(
                "k_s_m",
                "s/m",
                3.0,
                6.0,
                "relative thrust lost per m/s of inflow while advancing",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Effect(Arc::new(ForwardOnly { k: p[0] })),
        },
    ]
}

/// See the module documentation: power 1 the saturating loss, power 2 the quadratic one.
#[derive(Debug)]
struct Loss {
    /// Loss coefficient [s/m for power 1, s²/m² for power 2].
    k: f64,
    /// 1: saturating; 2: quadratic.
    power: i32,
}

impl Effect for Loss {
    fn name(&self) -> &'static str {
        if self.power == 1 {
            PROPORTIONAL
        } else {
            QUADRATIC
        }
    }
    fn summary(&self) -> &'static str {
        if self.power == 1 {
            PROPORTIONAL_LAW
        } else {
            QUADRATIC_LAW
        }
    }
    fn explanation(&self) -> &'static str {
        self.summary()
    }
    fn params(
        &self,
        _vehicle: &shoal_model::vehicle::VehicleParams,
    ) -> Vec<shoal_model::effects::ParamInfo> {
        Vec::new()
    }
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let u = ctx.inflow;
        let shape = if self.power == 1 {
            SATURATION_SPEED * (u / SATURATION_SPEED).tanh()
        } else {
            u * u.abs()
        };
        reduced(f, self.k * shape * f.abs())
    }
}

/// See the module documentation.
#[derive(Debug)]
struct ForwardOnly {
    /// Loss coefficient \[s/m\].
    k: f64,
}

impl Effect for ForwardOnly {
    truth_effect_meta!(FORWARD, FORWARD_LAW);
    fn thrust(&self, _p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        reduced(f, self.k * ctx.inflow.max(0.0) * f.abs())
    }
}
