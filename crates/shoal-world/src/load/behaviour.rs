//! Built-in behaviours (beacon, gossip, flock), checked against the vehicle that runs them.

use super::validator::{End, Validator};
use crate::error::{FieldPath, ProblemKind};
use crate::spec::*;
use shoal_model::prelude::*;

/// Validates a behaviour against the vehicle it runs on.
pub(super) fn validate_behaviour(
    b: &BehaviourSpec,
    model: &VehicleModel,
    p: &FieldPath,
    duration: f64,
    v: &mut Validator<'_>,
) {
    if model.params.modems.is_empty() {
        v.push(ProblemKind::Invalid, p, "a behaviour talks through optical modems, but this vehicle has none (add [[vehicles.model.modems]])".into());
        return;
    }
    let max_payload = model
        .params
        .modems
        .iter()
        .map(|m| m.max_payload)
        .min()
        .unwrap_or(0);
    match b {
        BehaviourSpec::Beacon {
            period,
            payload_bytes,
            jitter,
        } => {
            v.pos(p, "period", *period, 1e6, "s");
            v.within(
                p,
                "payload_bytes",
                *payload_bytes as f64,
                1.0,
                max_payload as f64,
                "bytes (the modems' max_payload)",
            );
            v.nonneg(p, "jitter", *jitter, 1e6, "s");
        }
        BehaviourSpec::Gossip {
            start,
            repeats,
            interval,
            jitter,
            ..
        } => {
            v.nonneg(p, "start", *start, duration, "s (0 … duration)");
            v.within(p, "repeats", f64::from(*repeats), 1.0, 1e4, "");
            v.pos(p, "interval", *interval, 1e6, "s");
            v.nonneg(p, "jitter", *jitter, 1e6, "s");
            if max_payload < 8 {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "gossip frames need 8 bytes of payload".into(),
                );
            }
        }
        BehaviourSpec::Flock {
            surge,
            period,
            too_close,
            too_far,
            cohesion,
        } => {
            v.within(p, "surge", *surge, -1.0, 1.0, "N");
            v.pos(p, "period", *period, 1e6, "s");
            v.pos(p, "too_close", *too_close, 1.0, "W");
            v.num(
                &p.key("too_far"),
                *too_far,
                End::Open(0.0),
                End::Open(*too_close),
                "W (below too_close)",
            );
            v.nonneg(p, "cohesion", *cohesion, 100.0, "");
            if model.uauv2.is_none() {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "flocking steers in auto mode and needs the μAUV² layout".into(),
                );
            }
        }
    }
}
