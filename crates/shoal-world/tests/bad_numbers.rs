//! Numbers that used to get past the loader: a negative, −0 or NaN obstacle dimension (which
//! panicked inside parry because the shape was built before the check), subnormal or absurdly
//! small parameters (NaN trajectories with exit 0), and problems that carried no location
//! (invalid UTF-8, a recursion limit, `dt = 1e-300`). Each now gives a located problem naming
//! the field, the value and the allowed range. Also: the docs' range table is the table the
//! checks use.

use shoal_world::error::ProblemKind;
use shoal_world::load::ranges;
use shoal_world::load::{load_file, load_str};
use shoal_world::prelude::*;
use std::path::Path;

fn err(text: &str) -> WorldError {
    match std::panic::catch_unwind(|| load_str(text, Path::new("bad.toml"))) {
        Ok(Ok(_)) => panic!("expected an error for:\n{text}"),
        Ok(Err(e)) => e,
        Err(_) => panic!("the loader panicked on:\n{text}"),
    }
}

/// Asserts one located range problem at `field` (line `line`) whose message has `parts`.
fn assert_range(e: &WorldError, field: &str, line: usize, parts: &[&str]) {
    let p = e
        .problems
        .iter()
        .find(|p| p.field.as_ref().map(|f| f.to_string()).as_deref() == Some(field))
        .unwrap_or_else(|| panic!("no problem at `{field}`: {e}"));
    assert_eq!(p.kind, ProblemKind::Range, "{e}");
    assert_eq!(p.line_col.map(|l| l.0), Some(line), "{e}");
    let msg = e.to_string();
    for part in parts {
        assert!(msg.contains(part), "`{part}` missing in: {msg}");
    }
}

const POOL: &str = "[pool]\nsize = [4.0, 4.0, 2.0]\n";

fn obstacle(shape: &str, dims: &str) -> String {
    format!(
        "{POOL}[[obstacles]]\nshape = \"{shape}\"\n{dims}\nposition = [2.0, 2.0, 1.0]\n\
         [[vehicles]]\nposition = [0.5, 0.5, 0.5]\n"
    )
}

#[test]
fn bad_obstacle_dimensions_are_located_range_problems_not_panics() {
    for shape in ["cylinder", "capsule"] {
        for (radius, height, bad, value) in [
            ("-0.1", "1.0", "radius", "-0.1 is out of range"),
            ("-0.0", "1.0", "radius", "0 is out of range"),
            ("nan", "1.0", "radius", "NaN is not a finite number"),
            ("0.1", "-2.0", "height", "-2 is out of range"),
            ("0.1", "-0.0", "height", "0 is out of range"),
            ("0.1", "nan", "height", "NaN is not a finite number"),
            ("0.1", "inf", "height", "inf is not a finite number"),
        ] {
            let text = obstacle(shape, &format!("radius = {radius}\nheight = {height}"));
            let e = err(&text);
            let line = if bad == "radius" { 5 } else { 6 };
            assert_range(
                &e,
                &format!("obstacles[0].{bad}"),
                line,
                &[value, &format!("0.001 ≤ {bad} ≤ 1e4 m")],
            );
        }
    }
    let e = err(&obstacle("sphere", "radius = -1.0"));
    assert_range(&e, "obstacles[0].radius", 5, &["-1 is out of range"]);
    let e = err(&obstacle("box", "size = [1.0, -0.0, 1.0]"));
    assert_range(&e, "obstacles[0].size[1]", 5, &["0 is out of range"]);
}

const ONE: &str = "[pool]\nsize = [4.0, 4.0, 2.0]\n[[vehicles]]\nposition = [1.0, 1.0, 0.5]\n";

