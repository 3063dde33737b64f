//! World files: the documented errors for bad input (unknown field, wrong unit, out-of-range
//! numbers, overlapping vehicles, vehicles outside the pool, broken references), and that good
//! files — the embedded default and every file in `worlds/` — load.

use shoal_world::error::ProblemKind;
use shoal_world::load::{load_file, load_str, vehicle_world_toml};
use shoal_world::prelude::*;
use shoal_world::spec::VehicleSpec;
use std::path::Path;

fn err(text: &str) -> WorldError {
    match load_str(text, Path::new("bad.toml")) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

const ONE: &str = "[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nposition = [1.0, 1.0, 0.5]\n";

#[test]
fn default_world_loads() {
    let w = default_world().expect("the embedded default world is valid");
    assert_eq!(w.vehicles.len(), 12);
    assert!(w.vehicles.iter().all(|v| v.model.uauv2.is_some()));
    assert_eq!(w.steps(), 10_000);
}

#[test]
fn every_shipped_world_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            load_file(&p).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 1);
}

#[test]
fn minimal_world_uses_defaults() {
    let w = load_str(ONE, Path::new("one.toml")).unwrap();
    assert_eq!(w.vehicles.len(), 1);
    assert_eq!(w.dt, 0.01);
    assert_eq!(w.duration, 60.0);
    assert_eq!(w.vehicles[0].model.params.name, "uauv2");
}

#[test]
fn unknown_field_is_named_with_line_and_suggestion() {
    let e = err("seed = 1\ndurration = 5.0\n");
    let p = e.first();
    assert_eq!(p.kind, ProblemKind::UnknownField);
    assert_eq!(p.line_col.map(|l| l.0), Some(2));
    let msg = e.to_string();
    assert!(msg.starts_with("bad.toml:2:"), "{msg}");
    assert!(
        msg.contains("`durration`") && msg.contains("did you mean `duration`"),
        "{msg}"
    );
}

#[test]
fn unknown_field_deep_in_a_mission() {
    let e = err(&format!(
        "{ONE}mission = [{{ t = 0, mode = \"diving\", dept = 0.4 }}]\n"
    ));
    assert_eq!(e.first().kind, ProblemKind::UnknownField);
    assert_eq!(e.first().line_col.map(|l| l.0), Some(5));
    assert!(e.to_string().contains("did you mean `depth`"), "{e}");
}

#[test]
fn wrong_unit_radians_field_suggests_degrees() {
    // There is no `yaw` field: angles in files are in degrees and say so.
    let e = err(&format!(
        "{ONE}mission = [{{ t = 0, mode = \"turning\", yaw = 1.57 }}]\n"
    ));
    assert_eq!(e.first().kind, ProblemKind::UnknownField);
    assert!(e.to_string().contains("did you mean `yaw_deg`"), "{e}");
}

#[test]
fn wrong_unit_written_in_the_value() {
    let e = err("duration = \"60 s\"\n");
    let p = e.first();
    assert_eq!(p.kind, ProblemKind::Type);
    assert_eq!(p.line_col.map(|l| l.0), Some(1));
    let msg = e.to_string();
    assert!(
        msg.contains("seconds") && msg.contains("units are implied"),
        "{msg}"
    );
}

#[test]
fn negative_mass_is_out_of_range_with_the_allowed_range() {
    let e = err(&format!("{ONE}[vehicles.model.body]\nmass = -1.2\n"));
    let p = e.first();
    assert_eq!(p.kind, ProblemKind::Range);
    assert_eq!(
        p.field.as_ref().unwrap().to_string(),
        "vehicles[0].model.body.mass"
    );
    assert_eq!(p.line_col.map(|l| l.0), Some(6));
    let msg = e.to_string();
    assert!(
        msg.contains("-1.2 is out of range") && msg.contains("0.001 ≤ mass ≤ 1e5 kg"),
        "{msg}"
    );
}

#[test]
fn typo_in_model_override_is_an_unknown_field() {
    let e = err(&format!("{ONE}[vehicles.model.body]\nmas = 1.2\n"));
    assert_eq!(e.first().kind, ProblemKind::UnknownField);
    assert_eq!(e.first().line_col.map(|l| l.0), Some(6));
    assert!(e.to_string().contains("did you mean `mass`"), "{e}");
}

