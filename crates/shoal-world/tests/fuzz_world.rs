//! Fuzzing the world loader at the text level: arbitrary bytes, and "TOML soup" — keys of the
//! world-file schema, numbers including the nasty ones (NaN, ±inf, −0, subnormals, 1e308),
//! brackets, quotes and newlines in random order. Every input must be answered with a world
//! or with problems, never a panic, and every problem must say where it is (a field path or
//! a line). Structure-aware mutation of the shipped worlds, with a few simulation steps on
//! every accepted world, is in `crates/shoal-sim/tests/fuzz_worlds.rs`.
//!
//! `cargo test` runs 256 cases per property; a long run:
//! `PROPTEST_CASES=1000000 cargo test --release -p shoal-world --test fuzz_world`.
//! The loader is linear in the text and bounded by the memory estimate, so every case ends;
//! no wall-clock bound is asserted here.

use proptest::prelude::*;
use shoal_world::load::{MemoryBudget, load_str_with};
use std::path::Path;

/// A budget that refuses large counts at once (the fuzzer's inputs must stay cheap).
const BUDGET: MemoryBudget = MemoryBudget {
    available_bytes: 64 << 20,
    bytes_per_vehicle: 16 << 10,
    extra_bytes_per_sender: 0,
};

fn load(text: &str) {
    let r = std::panic::catch_unwind(|| load_str_with(text, Path::new("fuzz.toml"), Some(&BUDGET)));
    match r {
        Err(_) => panic!("the loader panicked on:\n{text}"),
        Ok(Ok(w)) => {
            // What is accepted is within its ranges: a usable step, vehicles in the pool.
            assert!((1e-6..=0.1).contains(&w.dt), "dt {}", w.dt);
            let pool = w.geometry.pool;
            for v in &w.vehicles {
                let p = v.position;
                assert!(
                    (0.0..=pool.x).contains(&p.x)
                        && (0.0..=pool.y).contains(&p.y)
                        && (0.0..=pool.z).contains(&p.z),
                    "{} at {p:?} outside the pool {pool:?}",
                    v.name
                );
                assert!(v.model.params.body.mass >= 1e-3);
            }
        }
        Ok(Err(e)) => {
            assert!(!e.problems.is_empty(), "an error without problems:\n{text}");
            for p in &e.problems {
                assert!(
                    p.field.is_some() || p.line_col.is_some(),
                    "a problem without a location: {p:?}\n{text}"
                );
            }
            let _ = e.to_string();
        }
    }
}

const KEYS: &[&str] = &[
    "name",
    "seed",
    "duration",
    "dt",
    "integrator",
    "[pool]",
    "size",
    "[water]",
    "density",
    "attenuation",
    "current",
    "[[obstacles]]",
    "shape",
    "radius",
    "height",
    "position",
    "rotation_deg",
    "[[vehicles]]",
    "count",
    "grid",
    "origin",
    "spacing",
    "columns",
    "random",
    "min",
    "max",
    "heading_deg",
    "mission",
    "t",
    "depth",
    "yaw_deg",
    "mode",
    "[vehicles.model]",
    "[vehicles.model.body]",
    "mass",
    "inertia",
    "volume",
    "hull_size",
    "[[vehicles.model.modems]]",
    "led_power",
    "bit_rate",
    "[vehicles.behaviour]",
    "kind",
    "period",
    "[output]",
    "record_hz",
    "[agents]",
    "timeout",
    "preset",
];
const ATOMS: &[&str] = &[
    "=",
    " = ",
    "\n",
    "[",
    "]",
    "{",
    "}",
    ",",
    "\"",
    "'",
    "#",
    ".",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "-0.0",
    "0",
    "1",
    "-1",
    "5e-324",
    "1e-310",
    "1e308",
    "-1e308",
    "1e7",
    "10000000",
    "9223372036854775807",
    "0.5",
    "3.0",
    "\"cylinder\"",
    "\"box\"",
    "\"uauv2\"",
    "\"gossip\"",
    "\"diving\"",
    "true",
    "[1.0, 2.0, 0.5]",
    "[0.0, 0.0]",
    "[]",
    "{}",
];

fn soup() -> impl Strategy<Value = String> {
    let tok = prop_oneof![
        3 => prop::sample::select(KEYS).prop_map(str::to_string),
        4 => prop::sample::select(ATOMS).prop_map(str::to_string),
        1 => "[a-z_]{1,8}",
    ];
    prop::collection::vec(tok, 0..80).prop_map(|v| v.concat())
}

/// Lines `key = value` under random tables: mostly valid TOML, so the checks behind the
/// parser are reached.
fn lines() -> impl Strategy<Value = String> {
    let tables: Vec<&str> = KEYS
        .iter()
        .copied()
        .filter(|k| k.starts_with('['))
        .collect();
    let keys: Vec<&str> = KEYS
        .iter()
        .copied()
        .filter(|k| !k.starts_with('['))
        .collect();
    let values: Vec<&str> = ATOMS
        .iter()
        .copied()
        .filter(|a| {
            !matches!(
                *a,
                "=" | " = " | "\n" | "[" | "]" | "{" | "}" | "," | "\"" | "'" | "#" | "."
            )
        })
        .collect();
    let line = prop_oneof![
        1 => prop::sample::select(tables).prop_map(|k| format!("{k}\n")),
        4 => (prop::sample::select(keys), prop::sample::select(values))
            .prop_map(|(k, v)| format!("{k} = {v}\n")),
    ];
    prop::collection::vec(line, 0..40).prop_map(|v| v.concat())
}

proptest! {
    #[test]
    fn arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..2000)) {
        load(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn toml_soup(text in soup()) {
        load(&text);
    }

    #[test]
    fn plausible_lines(text in lines()) {
        load(&text);
    }
}