#[test]
fn subnormal_and_tiny_parameters_are_refused() {
    // A subnormal inertia (it gave NaN trajectories and exit 0).
    let e = err(&format!(
        "{ONE}[vehicles.model.body]\ninertia = [1e-310, 0.01, 0.01]\n"
    ));
    assert_range(
        &e,
        "vehicles[0].model.body.inertia[0]",
        6,
        &["subnormal", "1e-9 ≤ inertia ≤ 1e5 kg·m²"],
    );
    // A tiny but normal one is no vehicle either.
    let e = err(&format!(
        "{ONE}[vehicles.model.body]\ninertia = [1e-300, 0.01, 0.01]\n"
    ));
    assert_range(
        &e,
        "vehicles[0].model.body.inertia[0]",
        6,
        &["1e-300 is out of range"],
    );
    // The diagonal of a full inertia matrix has the same lower limit.
    let e = err(&format!(
        "{ONE}[vehicles.model.body]\ninertia = [[1e-12, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]]\n"
    ));
    assert_range(
        &e,
        "vehicles[0].model.body.inertia[0][0]",
        6,
        &["1e-12 is out of range", "1e-9 ≤ inertia ≤ 1e5"],
    );
    // A thrust coefficient of 5e-324 (the smallest subnormal).
    let e = err(&format!(
        "{ONE}[[vehicles.model.thrusters]]\nname = \"x\"\nposition = [0.0, 0.0, 0.0]\n\
         direction = [1.0, 0.0, 0.0]\ncurve = {{ kind = \"quadratic\", ct_pos = 5e-324, ct_neg = 0.001 }}\n\
         max_command = 100.0\nlag = 0.0\n"
    ));
    assert!(
        e.to_string().contains("ct_pos") && e.to_string().contains("subnormal"),
        "{e}"
    );
    // A coefficient that may be 0 (off) but not almost 0: the thruster lag.
    let e = err(&format!(
        "{ONE}[vehicles.model]\nthrusters = [{{ name = \"top\", position = [0.0, 0.0, 0.0], \
         direction = [1.0, 0.0, 0.0], curve = {{ kind = \"quadratic\", ct_pos = 0.001, ct_neg = 0.001 }}, \
         max_command = 100.0, lag = 1e-9 }}]\n"
    ));
    assert!(
        e.to_string()
            .contains("too small to be physical (0 switches it off)")
            && e.to_string().contains("lag = 0 or 1e-4 ≤ lag ≤ 100 s"),
        "{e}"
    );
}

#[test]
fn a_tiny_time_step_is_located_at_dt() {
    let e = err(&format!("dt = 1e-300\n{ONE}"));
    assert_range(
        &e,
        "dt",
        1,
        &["1e-300 is out of range", "1e-6 ≤ dt ≤ 0.1 s"],
    );
    // Within its range, but too many steps for the duration: still located, at dt.
    let e = err(&format!("duration = 1e7\ndt = 1e-6\n{ONE}"));
    let p = e.first();
    assert_eq!(p.field.as_ref().unwrap().to_string(), "dt");
    assert_eq!(p.line_col.map(|l| l.0), Some(2));
    assert!(e.to_string().contains("1e13 steps, more than 1e10"), "{e}");
}

#[test]
fn invalid_utf8_is_located() {
    let dir = std::env::temp_dir().join(format!("shoal-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    let mut bytes = b"seed = 1\nname = \"ab".to_vec();
    bytes.extend_from_slice(&[0xff, 0xfe]);
    bytes.extend_from_slice(b"\"\n");
    std::fs::write(&path, &bytes).unwrap();
    let e = load_file(&path).unwrap_err();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(e.first().kind, ProblemKind::Io);
    assert_eq!(e.first().line_col, Some((2, 11)), "{e}");
    assert!(e.to_string().contains("bad.toml:2:11"), "{e}");
    assert!(e.to_string().contains("not UTF-8"), "{e}");
}

#[test]
fn deep_nesting_is_a_located_problem() {
    let depth = 100_000;
    let text = format!("seed = {}1{}\n", "[".repeat(depth), "]".repeat(depth));
    let e = err(&text);
    assert!(e.first().line_col.is_some(), "no location: {e}");
    assert!(e.to_string().starts_with("bad.toml:1:"), "{e}");
}

#[test]
fn every_shipped_world_is_within_the_ranges() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            load_file(&p).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 3, "only {n} worlds found in {}", dir.display());
}

