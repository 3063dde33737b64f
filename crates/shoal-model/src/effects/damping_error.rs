//! `damping_error`: linear and quadratic damping differ from the baseline.
//!
//! Damping coefficients identified in one flow regime fail in another: turbulent heave flow,
//! appendages, a tether or a camera change the drag. Terminal speeds then differ from the
//! replay, and so do the coasting phases after the thrust stops.
//!
//! Modelled by scaling every linear damping coefficient by `scale_lin` and every quadratic
//! one by `scale_quad`.

use super::{Effect, ParamInfo};
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
