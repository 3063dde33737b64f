//! A vehicle model: a preset with the file's overrides merged over it, then every body,
//! thruster, tilt, ballast, sensor, controller, modem and effect parameter checked, and the
//! mass matrix checked for being symmetric positive definite.

use super::messages::{explain, suggest};
use super::validator::{End, Validator, axis};
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
/// with the `model` overrides merged over it. `path` is the group's field path (for messages).
pub fn vehicle_spec(
    preset: Option<&str>,
    model: Option<&toml::Table>,
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
    v.pos(&b, "mass", sb.mass, 1e5, "kg");
    match &sb.inertia {
        Mat3Spec::Diagonal(d) => {
            v.vec(
                &b.key("inertia"),
                d,
                End::Open(0.0),
                End::Closed(1e5),
                "kg·m²",
            );
        }
        Mat3Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                v.vec(
                    &b.key("inertia").index(i),
                    row,
                    End::Closed(-1e5),
                    End::Closed(1e5),
                    "kg·m²",
                );
            }
        }
    }
    v.within_all(&b, "cog", &sb.cog, -100.0, 100.0, "m");
    v.within_all(&b, "cob", &sb.cob, -100.0, 100.0, "m");
    v.pos(&b, "volume", sb.volume, 1e3, "m³");
    match &sb.added_mass {
        Mat6Spec::Diagonal(d) => {
            v.within_all(&b, "added_mass", d, 0.0, 1e5, "kg or kg·m²");
        }
        Mat6Spec::Full(r) => {
            for (i, row) in r.iter().enumerate() {
                v.vec(
                    &b.key("added_mass").index(i),
                    row,
                    End::Closed(-1e5),
                    End::Closed(1e5),
                    "",
                );
            }
        }
    }
    v.within_all(
        &b,
        "damping_linear",
        &sb.damping_linear,
        0.0,
        1e5,
        "N·s/m or N·m·s",
    );
    v.within_all(
        &b,
        "damping_quadratic",
        &sb.damping_quadratic,
        0.0,
        1e5,
        "N·s²/m² or N·m·s²",
    );
    v.vec(
        &b.key("hull_size"),
        &sb.hull_size,
        End::Open(0.0),
        End::Closed(100.0),
        "m",
    );

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
        v.within(&tp, "min_deg", t.min_deg, -360.0, 360.0, "deg");
        v.within(
            &tp,
            "max_deg",
            t.max_deg,
            t.min_deg.max(-360.0),
            360.0,
            "deg",
        );
        v.pos(&tp, "rate_deg_s", t.rate_deg_s, 1e4, "deg/s");
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
        v.within_all(&tp, "position", &t.position, -100.0, 100.0, "m");
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
        v.pos(&tp, "max_command", t.max_command, 1e4, "%");
        v.nonneg(&tp, "lag", t.lag, 100.0, "s");
        let cp = tp.key("curve");
        match &t.curve {
            CurveSpec::Quadratic { ct_pos, ct_neg } => {
                v.nonneg(&cp, "ct_pos", *ct_pos, 1e3, "N/%²");
                v.nonneg(&cp, "ct_neg", *ct_neg, 1e3, "N/%²");
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
                    if !pt[0].is_finite() || !pt[1].is_finite() {
                        v.push(
                            ProblemKind::Range,
                            &cp.key("points").index(k),
                            "not a finite number".into(),
                        );
                    }
                }
            }
        }
    }
    if let Some(bl) = &s.ballast {
        let bp = p.key("ballast");
        v.pos(&bp, "capacity", bl.capacity, 10.0, "m³");
        v.nonneg(&bp, "flow", bl.flow, 1.0, "m³/s");
        v.within_all(&bp, "position", &bl.position, -100.0, 100.0, "m");
        v.nonneg(
            &bp,
            "initial_volume",
            bl.initial_volume,
            bl.capacity.max(0.0),
            "m³ (the tank capacity)",
        );
    }
    let pp = p.key("pressure");
    let ps = &s.pressure;
    v.pos(&pp, "c1", ps.c1, 1e4, "m/V");
    v.within(&pp, "c2", ps.c2, -1e4, 1e4, "m");
    v.pos(&pp, "depth_step", ps.depth_step, 10.0, "m");
    v.within(&pp, "bits", f64::from(ps.bits), 1.0, 32.0, "bits");
    v.nonneg(&pp, "noise_std", ps.noise_std, 10.0, "m");
    v.within_all(&pp, "position", &ps.position, -100.0, 100.0, "m");
    let ip = p.key("imu");
    v.nonneg(
        &ip,
        "attitude_noise_deg",
        s.imu.attitude_noise_deg,
        90.0,
        "deg",
    );
    v.nonneg(&ip, "gyro_noise", s.imu.gyro_noise, 10.0, "rad/s");
    v.within_all(&ip, "gyro_bias", &s.imu.gyro_bias, -10.0, 10.0, "rad/s");
    v.nonneg(&ip, "accel_noise", s.imu.accel_noise, 100.0, "m/s²");
    let c = p.key("control");
    let sc = &s.control;
    v.pos(&c, "period", sc.period, 10.0, "s");
    for (k, pd) in [
        ("heave", &sc.heave),
        ("heave_buoyancy", &sc.heave_buoyancy),
        ("yaw", &sc.yaw),
    ] {
        let kp = c.key(k);
        v.pos(&kp, "omega", pd.omega, 100.0, "rad/s");
        v.pos(&kp, "zeta", pd.zeta, 100.0, "");
        if let Some(x) = pd.kp {
            v.nonneg(&kp, "kp", x, 1e6, "");
        }
        if let Some(x) = pd.kd {
            v.nonneg(&kp, "kd", x, 1e6, "");
        }
    }
    v.nonneg(&c, "dead_zone", sc.dead_zone, 10.0, "m");
    v.within(
        &c,
        "filter_window",
        sc.filter_window as f64,
        1.0,
        1000.0,
        "samples",
    );
    v.nonneg(&c, "auto_tilt_max_deg", sc.auto_tilt_max_deg, 90.0, "deg");
    v.nonneg(&c, "rate_filter", sc.rate_filter, 100.0, "s");
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

