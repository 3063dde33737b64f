//! Advice: what a world file may say but probably does not mean. Unlike problems these do not
//! stop the load; `shoal check` and `shoal run` print them.
//!
//! A vehicle far from neutral buoyancy is the common case: an overridden mass or volume leaves
//! it heavy or light by more than its thrusters can comfortably hold, and it sinks or rises
//! while every number in the file is within its range.

use crate::desc::VehicleDesc;
use shoal_model::prelude::*;

/// Net weight beyond this fraction of the thrust the vehicle's thrusters give together is
/// "strongly non-neutral": the controller spends most of its authority on it.
pub const NON_NEUTRAL_FRACTION: f64 = 0.25;

/// The advice for the vehicles of each group (the first vehicle stands for its group, whose
/// vehicles share one model).
pub(super) fn advice(
    vehicles: &[VehicleDesc],
    groups: &[String],
    env: &Environment,
) -> Vec<String> {
    let mut out = Vec::new();
    for (g, name) in groups.iter().enumerate() {
        let Some(v) = vehicles.iter().find(|v| v.group == g) else {
            continue;
        };
        if let Some(a) = buoyancy(name, &v.model.params, env) {
            out.push(a);
        }
    }
    out
}

/// Advice on a model whose net weight in this water is large against its thrust.
fn buoyancy(group: &str, p: &VehicleParams, env: &Environment) -> Option<String> {
    let net = p.net_weight(env);
    let thrust: f64 = p
        .thrusters
        .iter()
        .map(|t| t.curve.thrust(t.max_command).abs())
        .sum();
    let weight = (p.body.mass + p.initial_ballast() * env.density) * env.gravity;
    let strong = if thrust > 0.0 {
        net.abs() > NON_NEUTRAL_FRACTION * thrust
    } else {
        net.abs() > 0.01 * weight
    };
    if !strong {
        return None;
    }
    let neutral_mass = (p.body.volume - p.initial_ballast()) * env.density;
    let share = if thrust > 0.0 {
        format!(
            " ({:.0} % of the {:.2} N its thrusters give together at full command)",
            100.0 * net.abs() / thrust,
            thrust
        )
    } else {
        String::new()
    };
    Some(format!(
        "vehicles `{group}` are {:.3} N {} in this water at their initial ballast{share}: \
         they {} unless a controller holds them. Neutral would be model.body.mass = {:.4} kg \
         (now {:.4} kg) or model.body.volume = {:.4e} m³",
        net.abs(),
        if net > 0.0 { "heavy" } else { "light" },
        if net > 0.0 { "sink" } else { "rise" },
        neutral_mass,
        p.body.mass,
        p.body.mass / env.density + p.initial_ballast(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::presets;

    #[test]
    fn the_preset_is_neutral_and_a_heavier_one_is_named_with_the_neutral_mass() {
        let env = Environment::default();
        let p = presets::uauv2();
        assert!(buoyancy("g", &p, &env).is_none());
        let mut heavy = p.clone();
        heavy.body.mass += 0.02; // +0.196 N
        let a = buoyancy("divers", &heavy, &env).expect("advice");
        assert!(a.contains("`divers` are 0.196 N heavy"), "{a}");
        assert!(
            a.contains(&format!("model.body.mass = {:.4} kg", p.body.mass)),
            "{a}"
        );
        // A few grams are within what the thrusters hold easily.
        let mut slight = p.clone();
        slight.body.mass += 0.002;
        assert!(buoyancy("g", &slight, &env).is_none());
    }
}