/// The "Allowed ranges" section of docs/world-files.md is printed from the table the checks
/// use. To update it after changing a range: `SHOAL_UPDATE_DOCS=1 cargo test -p shoal-world
/// --test bad_numbers`.
#[test]
fn docs_range_table_is_the_checked_table() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/world-files.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let (begin, end) = ("<!-- ranges:begin -->\n", "<!-- ranges:end -->");
    let (Some(a), Some(b)) = (doc.find(begin), doc.find(end)) else {
        panic!("docs/world-files.md has no {begin:?} … {end:?} section");
    };
    let want = ranges::markdown();
    let have = &doc[a + begin.len()..b];
    if have != want {
        if std::env::var_os("SHOAL_UPDATE_DOCS").is_some() {
            let new = format!("{}{want}{}", &doc[..a + begin.len()], &doc[b..]);
            std::fs::write(&path, new).unwrap();
        } else {
            panic!(
                "docs/world-files.md's range table differs from shoal_world::load::ranges; \
                 run `SHOAL_UPDATE_DOCS=1 cargo test -p shoal-world --test bad_numbers`"
            );
        }
    }
}

#[test]
fn a_count_this_machine_cannot_hold_is_refused_before_placement() {
    use shoal_world::load::{MemoryBudget, load_str_with};
    let text = "[pool]\nsize = [100.0, 100.0, 3.0]\n[[vehicles]]\nname = \"small\"\n\
                position = [1.0, 1.0, 1.0]\n[[vehicles]]\nname = \"swarm\"\ncount = 5000000\n\
                grid = { origin = [1.0, 1.0, 1.0], spacing = [0.5, 0.5], columns = 100 }\n";
    let budget = MemoryBudget {
        available_bytes: 8_000_000_000,
        bytes_per_vehicle: 4096,
        extra_bytes_per_sender: 0,
    };
    // 5 000 001 vehicles × 4 KB = 20.5 GB > 8 GB: refused at the large group's count, with the
    // estimate and what fits. Placing them would take seconds; the refusal is immediate
    // because nothing is placed (the grid would not even fit the pool).
    let e = load_str_with(text, Path::new("big.toml"), Some(&budget)).unwrap_err();
    assert_eq!(e.problems.len(), 1, "{e}");
    let p = e.first();
    assert_eq!(p.kind, ProblemKind::Range);
    assert_eq!(p.field.as_ref().unwrap().to_string(), "vehicles[1].count");
    assert_eq!(p.line_col.map(|l| l.0), Some(8));
    let msg = e.to_string();
    assert!(
        msg.contains("5000001 vehicles need about 20.5 GB (≈ 4.0 KB each, estimated)")
            && msg
                .contains("this machine has 8.0 GB available: at most about 1953125 vehicles fit"),
        "{msg}"
    );
    // The same world within the budget gets past the estimate (and fails on placement: the
    // grid leaves the 100 m pool).
    let budget = MemoryBudget {
        available_bytes: 30_000_000_000,
        bytes_per_vehicle: 4096,
        extra_bytes_per_sender: 0,
    };
    let e = load_str_with(text, Path::new("big.toml"), Some(&budget)).unwrap_err();
    assert!(e.has(ProblemKind::Outside), "{e}");
    assert!(!e.to_string().contains("need about"), "{e}");
}

#[test]
fn vehicles_that_transmit_count_their_receivers_link_tables_in_the_estimate() {
    use shoal_world::load::{MemoryBudget, load_str_with};
    let world = |behaviour: &str| {
        format!(
            "[pool]\nsize = [100.0, 100.0, 3.0]\n[[vehicles]]\nname = \"swarm\"\ncount = 700000\n\
             grid = {{ origin = [1.0, 1.0, 1.0], spacing = [0.5, 0.5], columns = 100 }}\n{behaviour}"
        )
    };
    let budget = MemoryBudget {
        available_bytes: 8_000_000_000,
        bytes_per_vehicle: 4096,
        extra_bytes_per_sender: 8192,
    };
    // Quiet: 700 000 × 4 KB = 2.9 GB fits (the load then fails on placement, not memory).
    let e = load_str_with(&world(""), Path::new("quiet.toml"), Some(&budget)).unwrap_err();
    assert!(!e.to_string().contains("need about"), "{e}");
    // Beaconing: 700 000 × 12 KB = 8.6 GB does not.
    let beacons = "behaviour = { kind = \"beacon\", period = 1.0, payload_bytes = 8 }\n";
    let e = load_str_with(&world(beacons), Path::new("loud.toml"), Some(&budget)).unwrap_err();
    let msg = e.to_string();
    assert_eq!(e.problems.len(), 1, "{e}");
    assert!(
        msg.contains("700000 vehicles need about 8.6 GB (≈ 12.0 KB each, estimated)")
            && msg.contains("at most about 651041 vehicles fit"),
        "{msg}"
    );
}