#[test]
fn overlapping_vehicles_are_rejected() {
    let text = "[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nname = \"a\"\nposition = [1.0, 1.0, 0.5]\n[[vehicles]]\nname = \"b\"\nposition = [1.1, 1.0, 0.5]\n";
    let e = err(text);
    assert_eq!(e.first().kind, ProblemKind::Overlap);
    let msg = e.to_string();
    assert!(
        msg.contains("`b`") && msg.contains("overlaps vehicle `a`"),
        "{msg}"
    );
    assert_eq!(e.first().line_col.map(|l| l.0), Some(6));
    // A grid with too little spacing overlaps too.
    let e = err(
        "[[vehicles]]\ncount = 3\ngrid = { origin = [1, 1, 1], spacing = [0.2, 0.0], columns = 3 }\n",
    );
    assert_eq!(e.first().kind, ProblemKind::Overlap);
}

#[test]
fn vehicle_outside_the_pool_is_rejected() {
    let e = err("[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nposition = [5.0, 1.0, 0.5]\n");
    assert_eq!(e.first().kind, ProblemKind::Outside);
    assert_eq!(e.first().line_col.map(|l| l.0), Some(4));
    assert!(e.to_string().contains("0 ≤ x ≤ 4"), "{e}");
    // Through the floor.
    let e = err("[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nposition = [1.0, 1.0, 1.95]\n");
    assert_eq!(e.first().kind, ProblemKind::Outside);
}

#[test]
fn vehicle_inside_an_obstacle_is_rejected() {
    let e = err(
        "[[obstacles]]\nshape = \"sphere\"\nradius = 0.5\nposition = [2, 2, 1]\n[[vehicles]]\nposition = [2.2, 2.0, 1.0]\n",
    );
    assert_eq!(e.first().kind, ProblemKind::Overlap);
    assert!(e.to_string().contains("obstacle `obstacle-0`"), "{e}");
}

#[test]
fn broken_references_are_named() {
    let e = err(&format!(
        "{ONE}mission = [{{ t = 0, mode = \"raw\", thrusters = {{ left = 50 }} }}]\n"
    ));
    assert_eq!(e.first().kind, ProblemKind::Reference);
    assert!(e.to_string().contains("top, port, stbd"), "{e}");
    let e = err("[[vehicles]]\npreset = \"uav2\"\nposition = [1, 1, 1]\n");
    assert_eq!(e.first().kind, ProblemKind::Reference);
    assert!(e.to_string().contains("did you mean `uauv2`"), "{e}");
    let e = err(&format!("{ONE}mission = [{{ t = 0, mode = \"hover\" }}]\n"));
    assert_eq!(e.first().kind, ProblemKind::Reference);
    assert!(e.to_string().contains("diving"), "{e}");
    let e = err("[water]\nattenuation = \"harbour\"\n");
    assert!(e.to_string().contains("turbid_harbour"), "{e}");
}

#[test]
fn other_ranges_and_consistency() {
    assert_eq!(err("dt = 0.0\n").first().kind, ProblemKind::Range);
    assert_eq!(err("dt = nan\n").first().kind, ProblemKind::Range);
    let e = err(&format!("{ONE}mission = [{{ t = 0, depth = 3.5 }}]\n"));
    assert!(e.to_string().contains("pool depth"), "{e}");
    let e = err(&format!("{ONE}mission = [{{ t = 5 }}, {{ t = 1 }}]\n"));
    assert!(e.to_string().contains("time order"), "{e}");
    let e = err(&format!("{ONE}[vehicles.model.control]\nperiod = 0.033\n"));
    assert!(e.to_string().contains("whole multiple of dt"), "{e}");
    let e = err(&format!(
        "{ONE}[vehicles.model.ballast]\ninitial_volume = 1.0\n"
    ));
    assert_eq!(e.first().kind, ProblemKind::Range);
    // Several problems are all reported.
    let e = err("dt = -1\nduration = -5\n");
    assert_eq!(e.problems.len(), 2);
}