pub(super) fn validate_effect(e: &EffectSpec, vehicle: &VehicleParams, p: &FieldPath, v: &mut Validator<'_>) {
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
                v.within(&pp, k, x, i.lo, i.hi, i.unit);
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
    v.within_all(p, "position", &m.position, -100.0, 100.0, "m");
    axis(v, &p.key("direction"), &m.direction);
    v.pos(p, "led_power", m.led_power, 1e3, "W");
    v.num(
        &p.key("led_half_angle_deg"),
        m.led_half_angle_deg,
        End::Open(0.0),
        End::Open(90.0),
        "deg",
    );
    v.pos(p, "rx_area", m.rx_area, 1.0, "m²");
    v.pos(p, "rx_fov_deg", m.rx_fov_deg, 90.0, "deg");
    v.pos(p, "responsivity", m.responsivity, 10.0, "A/W");
    v.nonneg(p, "noise_density", m.noise_density, 1e-6, "A/√Hz");
    v.pos(p, "bandwidth", m.bandwidth, 1e10, "Hz");
    v.nonneg(p, "dark_current", m.dark_current, 1e-3, "A");
    v.pos(p, "bit_rate", m.bit_rate, 1e10, "bit/s");
    v.within(
        p,
        "bits_per_byte",
        f64::from(m.bits_per_byte),
        8.0,
        16.0,
        "bits",
    );
    v.nonneg(p, "header_bytes", m.header_bytes as f64, 64.0, "bytes");
    v.within(
        p,
        "max_payload",
        m.max_payload as f64,
        1.0,
        65536.0,
        "bytes",
    );
    v.within(p, "queue_frames", m.queue_frames as f64, 1.0, 1e5, "frames");
    v.within(
        p,
        "capture_ratio",
        m.capture_ratio,
        1.0,
        1e6,
        "(power ratio)",
    );
    v.pos(p, "cs_threshold", m.cs_threshold, 1.0, "W");
    v.pos(p, "backoff_max", m.backoff_max, 100.0, "s");
}
