//! A vehicle model: a preset with the file's overrides merged over it, then every body,
//! thruster, tilt, ballast, sensor, controller, modem and effect parameter checked, and the
//! mass matrix checked for being symmetric positive definite.

use super::group_link;
use super::messages::{explain, suggest};
use super::ranges::End;
use super::validator::{Validator, axis};
use crate::access::Frames;
use crate::error::{FieldPath, ProblemKind};
use crate::spec::*;
use shoal_model::prelude::*;

/// Recursively merges `over` into `base`: tables merge, everything else replaces.
pub fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// Builds and validates the vehicle model of a group: `preset` (default `uauv2`, or `custom`)
/// with the `model` overrides merged over it, and the group's link settings (`link`: name,
/// value) in every modem (see `group_link.rs`). `path` is the group's field path (for
/// messages).
pub fn vehicle_spec(
    (preset, model, link): (Option<&str>, Option<&toml::Table>, &[(&str, &toml::Value)]),
    path: &FieldPath,
    v: &mut Validator<'_>,
) -> Option<VehicleSpec> {
    let preset_name = preset.unwrap_or("uauv2");
    let mut base = if preset_name == "custom" {
        toml::Table::new()
    } else {
        match presets::by_name(preset_name) {
            Some(p) => match toml::Value::try_from(VehicleSpec::from_params(&p)) {
                Ok(toml::Value::Table(t)) => t,
                _ => toml::Table::new(),
            },
            None => {
                let mut names: Vec<&str> = presets::NAMES.to_vec();
                names.push("custom");
                let hint = suggest(preset_name, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::Reference,
                    &path.key("preset"),
                    format!(
                        "unknown preset `{preset_name}`{hint} (allowed: {})",
                        names.join(", ")
                    ),
                );
                return None;
            }
        }
    };
    if let Some(m) = model {
        merge(&mut base, m);
    }
    if !link.is_empty() && !group_link::apply(&mut base, model, link, path, v) {
        return None;
    }
    // Problems in the group's link settings are reported at them, once.
    let n0 = v.problems.len();
    let spec = read_model(base, preset_name, path, v);
    if !link.is_empty() {
        let given: Vec<&str> = link.iter().map(|(k, _)| *k).collect();
        v.move_problems(n0, |f| group_link::to_group(f, path, &given));
    }
    spec
}

/// Reads and validates the merged model table `base` of the group at `path`.
fn read_model(
    base: toml::Table,
    preset_name: &str,
    path: &FieldPath,
    v: &mut Validator<'_>,
) -> Option<VehicleSpec> {
    let mpath = path.key("model");
    let spec: VehicleSpec = match serde_path_to_error::deserialize(toml::Value::Table(base)) {
        Ok(s) => s,
        Err(e) => {
            let field = mpath.join(&FieldPath::parse(&e.path().to_string()));
            let (kind, message) = explain(e.inner().message(), Some(&field), ProblemKind::Invalid);
            let message = if kind == ProblemKind::MissingField && preset_name == "custom" {
                format!("{message} (a `custom` vehicle must give its whole model)")
            } else {
                message
            };
            v.push(kind, &field, message);
            return None;
        }
    };
    validate_vehicle(&spec, &mpath, v).then_some(spec)
}