/// A modem's `access` is a protocol's name or a table with its `kind` and settings; a
/// setting of another protocol, one out of range, and a setting written beside `access` as
/// older files did are refused with the field, its line and what to write.
#[test]
fn medium_access_settings_are_checked_in_their_table() {
    let modem = |m: &str| format!("{ONE}[[vehicles.model.modems]]\n{m}\n");
    let ok = load_str(
        &modem("access = { kind = \"tdma\", slot = 0.04, slots = 4, own_slot = 3 }"),
        Path::new("ok.toml"),
    )
    .unwrap();
    let l = ok.vehicles[0].link[0];
    assert_eq!(l.access.slot(), Some(0.04));
    let e = err(&modem("access = { kind = \"tdma\", cw_min = 8 }"));
    assert_eq!(e.first().kind, ProblemKind::UnknownField);
    assert!(e.to_string().contains("`cw_min`"), "{e}");
    let e = err(&modem(
        "access = { kind = \"tdma\", slots = 4, own_slot = 4 }",
    ));
    let msg = e.to_string();
    assert!(
        msg.contains("access.own_slot") && msg.contains("< 4 (slots)"),
        "{msg}"
    );
    // The slot must hold a 58-byte frame: 640 line bits at 19.2 kbit/s.
    let e = err(&modem("access = { kind = \"slotted_aloha\", slot = 0.01 }"));
    assert!(e.to_string().contains("0.0333"), "{e}");
    let e = err(&modem("access = { kind = \"p_persistent\", p = 0.0 }"));
    assert!(e.to_string().contains("0 < p ≤ 1"), "{e}");
    let e = err(&modem("access = \"csma_ca\"\ncw_min = 8"));
    assert!(
        e.to_string()
            .contains("access = { kind = \"csma_ca\", cw_min = … }"),
        "{e}"
    );
    assert_eq!(e.first().line_col.map(|l| l.0), Some(7));
}

/// A group's `access` sets the medium access of every modem of its model — its own modems
/// and the preset's — in one line; a problem in it is reported once, at the group's field and line;
/// a modem that sets its own as well is refused.
#[test]
fn a_groups_access_sets_every_modem_and_is_checked_there() {
    let group = |a: &str| format!("{ONE}access = {a}\n");
    let csma = "{ kind = \"csma_ca\", cw_min = 8 }";
    let two = "[[vehicles.model.modems]]\n[[vehicles.model.modems]]\nname = \"back\"\ndirection = [-1.0, 0.0, 0.0]\n";
    for text in [group(csma), format!("{}{two}", group(csma))] {
        let ok = load_str(&text, Path::new("ok.toml")).unwrap();
        let links = &ok.vehicles[0].link;
        assert_eq!(links.len(), if text.contains("direction") { 2 } else { 1 });
        for l in links.iter() {
            assert!(
                format!("{:?}", l.access).contains("cw_min: 8"),
                "{:?}",
                l.access
            );
        }
    }
    // Without it, ALOHA as before.
    let plain = load_str(ONE, Path::new("ok.toml")).unwrap();
    assert!(format!("{:?}", plain.vehicles[0].link[0].access).starts_with("Aloha"));
    // Out of range: once, at the group's `access`, on its line (line 5).
    let e = err(&group("{ kind = \"p_persistent\", p = 2.0 }"));
    let field = |e: &WorldError| e.first().field.as_ref().map(ToString::to_string);
    assert_eq!(e.problems.len(), 1, "{e}");
    assert_eq!(e.first().kind, ProblemKind::Range);
    assert_eq!(field(&e).as_deref(), Some("vehicles[0].access.p"), "{e}");
    assert_eq!(e.first().line_col.map(|l| l.0), Some(5), "{e}");
    // Another protocol's setting, or an unknown protocol: at the group's `access`.
    let e = err(&group("{ kind = \"tdma\", cw_min = 8 }"));
    assert_eq!(e.first().kind, ProblemKind::UnknownField);
    for e in [e, err(&group("\"csma\""))] {
        let f = field(&e).unwrap_or_default();
        assert!(f.starts_with("vehicles[0].access"), "{e}");
    }
    // Both the group and a modem: refused at the modem's, naming the group's.
    let e = err(&format!(
        "{}[[vehicles.model.modems]]\naccess = \"tdma\"\n",
        group("\"csma_ca\"")
    ));
    assert_eq!(
        field(&e).as_deref(),
        Some("vehicles[0].model.modems[0].access")
    );
    assert!(e.to_string().contains("vehicles[0].access"), "{e}");
}

