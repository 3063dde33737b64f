//! `tether_drag`: a cable from the surface pulls on the hull.
//!
//! A tethered vehicle (a ROV's data and power cable, a safety line) drags its cable through
//! the water. The cable runs from an anchor on the surface at (x_a, y_a) — by default the
//! world origin, which is where the replay of a log without tracked positions starts, so the
//! anchor is above the start; with tracked positions a fit finds it — to an attachment point
//! on the hull at body `x = x_att` (on the centre line; aft for a ROV whose tether leaves at
//! the stern). The anchor and the attachment point are shape parameters of both forms.
//!
//! **`drag` (standard form).** The cable is taken as straight from the anchor to the hull, of
//! length L (the distance between them: a tether paid out as needed). When the attachment point
//! moves through the water at v, the cable pivots about the anchor: a point a fraction s of the
//! way along it moves at s·v, and its normal drag per metre is ½ ρ C_d d (s v_n)|s v_n|, v_n
//! the part of v across the cable (drag along a cable is small and neglected). Of the whole
//! cable's drag, ½ ρ C_d d L v_n|v_n| / 3, the hull carries the share that balances the moment
//! about the anchor, 3/4:
//!
//! ```text
//! F = −⅛ ρ (C_d d) L |v_n| v_n     at the attachment point (world frame)
//! ```
//!
//! Unlike a damping error it grows with the distance from the anchor, acts only across the
//! cable (a vehicle straight below its anchor diving along the cable feels none of it), and
//! pulls at the attachment point, so sway and yaw of a hull with an aft tether couple.
//!
//! **`taut`.** A cable that runs out as the vehicle travels: within a horizontal distance ℓ of
//! the anchor it is slack and does nothing, beyond it it pulls back towards the anchor like a
//! spring of stiffness k, F = −k (r_h − ℓ) ê_h, r_h and ê_h the horizontal distance and
//! direction from the anchor to the attachment point — a tether on a fixed length, a safety
//! line. The pull is taken horizontal: a cable straight above a hull pulling it up would be a
//! vertical force that grows with depth, which `buoyancy_offset` (`depth`) already describes
//! and no log can tell from it (fitted on a yaw run that held its place, such a cable took a
//! depth-sensor drift for itself).

use super::effect::{Effect, ForceContext, ParamInfo};
use super::family::{DirectChannels, Family, FamilyFacts, Regressor};
use crate::math::{Vec3, Vec6, join6};
use crate::vehicle_params::VehicleParams;
use std::sync::Arc;

/// The attachment point's body-frame `x`, a shape parameter of both forms.
fn x_att_param() -> ParamInfo {
    ParamInfo {
        name: "x_att_m",
        unit: "m",
        lo: -1.0,
        hi: 1.0,
        null: 0.0,
        typical: 0.0,
        doc: "body x of the attachment point on the hull's centre line (negative: aft)",
        shape: true,
    }
}

/// The anchor's place on the surface, world `x` or `y`, a shape parameter of both forms.
fn anchor_param(name: &'static str, doc: &'static str) -> ParamInfo {
    ParamInfo {
        name,
        unit: "m",
        lo: -100.0,
        hi: 100.0,
        null: 0.0,
        typical: 0.0,
        doc,
        shape: true,
    }
}

/// The shape parameters both forms end with: attachment point, anchor x and y.
fn geometry_params() -> [ParamInfo; 3] {
    [
        x_att_param(),
        anchor_param("anchor_x_m", "world x of the anchor on the surface"),
        anchor_param("anchor_y_m", "world y of the anchor on the surface"),
    ]
}

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct TetherDrag;

impl TetherDrag {
    /// Where the cable meets the hull, for the geometry `g` = (x_att \[m\], anchor x \[m\],
    /// anchor y \[m\]): the attachment point `a` (body frame), its position relative to the
    /// anchor and its velocity through the water (world frame) [m, m/s].
    pub fn attachment(g: &[f64], ctx: &ForceContext<'_>) -> (Vec3, Vec3, Vec3) {
        let r = ctx.rigid;
        let a = Vec3::new(g[0], 0.0, 0.0);
        let v = Vec3::new(r.nu[0], r.nu[1], r.nu[2]);
        let w = Vec3::new(r.nu[3], r.nu[4], r.nu[5]);
        let anchor = Vec3::new(g[1], g[2], 0.0);
        let pos = r.position + r.attitude.transform_vector(&a) - anchor;
        let vel = r.attitude.transform_vector(&(v + w.cross(&a)));
        (a, pos, vel)
    }

    /// The world-frame force `f` \[N\] at the body point `a` \[m\] as a body-frame wrench
    /// [N, N·m].
    pub fn wrench_at(a: &Vec3, f: &Vec3, ctx: &ForceContext<'_>) -> Vec6 {
        let fb = ctx.rigid.attitude.inverse_transform_vector(f);
        join6(&fb, &a.cross(&fb))
    }

