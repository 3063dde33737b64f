//! Built-in behaviours (beacon, Poisson traffic, gossip, reliable gossip, leader and
//! follower, flock), checked against the vehicle that runs them.

use super::validator::Validator;
use crate::error::{FieldPath, ProblemKind};
use crate::spec::*;
use shoal_model::prelude::*;

/// Checks that the destinations the behaviours of `vehicles` name are vehicles of the world
/// (by group: the behaviour is the group's).
pub(super) fn check_destinations(
    wf: &WorldFile,
    vehicles: &[crate::desc::VehicleDesc],
    v: &mut Validator<'_>,
) {
    let names: std::collections::HashSet<&str> = vehicles.iter().map(|d| d.name.as_str()).collect();
    for (gi, g) in wf.vehicles.iter().enumerate() {
        let bp = FieldPath::root().key("vehicles").index(gi).key("behaviour");
        let named: Vec<(FieldPath, &String)> = match &g.behaviour {
            Some(BehaviourSpec::Poisson { to: Some(to), .. }) => vec![(bp.key("to"), to)],
            Some(BehaviourSpec::Leader { followers, .. }) => followers
                .iter()
                .enumerate()
                .map(|(i, f)| (bp.key("followers").index(i), f))
                .collect(),
            _ => Vec::new(),
        };
        for (field, name) in named {
            if names.contains(name.as_str()) {
                continue;
            }
            let all: Vec<&str> = vehicles
                .iter()
                .map(|d| d.name.as_str())
                .take(1000)
                .collect();
            let hint = super::messages::suggest(name, &all)
                .map(|s| format!(" — did you mean `{s}`?"))
                .unwrap_or_default();
            v.push(
                ProblemKind::Reference,
                &field,
                format!("no vehicle is named `{name}`{hint}"),
            );
        }
    }
}

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
            v.field(&p.key("period"), *period);
            v.field_with(
                &p.key("payload_bytes"),
                *payload_bytes as f64,
                None,
                Some(max_payload as f64),
            );
            v.field(&p.key("jitter"), *jitter);
        }
        BehaviourSpec::Leader { period, .. } => {
            v.field(&p.key("period"), *period);
            if max_payload < 13 {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "orders need 13 bytes of payload".into(),
                );
            }
        }
        BehaviourSpec::Follower {} => {
            if model.uauv2.is_none() {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "a follower steers in auto mode and needs the μAUV² layout".into(),
                );
            }
        }
        BehaviourSpec::ReliableGossip { start, hello, .. } => {
            v.field_with(&p.key("start"), *start, None, Some(duration));
            v.field(&p.key("hello"), *hello);
            if max_payload < 6 {
                v.push(
                    ProblemKind::Invalid,
                    p,
                    "reliable gossip frames need 6 bytes of payload".into(),
                );
            }
        }
        BehaviourSpec::Poisson {
            rate,
            payload_bytes,
            to,
            ack,
        } => {
            if *ack && to.is_none() {
                v.push(
                    ProblemKind::Invalid,
                    &p.key("ack"),
                    "only a unicast is acknowledged: name its destination with `to`".into(),
                );
            }
            v.field(&p.key("rate"), *rate);
            v.field_with(
                &p.key("payload_bytes"),
                *payload_bytes as f64,
                None,
                Some(max_payload as f64),
            );
        }
        BehaviourSpec::Gossip {
            start,
            repeats,
            interval,
            jitter,
            ..
        } => {
            v.field_with(&p.key("start"), *start, None, Some(duration));
            v.field(&p.key("repeats"), f64::from(*repeats));
            v.field(&p.key("interval"), *interval);
            v.field(&p.key("jitter"), *jitter);
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
            v.field(&p.key("surge"), *surge);
            v.field(&p.key("period"), *period);
            v.field(&p.key("too_close"), *too_close);
            v.field_with(&p.key("too_far"), *too_far, None, Some(*too_close));
            v.field(&p.key("cohesion"), *cohesion);
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