/// A group's `arq_retries` and `ack_timeout` set every modem's as its `access` does: in
/// every modem (its own and the preset's), checked there and reported at the group's field
/// and line; a modem's own setting that the group does not give stays the modem's; a modem
/// that sets what the group gives is refused.
#[test]
fn a_groups_retry_settings_set_every_modem_and_are_checked_there() {
    let two = "[[vehicles.model.modems]]\n[[vehicles.model.modems]]\nname = \"back\"\ndirection = [-1.0, 0.0, 0.0]\n";
    let text = format!("{ONE}arq_retries = 5\nack_timeout = 0.2\n{two}");
    let ok = load_str(&text, Path::new("ok.toml")).unwrap();
    let links = &ok.vehicles[0].link;
    assert_eq!(links.len(), 2);
    for l in links.iter() {
        assert_eq!((l.retries, l.ack_timeout), (5, 0.2));
    }
    // The defaults without them.
    let plain = load_str(ONE, Path::new("ok.toml")).unwrap();
    let l = &plain.vehicles[0].link[0];
    assert_eq!((l.retries, l.ack_timeout), (3, 0.05));
    let field = |e: &WorldError| e.first().field.as_ref().map(ToString::to_string);
    // Out of range: once, at the group's field, on its line (line 5).
    let e = err(&format!("{ONE}arq_retries = 1000\n{two}"));
    assert_eq!(e.problems.len(), 1, "{e}");
    assert_eq!(e.first().kind, ProblemKind::Range);
    assert_eq!(field(&e).as_deref(), Some("vehicles[0].arq_retries"), "{e}");
    assert_eq!(e.first().line_col.map(|l| l.0), Some(5), "{e}");
    // A modem's own, where the group gives another setting: at the modem's.
    let e = err(&format!(
        "{ONE}ack_timeout = 0.2\n[[vehicles.model.modems]]\narq_retries = 1000\n"
    ));
    assert_eq!(
        field(&e).as_deref(),
        Some("vehicles[0].model.modems[0].arq_retries"),
        "{e}"
    );
    // Both the group and a modem: refused at the modem's, naming the group's.
    let e = err(&format!(
        "{ONE}ack_timeout = 0.2\n[[vehicles.model.modems]]\nack_timeout = 0.1\n"
    ));
    assert_eq!(
        field(&e).as_deref(),
        Some("vehicles[0].model.modems[0].ack_timeout")
    );
    assert!(e.to_string().contains("vehicles[0].ack_timeout"), "{e}");
}

#[test]
fn syntax_errors_have_a_line() {
    let e = err("seed = 1\n[pool\nsize = 3\n");
    assert_eq!(e.first().kind, ProblemKind::Syntax);
    assert_eq!(e.first().line_col.map(|l| l.0), Some(2));
}

#[test]
fn a_vehicle_file_round_trips_through_the_world_format() {
    let spec = VehicleSpec::from_params(&shoal_model::presets::uauv2());
    let text = vehicle_world_toml(&spec, [2.0, 2.0, 1.0]).unwrap();
    let w = load_str(&text, Path::new("vehicle.toml")).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(w.vehicles.len(), 1);
    assert_eq!(w.vehicles[0].model.params, shoal_model::presets::uauv2());
}

#[test]
fn custom_vehicle_must_be_complete() {
    let e = err(
        "[[vehicles]]\npreset = \"custom\"\nposition = [1, 1, 1]\n[vehicles.model]\nname = \"x\"\n",
    );
    assert_eq!(e.first().kind, ProblemKind::MissingField);
    assert!(e.to_string().contains("whole model"), "{e}");
}

const WITH_EFFECTS: &str = "[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nposition = [1.0, 1.0, 0.5]\n\
[[vehicles.model.effects]]\nname = \"thruster_lag\"\nparams = { tau_s = 0.3 }\n\
[[vehicles.model.effects]]\nname = \"water_current\"\nparams = { vx_m_s = 0.02, vy_m_s = 0.0 }\n";