    /// The force on the hull, world frame \[N\], of a cable with drag area per length `cd_d`
    /// \[m\] from the anchor to the attachment point at `pos` from it, moving at `vel`
    /// through water of density `rho` [kg/m³].
    pub fn cable_force(cd_d: f64, pos: &Vec3, vel: &Vec3, rho: f64) -> Vec3 {
        let len = pos.norm();
        if len < 1e-9 {
            return Vec3::zeros();
        }
        let e = pos / len;
        let vn = vel - e * vel.dot(&e);
        -0.125 * rho * cd_d * len * vn.norm() * vn
    }
}

impl Effect for TetherDrag {
    fn name(&self) -> &'static str {
        "tether_drag"
    }
    fn form(&self) -> &'static str {
        "drag"
    }
    fn summary(&self) -> &'static str {
        "a cable from the surface drags on the hull, in proportion to its length"
    }
    fn explanation(&self) -> &'static str {
        "A tether (data or power cable, safety line) from an anchor on the surface: moving \
         across the cable drags it through the water, and the hull carries 3/4 of the \
         cable's drag, −⅛ ρ C_d d L |v_n| v_n at the attachment point — a drag that grows \
         with the distance L from the anchor."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = vec![ParamInfo {
            name: "cd_d_m",
            unit: "m",
            lo: 0.0,
            hi: 0.2,
            null: 0.0,
            typical: 0.01,
            doc: "drag coefficient times cable diameter, C_d·d (1.2 × 8 mm ≈ 0.01 m)",
            shape: false,
        }];
        p.extend(geometry_params());
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        if p[0] == 0.0 {
            return Vec6::zeros();
        }
        let (a, pos, vel) = Self::attachment(&p[1..], ctx);
        let f = Self::cable_force(p[0], &pos, &vel, ctx.density);
        Self::wrench_at(&a, &f, ctx)
    }
}

/// The `taut` form: a cable of length ℓ that pulls back like a spring once it runs out.
#[derive(Clone, Copy, Debug, Default)]
pub struct TetherTaut;

impl Effect for TetherTaut {
    fn name(&self) -> &'static str {
        "tether_drag"
    }
    fn form(&self) -> &'static str {
        "taut"
    }
    fn summary(&self) -> &'static str {
        "a cable from the surface pulls the hull back horizontally once it runs out at ℓ"
    }
    fn explanation(&self) -> &'static str {
        "A tether or safety line of fixed length from an anchor on the surface: slack within \
         a horizontal distance ℓ of the anchor, beyond it the cable stretches and pulls the \
         attachment point back towards the anchor, horizontally, with k·(r_h − ℓ)."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        let mut p = vec![
            ParamInfo {
                name: "k_n_per_m",
                unit: "N/m",
                lo: 0.0,
                hi: 100.0,
                null: 0.0,
                typical: 5.0,
                doc: "stiffness of the taut cable",
                shape: false,
            },
            ParamInfo {
                name: "length_m",
                unit: "m",
                lo: 0.1,
                hi: 100.0,
                null: 5.0,
                typical: 5.0,
                doc: "horizontal distance from the anchor at which the cable runs out",
                shape: true,
            },
        ];
        p.extend(geometry_params());
        p
    }
    fn force(&self, p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        if p[0] == 0.0 {
            return Vec6::zeros();
        }
        let (a, pos, _) = TetherDrag::attachment(&p[2..], ctx);
        let horizontal = Vec3::new(pos.x, pos.y, 0.0);
        let r = horizontal.norm();
        if r <= p[1] {
            return Vec6::zeros();
        }
        let f = -p[0] * (r - p[1]) * horizontal / r;
        TetherDrag::wrench_at(&a, &f, ctx)
    }
}

/// The family: its forms, default first, and its facts.
pub(super) fn family() -> Family {
    Family {
        forms: vec![Arc::new(TetherDrag), Arc::new(TetherTaut)],
        facts: FamilyFacts {
            excitation: "travelling away from the anchor and back with the position tracked",
            // A tether's pull grows with the distance from its anchor: without the position (or the
            // horizontal velocity) a log cannot place the hull relative to the anchor, and the
            // cable's drag is just more drag, or less thrust, at speed — the damping-error and
            // inflow families' marks (on the BlueROV yaw runs it fitted C_d·d at its bound as a
            // stand-in for the damping error; in a mission the inflow loss won instead of it).
            direct: Some(DirectChannels {
                channels: &["x", "y", "u", "v"],
                why_not_fitted: "not fitted: these runs log neither the horizontal position nor the horizontal \
             velocity, which a tether's pull depends on (its distance from the anchor)",
            }),
            regressor: Regressor::Time,
            thrust_map: false,
            separations: &[],
        },
    }
}