pub(super) fn validate_vehicle(s: &VehicleSpec, p: &FieldPath, v: &mut Validator<'_>) -> bool {
    let n0 = v.problems.len();
    let b = p.key("body");
    let sb = &s.body;
    v.field(&b.key("mass"), sb.mass);
    match &sb.inertia {
        Mat3Spec::Diagonal(d) => {
            v.fields(&b.key("inertia"), d);
        }
        Mat3Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                // The diagonal (principal moments) has the diagonal form's range.
                if v.fields(&b.key("inertia").index(i), row) {
                    v.field_by(
                        &b.key("inertia").index(i).index(i),
                        &b.key("inertia"),
                        row[i],
                    );
                }
            }
        }
    }
    v.fields(&b.key("cog"), &sb.cog);
    v.fields(&b.key("cob"), &sb.cob);
    v.field(&b.key("volume"), sb.volume);
    match &sb.added_mass {
        Mat6Spec::Diagonal(d) => {
            v.fields(&b.key("added_mass"), d);
        }
        Mat6Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                v.fields(&b.key("added_mass").index(i), row);
            }
        }
    }
    v.fields(&b.key("damping_linear"), &sb.damping_linear);
    v.fields(&b.key("damping_quadratic"), &sb.damping_quadratic);
    v.fields(&b.key("hull_size"), &sb.hull_size);

    let mut tilt_names: Vec<&str> = Vec::new();
    for (i, t) in s.tilts.iter().enumerate() {
        let tp = p.key("tilts").index(i);
        if tilt_names.contains(&t.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &tp.key("name"),
                format!("tilt name `{}` is used twice", t.name),
            );
        }
        tilt_names.push(&t.name);
        axis(v, &tp.key("axis"), &t.axis);
        v.field(&tp.key("min_deg"), t.min_deg);
        v.field_with(&tp.key("max_deg"), t.max_deg, Some(t.min_deg), None);
        v.field(&tp.key("rate_deg_s"), t.rate_deg_s);
    }
    let mut thruster_names: Vec<&str> = Vec::new();
    for (i, t) in s.thrusters.iter().enumerate() {
        let tp = p.key("thrusters").index(i);
        if thruster_names.contains(&t.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &tp.key("name"),
                format!("thruster name `{}` is used twice", t.name),
            );
        }
        thruster_names.push(&t.name);
        v.fields(&tp.key("position"), &t.position);
        axis(v, &tp.key("direction"), &t.direction);
        if let Some(n) = &t.tilt
            && !tilt_names.contains(&n.as_str())
        {
            let defined = if tilt_names.is_empty() {
                "none".into()
            } else {
                tilt_names.join(", ")
            };
            v.push(
                ProblemKind::Reference,
                &tp.key("tilt"),
                format!("no tilt drive named `{n}` (defined: {defined})"),
            );
        }
        v.field(&tp.key("max_command"), t.max_command);
        v.field(&tp.key("lag"), t.lag);
        let cp = tp.key("curve");
        match &t.curve {
            CurveSpec::Quadratic { ct_pos, ct_neg } => {
                v.field(&cp.key("ct_pos"), *ct_pos);
                v.field(&cp.key("ct_neg"), *ct_neg);
            }
            CurveSpec::Table { points } => {
                if points.len() < 2 {
                    v.push(
                        ProblemKind::Invalid,
                        &cp.key("points"),
                        "a thrust table needs at least 2 [command, thrust] points".into(),
                    );
                }
                for (k, w) in points.windows(2).enumerate() {
                    if w[1][0].partial_cmp(&w[0][0]) != Some(std::cmp::Ordering::Greater)
                        || w[1][1] < w[0][1]
                    {
                        v.push(
                            ProblemKind::Invalid,
                            &cp.key("points").index(k + 1),
                            "thrust table points must increase in command and must not decrease in thrust".into(),
                        );
                    }
                }
                for (k, pt) in points.iter().enumerate() {
                    v.fields(&cp.key("points").index(k), pt);
                }
            }
        }
    }
    if let Some(bl) = &s.ballast {
        let bp = p.key("ballast");
        v.field(&bp.key("capacity"), bl.capacity);
        v.field(&bp.key("flow"), bl.flow);
        v.fields(&bp.key("position"), &bl.position);
        v.field_with(
            &bp.key("initial_volume"),
            bl.initial_volume,
            None,
            Some(bl.capacity),
        );
    }
    let pp = p.key("pressure");
    let ps = &s.pressure;
    v.field(&pp.key("c1"), ps.c1);
    v.field(&pp.key("c2"), ps.c2);
    v.field(&pp.key("depth_step"), ps.depth_step);
    v.field(&pp.key("bits"), f64::from(ps.bits));
    v.field(&pp.key("noise_std"), ps.noise_std);
    v.fields(&pp.key("position"), &ps.position);
    let ip = p.key("imu");
    v.field(&ip.key("attitude_noise_deg"), s.imu.attitude_noise_deg);
    v.field(&ip.key("gyro_noise"), s.imu.gyro_noise);
    v.fields(&ip.key("gyro_bias"), &s.imu.gyro_bias);
    v.field(&ip.key("accel_noise"), s.imu.accel_noise);
    let c = p.key("control");
    let sc = &s.control;
    v.field(&c.key("period"), sc.period);
    for (k, pd) in [
        ("heave", &sc.heave),
        ("heave_buoyancy", &sc.heave_buoyancy),
        ("yaw", &sc.yaw),
    ] {
        let kp = c.key(k);
        v.field(&kp.key("omega"), pd.omega);
        v.field(&kp.key("zeta"), pd.zeta);
        if let Some(x) = pd.kp {
            v.field(&kp.key("kp"), x);
        }
        if let Some(x) = pd.kd {
            v.field(&kp.key("kd"), x);
        }
    }
    v.field(&c.key("dead_zone"), sc.dead_zone);
    v.field(&c.key("filter_window"), sc.filter_window as f64);
    v.field(&c.key("auto_tilt_max_deg"), sc.auto_tilt_max_deg);
    v.field(&c.key("rate_filter"), sc.rate_filter);
    let mut modem_names: Vec<&str> = Vec::new();
    for (i, m) in s.modems.iter().enumerate() {
        let mp = p.key("modems").index(i);
        validate_modem(m, &mp, v);
        if modem_names.contains(&m.name.as_str()) {
            v.push(
                ProblemKind::Invalid,
                &mp.key("name"),
                format!("modem name `{}` is used twice", m.name),
            );
        }
        modem_names.push(&m.name);
    }
    if v.problems.len() > n0 {
        return false;
    }
    // Physical consistency: the mass matrix must be symmetric positive definite.
    let params = s.to_params();
    let m = params
        .mass_properties(params.initial_ballast(), 1000.0)
        .m_total;
    if (m - m.transpose()).abs().max() > 1e-9 * m.abs().max() || m.cholesky().is_none() {
        v.push(ProblemKind::Invalid, &b.key("added_mass"),
            "mass matrix M_RB + M_A is not symmetric positive definite (check inertia and added_mass)".into());
        return false;
    }
    for (i, e) in s.effects.iter().enumerate() {
        validate_effect(e, &params, &p.key("effects").index(i), v);
    }
    v.problems.len() == n0
}