#[test]
fn effects_in_a_world_file_reach_the_model() {
    let w = load_str(WITH_EFFECTS, Path::new("fx.toml")).unwrap();
    let m = &w.vehicles[0].model;
    let names: Vec<&str> = m.effects.list().iter().map(|e| e.effect.name()).collect();
    assert_eq!(names, ["thruster_lag", "water_current"]);
    // Configure hooks applied: the lag is in the thrusters; the current in the vehicle's water.
    assert!(
        m.params
            .thrusters
            .iter()
            .all(|t| (t.lag - 0.3).abs() < 1e-15)
    );
    assert_eq!(m.environment(&w.env).current.x, 0.02);
    // The controller is designed on the model as given.
    let plain = load_str(ONE, Path::new("one.toml")).unwrap();
    assert_eq!(m.uauv2, plain.vehicles[0].model.uauv2);
}

#[test]
fn bad_effects_are_located_with_allowed_values() {
    let e = err(&WITH_EFFECTS.replace("thruster_lag", "thruster_lagg"));
    let msg = e.to_string();
    assert!(
        msg.contains("unknown effect `thruster_lagg`")
            && msg.contains("did you mean `thruster_lag`"),
        "{msg}"
    );
    assert!(msg.starts_with("bad.toml:6:"), "{msg}");
    let e = err(&WITH_EFFECTS.replace("tau_s = 0.3", "tau_s = 7.0"));
    let msg = e.to_string();
    assert!(
        msg.contains("tau_s") && msg.contains("7 is out of range") && msg.contains("≤ 2 s"),
        "{msg}"
    );
    let e = err(&WITH_EFFECTS.replace("tau_s = 0.3", "tau = 0.3"));
    let msg = e.to_string();
    assert!(
        msg.contains("unknown parameter `tau`") && msg.contains("did you mean `tau_s`"),
        "{msg}"
    );
    let e = err(&WITH_EFFECTS.replace(", vy_m_s = 0.0", ""));
    assert!(e.to_string().contains("needs parameter `vy_m_s`"), "{e}");
}

#[test]
fn a_model_with_effects_round_trips_through_vehicle_world_toml() {
    let w = load_str(WITH_EFFECTS, Path::new("fx.toml")).unwrap();
    let m = &w.vehicles[0].model;
    let mut spec = VehicleSpec::from_params(&shoal_model::presets::uauv2());
    spec.effects = VehicleSpec::effect_specs(m.effects.list(), &spec.to_params());
    let text = vehicle_world_toml(&spec, [2.0, 2.0, 1.0]).unwrap();
    let again = load_str(&text, Path::new("again.toml")).unwrap();
    assert_eq!(again.vehicles[0].model.effects, m.effects);
    assert_eq!(again.vehicles[0].model.params, m.params);
}

#[test]
fn every_unknown_field_and_bad_number_is_reported_at_once() {
    // Two typos (lines 2 and 7) and a negative time step (line 3): one error names all three,
    // in file order, each with its line, field and suggestion or allowed range.
    let text = "seed = 1\ndurration = 5.0\ndt = -0.01\n[pool]\nsize = [4.0, 4.0, 2.0]\n\
                [[vehicles]]\npositon = [1.0, 1.0, 0.5]\nposition = [1.0, 1.0, 0.5]\n";
    let e = err(text);
    let lines: Vec<Option<usize>> = e.problems.iter().map(|p| p.line_col.map(|l| l.0)).collect();
    assert_eq!(lines, [Some(2), Some(3), Some(7)], "{e}");
    let kinds: Vec<ProblemKind> = e.problems.iter().map(|p| p.kind).collect();
    assert_eq!(
        kinds,
        [
            ProblemKind::UnknownField,
            ProblemKind::Range,
            ProblemKind::UnknownField
        ],
        "{e}"
    );
    let msg = e.to_string();
    for part in [
        "bad.toml:2:",
        "did you mean `duration`",
        "bad.toml:3:",
        "allowed",
        "bad.toml:7:",
        "`positon`",
        "did you mean `position`",
    ] {
        assert!(msg.contains(part), "`{part}` missing in:\n{msg}");
    }
}
