//! `tether_drag` truth forms — a cable from the surface drags on the hull, but not as the
//! fitting side's straight, taut-enough cable with drag only across it:
//!
//! * `tether_drag/slack_cable` — more cable is paid out than the distance needs: a length ℓ_s
//!   of slack lies in the water besides the straight run, and drags with it, so the drag grows
//!   with L + ℓ_s instead of L (a drag that does not vanish near the anchor).
//! * `tether_drag/along_and_across` — the cable drags along its length too (skin friction,
//!   a fraction c_t of its normal drag coefficient): moving towards or away from the anchor
//!   pulls on the hull as well, which the fitting side's normal drag never does.
//!
//! Both anchor the cable on the surface above the closed-loop missions' start, [`ANCHOR`],
//! and attach it at body x = x_att. No designed experiment shows them (see
//! [`TruthForm::excites`]): they are hidden in the closed-loop missions only.

use super::effect_meta::truth_effect_meta;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use shoal_model::effects::{Effect, ForceContext, TetherDrag};
use shoal_model::math::{Vec3, Vec6};
use std::sync::Arc;

/// The anchor: on the surface above the start of the closed-loop missions
/// ([`crate::mission`]), world frame \[m\].
pub const ANCHOR: Vec3 = Vec3::new(0.0, 0.0, 0.0);

const SLACK: &str = "tether_drag/slack_cable";
const SLACK_LAW: &str = "F = −⅛ ρ C_d d (L + ℓ_s) |v_n| v_n at the attachment point";
const ALONG: &str = "tether_drag/along_and_across";
const ALONG_LAW: &str =
    "F = −⅛ ρ C_d d L (|v_n| v_n + c_t |v_t| v_t): drag across and along the cable";

pub(super) fn forms() -> Vec<TruthForm> {
    let cd_d = |lo, hi| {
        FormParam::magnitude(
            "cd_d_m",
            "m",
            lo,
            hi,
            "normal drag coefficient times cable diameter",
        )
    };
    let x_att = FormParam::shape(
        "x_att_m",
        "m",
        -0.13,
        0.0,
        "body x of the attachment point (aft half of the hull)",
    );
    vec![
        TruthForm {
            name: SLACK,
            family: "tether_drag",
            law: SLACK_LAW,
            params: vec![
                cd_d(0.015, 0.03),
                FormParam::shape(
                    "slack_m",
                    "m",
                    1.0,
                    3.0,
                    "cable paid out beyond the distance",
                ),
                x_att.clone(),
            ],
            excites: &[],
            build: |p| {
                Part::Effect(Arc::new(Cable {
                    name: SLACK,
                    law: SLACK_LAW,
                    cd_d: p[0],
                    slack: p[1],
                    c_t: 0.0,
                    x_att: p[2],
                }))
            },
        },
        TruthForm {
            name: ALONG,
            family: "tether_drag",
            law: ALONG_LAW,
            params: vec![
                cd_d(0.015, 0.03),
                FormParam::shape(
                    "c_t",
                    "-",
                    0.2,
                    0.5,
                    "tangential over normal drag coefficient",
                ),
                x_att,
            ],
            excites: &[],
            build: |p| {
                Part::Effect(Arc::new(Cable {
                    name: ALONG,
                    law: ALONG_LAW,
                    cd_d: p[0],
                    slack: 0.0,
                    c_t: p[1],
                    x_att: p[2],
                }))
            },
        },
    ]
}

/// See the module documentation (lengths \[m\], c_t \[-\]).
#[derive(Debug)]
struct Cable {
    name: &'static str,
    law: &'static str,
    cd_d: f64,
    slack: f64,
    c_t: f64,
    x_att: f64,
}

impl Effect for Cable {
    truth_effect_meta!(fields);
    fn force(&self, _p: &[f64], ctx: &ForceContext<'_>) -> Vec6 {
        let geometry = [self.x_att, ANCHOR.x, ANCHOR.y];
        let (a, pos, vel) = TetherDrag::attachment(&geometry, ctx);
        let len = pos.norm();
        if len < 1e-9 {
            return Vec6::zeros();
        }
        // Across the cable: the fitting side's law for the wet length L + ℓ_s.
        let across = TetherDrag::cable_force(self.cd_d, &pos, &vel, ctx.density)
            * ((len + self.slack) / len);
        // Along it: the same ⅛ share of the cable's drag with c_t·C_d.
        let e = pos / len;
        let vt = e * vel.dot(&e);
        let along = -0.125 * ctx.density * self.c_t * self.cd_d * len * vt.norm() * vt;
        TetherDrag::wrench_at(&a, &(across + along), ctx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;
    use shoal_model::rigid_body::{Environment, RigidState};

    fn force(form: &str, p: &[f64], position: Vec3, nu: Vec6) -> Vec6 {
        let f = forms()
            .into_iter()
            .find(|f| f.name == form)
            .expect("registered");
        let Part::Effect(e) = f.part(p) else {
            panic!("an effect")
        };
        let vehicle = presets::uauv2();
        let rigid = RigidState {
            position,
            attitude: shoal_model::math::Quat::identity(),
            nu,
        };
        e.force(
            &[],
            &ForceContext::idle(0.0, &rigid, &vehicle, &Environment::default()),
        )
    }

    #[test]
    fn slack_and_tangential_drag_follow_their_laws() {
        // 3 m north of the anchor and 4 m deep: L = 5 m along (0.6, 0, 0.8).
        let at = ANCHOR + Vec3::new(3.0, 0.0, 4.0);
        // Sway at 0.5 m/s across the cable with 2 m of slack: −⅛·1000·0.02·7·0.25 = −4.375 N.
        let sway = Vec6::new(0.0, 0.5, 0.0, 0.0, 0.0, 0.0);
        let f = force(SLACK, &[0.02, 2.0, 0.0], at, sway);
        assert!(
            (f - Vec6::new(0.0, -4.375, 0.0, 0.0, 0.0, 0.0)).norm() < 1e-12,
            "{f}"
        );
        // Straight away from the anchor at 0.5 m/s: no normal drag, the tangential part
        // −⅛·1000·0.3·0.02·5·0.5·0.5·(0.6, 0, 0.8) = −0.9375·(0.6, 0, 0.8).
        let away = Vec6::new(0.3, 0.0, 0.4, 0.0, 0.0, 0.0);
        let f = force(ALONG, &[0.02, 0.3, 0.0], at, away);
        let want = Vec6::new(-0.5625, 0.0, -0.75, 0.0, 0.0, 0.0);
        assert!((f - want).norm() < 1e-12, "{f}");
        // The fitting side's law feels nothing there.
        let z = force(SLACK, &[0.02, 0.0, 0.0], at, away);
        assert!(z.norm() < 1e-12, "{z}");
    }
}
