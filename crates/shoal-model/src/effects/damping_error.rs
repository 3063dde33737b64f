//! `damping_error`: linear and quadratic damping differ from the baseline.
//!
//! Damping coefficients identified in one flow regime fail in another: turbulent heave flow,
//! appendages, a tether or a camera change the drag. Terminal speeds then differ from the
//! replay, and so do the coasting phases after the thrust stops.
//!
//! Modelled by scaling every linear damping coefficient by `scale_lin` and every quadratic
//! one by `scale_quad`.
//!
//! A `direction` form competes: the whole drag law is scaled by k₊ for motion in the positive
//! sense of a degree of freedom and by k₋ for the negative — a hull whose nose and tail, or top
//! and bottom, are shaped differently (a camera dome, a flat belly).

use super::{Effect, ForceContext, ParamInfo};
use crate::math::Vec6;
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct DampingError;

impl Effect for DampingError {
    fn name(&self) -> &'static str {
        "damping_error"
    }
    fn summary(&self) -> &'static str {
        "linear and quadratic damping differ from the baseline (scale factors)"
    }
    fn explanation(&self) -> &'static str {
        "Turbulent flow, appendages or a tether: the drag differs from the identified law; \
         linear and quadratic coefficients are scaled separately."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            ParamInfo {
                name: "scale_lin",
                unit: "-",
                lo: 0.0,
                hi: 10.0,
                null: 1.0,
                typical: 1.5,
                doc: "factor on the linear damping coefficients",
                shape: false,
            },
            ParamInfo {
                name: "scale_quad",
                unit: "-",
                lo: 0.1,
                hi: 10.0,
                null: 1.0,
                typical: 1.5,
                doc: "factor on the quadratic damping coefficients",
                shape: false,
            },
        ]
    }
    fn configure(&self, p: &[f64], vehicle: &mut VehicleParams) {
        vehicle.body.damping_linear *= p[0];
        vehicle.body.damping_quadratic *= p[1];
    }
}

/// The `direction` form: the baseline drag of each degree of freedom scaled by k₊ while its
/// velocity is positive and by k₋ while it is negative (applied as the extra force
/// −(k − 1)·(D_lin·ν + D_quad·|ν|·ν), per degree of freedom).
#[derive(Clone, Copy, Debug, Default)]
pub struct DampingErrorDirection;

impl Effect for DampingErrorDirection {
    fn name(&self) -> &'static str {
        "damping_error"
    }
    fn form(&self) -> &'static str {
        "direction"
    }
    fn summary(&self) -> &'static str {
        "drag scaled by k₊ for positive and k₋ for negative motion of each degree of freedom"
    }
    fn explanation(&self) -> &'static str {
        "A hull shaped differently fore and aft or top and bottom (a camera dome, a flat \
         belly): the drag differs with the direction of motion."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let k = |name, doc| ParamInfo {
            name,
            unit: "-",
            lo: 0.1,
            hi: 10.0,
            null: 1.0,
            typical: 1.5,
            doc,
            shape: false,
        };
        vec![
            k("k_pos", "factor on the drag while the velocity is positive"),
            k("k_neg", "factor on the drag while the velocity is negative"),
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let drag = ctx.vehicle.body.damping(nu);
        Vec6::from_fn(|i, _| {
            let k = if nu[i] >= 0.0 { p[0] } else { p[1] };
            -(k - 1.0) * drag[i]
        })
    }
}
