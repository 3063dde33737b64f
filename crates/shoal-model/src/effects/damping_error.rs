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

use super::effect::{Effect, ForceContext, ParamInfo};
use super::family::{Family, FamilyFacts, Regressor};
use crate::math::Vec6;
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// Reference speeds per degree of freedom for laws that depend on speed: translations
/// [m/s], rotations \[rad/s\] — a small vehicle's typical cruise (the μAUV²'s heave speed at
/// 60 % command, its yaw rate at 35 %).
pub const NU_REF: [f64; 6] = [0.1, 0.1, 0.1, 1.0, 1.0, 1.0];

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

/// The `power` form: an extra drag term of a fitted power p of the speed, s times the
/// quadratic drag at the reference speed [`NU_REF`]: −s·d_quad·ν_ref²·|x|^(p−1)·x with
/// x = ν/ν_ref, per degree of freedom.
#[derive(Clone, Copy, Debug, Default)]
pub struct DampingErrorPower;

impl Effect for DampingErrorPower {
    fn name(&self) -> &'static str {
        "damping_error"
    }
    fn form(&self) -> &'static str {
        "power"
    }
    fn summary(&self) -> &'static str {
        "extra drag growing as a fitted power p of the speed"
    }
    fn explanation(&self) -> &'static str {
        "An appendage, a tether or separated flow: a drag that does not grow with the square \
         of the speed, added to the identified law."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![
            ParamInfo {
                name: "s",
                unit: "-",
                lo: -0.9,
                hi: 10.0,
                null: 0.0,
                typical: 0.5,
                doc: "extra drag at the reference speed, relative to the quadratic drag there",
                shape: false,
            },
            ParamInfo {
                name: "p",
                unit: "-",
                lo: 1.0,
                hi: 4.0,
                null: 2.0,
                typical: 3.0,
                doc: "power of the speed",
                shape: true,
            },
        ]
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let nu = &ctx.rigid.nu;
        let d = &ctx.vehicle.body.damping_quadratic;
        Vec6::from_fn(|i, _| {
            let x = nu[i] / NU_REF[i];
            -p[0] * d[i] * NU_REF[i] * NU_REF[i] * x.abs().powf(p[1] - 1.0) * x
        })
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![
            Arc::new(DampingError),
            Arc::new(DampingErrorDirection),
            Arc::new(DampingErrorPower),
        ],
        facts: FamilyFacts {
            excitation: "coasting down from several speeds",
            direct: None,
            regressor: Regressor::Rate,
            thrust_map: false,
            separations: &[],
        },
    }
}
