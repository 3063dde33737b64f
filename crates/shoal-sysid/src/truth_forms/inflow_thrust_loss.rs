//! `inflow_thrust_loss` truth forms — a propeller advancing into its own thrust direction pushes
//! less, but not as f − κ√|f|·u_a (advance ratio) or f·(1 − k·u_a) as the fitting side assumes:
//!
//! * `inflow_thrust_loss/proportional` — f − k·u_a·|f|: the loss is proportional to the inflow
//!   and the thrust's magnitude, so it lowers reverse thrust when backing up, too (where
//!   f·(1 − k·u_a) would raise it).
//! * `inflow_thrust_loss/quadratic` — f − c·u_a·|u_a|·|f|: the loss grows with the square of
//!   the inflow (a ducted propeller whose duct loses its suction at speed).
//!
//! u_a is the axial inflow: the thruster's speed through the water along its thrust direction.
//! The thrust never changes sign through the loss.

use super::{ExpKind, FormParam, Part, TruthForm};
use shoal_model::effects::{Effect, ThrustContext};
use std::sync::Arc;

const PROPORTIONAL: &str = "inflow_thrust_loss/proportional";
const PROPORTIONAL_LAW: &str = "thrust f − k·u_a·|f|";
const QUADRATIC: &str = "inflow_thrust_loss/quadratic";
const QUADRATIC_LAW: &str = "thrust f − c·u_a·|u_a|·|f|";

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: PROPORTIONAL,
            family: "inflow_thrust_loss",
            law: PROPORTIONAL_LAW,
            params: vec![FormParam::magnitude(
                "k_s_m",
                "s/m",
                2.0,
                4.0,
                "relative thrust lost per m/s of inflow (20–45 % at 0.11 m/s, 60 % heave)",
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
    ]
}

/// See the module documentation: f − k·u_a·|u_a|^(power−1)·|f|.
#[derive(Debug)]
struct Loss {
    /// Loss coefficient [s/m for power 1, s²/m² for power 2].
    k: f64,
    /// Power of the inflow (1 or 2).
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
        let g = f - self.k * u * u.abs().powi(self.power - 1) * f.abs();
        if g * f < 0.0 { 0.0 } else { g }
    }
}