pub(super) fn validate_effect(
    e: &EffectSpec,
    vehicle: &VehicleParams,
    p: &FieldPath,
    v: &mut Validator<'_>,
) {
    let Some(effect) = shoal_model::effects::by_name(&e.name) else {
        let names = shoal_model::effects::names();
        let hint = suggest(&e.name, &names)
            .map(|s| format!(" — did you mean `{s}`?"))
            .unwrap_or_default();
        v.push(
            ProblemKind::Reference,
            &p.key("name"),
            format!(
                "unknown effect `{}`{hint} (allowed: {})",
                e.name,
                names.join(", ")
            ),
        );
        return;
    };
    let effect = match e.form.as_deref() {
        None => effect,
        Some(f) => match shoal_model::effects::by_name_form(&e.name, Some(f)) {
            Some(x) => x,
            None => {
                v.push(
                    ProblemKind::Reference,
                    &p.key("form"),
                    format!(
                        "effect `{}` has no form `{f}` (allowed: {})",
                        e.name,
                        shoal_model::effects::forms(&e.name).join(", ")
                    ),
                );
                return;
            }
        },
    };
    if let Some(why) = effect.not_applicable(vehicle) {
        v.push(
            ProblemKind::Invalid,
            &p.key("name"),
            format!("effect `{}` does not apply: {why}", e.name),
        );
        return;
    }
    let infos = effect.params(vehicle);
    let names: Vec<&str> = infos.iter().map(|i| i.name).collect();
    let pp = p.key("params");
    for (k, &x) in &e.params {
        match infos.iter().find(|i| i.name == k) {
            Some(i) => {
                v.num(&pp.key(k), x, End::Closed(i.lo), End::Closed(i.hi), i.unit);
            }
            None => {
                let hint = suggest(k, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::UnknownField,
                    &pp.key(k),
                    format!(
                        "unknown parameter `{k}` of effect `{}`{hint} (allowed: {})",
                        e.name,
                        names.join(", ")
                    ),
                );
            }
        }
    }
    for i in &infos {
        if !e.params.contains_key(i.name) {
            v.push(
                ProblemKind::MissingField,
                &pp,
                format!(
                    "effect `{}` needs parameter `{}` [{}] ({}; {} … {}, {} = no effect)",
                    e.name, i.name, i.unit, i.doc, i.lo, i.hi, i.null
                ),
            );
        }
    }
}

pub(super) fn validate_modem(m: &ModemSpec, p: &FieldPath, v: &mut Validator<'_>) {
    v.fields(&p.key("position"), &m.position);
    axis(v, &p.key("direction"), &m.direction);
    v.field(&p.key("led_power"), m.led_power);
    v.field(&p.key("led_half_angle_deg"), m.led_half_angle_deg);
    v.field(&p.key("rx_area"), m.rx_area);
    v.field(&p.key("rx_fov_deg"), m.rx_fov_deg);
    v.field(&p.key("responsivity"), m.responsivity);
    v.field(&p.key("noise_density"), m.noise_density);
    v.field(&p.key("bandwidth"), m.bandwidth);
    v.field(&p.key("dark_current"), m.dark_current);
    v.field(&p.key("bit_rate"), m.bit_rate);
    v.field(&p.key("bits_per_byte"), f64::from(m.bits_per_byte));
    v.field(&p.key("header_bytes"), m.header_bytes as f64);
    v.field(&p.key("max_payload"), m.max_payload as f64);
    v.field(&p.key("queue_frames"), m.queue_frames as f64);
    v.field(&p.key("capture_ratio"), m.capture_ratio);
    // The protocol's settings, each against its row (a slot must hold the longest frame).
    let frames = Frames {
        longest: m.to_params().airtime(m.max_payload),
    };
    let ap = p.key("access");
    for n in m.access.numbers(&frames) {
        v.field_with(&ap.key(n.name), n.value, n.lo, n.hi);
    }
    v.field(&p.key("arq_retries"), f64::from(m.arq_retries));
    v.field(&p.key("ack_timeout"), m.ack_timeout);
}
