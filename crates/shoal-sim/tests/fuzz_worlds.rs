//! Structure-aware fuzzing of world files: every shipped world, parsed, mutated (a number or
//! string replaced by a nasty value — NaN, ±inf, −0, a subnormal, 1e±308, a huge count, a
//! wrong type —, a key deleted, an unknown key added, an array element duplicated), written
//! back and loaded. A world the loader refuses must say where; a world it accepts is built
//! and stepped: no panic, and every vehicle's state stays finite or the run reports which one
//! stopped being finite ([`Sim::fault`]). Of ~20 000 such files the loader once panicked on 25
//! and let NaN trajectories through on others.
//!
//! `cargo test` runs 256 cases; a long run:
//! `PROPTEST_CASES=1000000 cargo test --release -p shoal-sim --test fuzz_worlds`.

use proptest::prelude::*;
use shoal_sim::prelude::*;
use shoal_world::load::{MemoryBudget, load_str_with};
use std::path::Path;

/// Small enough that a mutated count is refused at once instead of placing millions.
const BUDGET: MemoryBudget = MemoryBudget {
    available_bytes: 64 << 20,
    bytes_per_vehicle: 16 << 10,
    extra_bytes_per_sender: 0,
};

fn worlds() -> &'static [(String, toml::Table)] {
    static W: std::sync::OnceLock<Vec<(String, toml::Table)>> = std::sync::OnceLock::new();
    W.get_or_init(read_worlds)
}

fn read_worlds() -> Vec<(String, toml::Table)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../worlds");
    let mut out = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            out.push((p.display().to_string(), toml::from_str(&text).unwrap()));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(out.len() >= 5);
    out
}

/// Paths to every value of a table (keys and array indices).
fn leaves(v: &toml::Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                path.push(Step::Key(k.clone()));
                out.push(path.clone());
                leaves(x, path, out);
                path.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Step::Index(i));
                out.push(path.clone());
                leaves(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn at<'a>(v: &'a mut toml::Value, path: &[Step]) -> Option<&'a mut toml::Value> {
    let mut cur = v;
    for s in path {
        cur = match (s, cur) {
            (Step::Key(k), toml::Value::Table(t)) => t.get_mut(k)?,
            (Step::Index(i), toml::Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn nasty(i: usize) -> toml::Value {
    use toml::Value::*;
    let all = [
        Float(f64::NAN),
        Float(f64::INFINITY),
        Float(f64::NEG_INFINITY),
        Float(-0.0),
        Float(5e-324),
        Float(1e-310),
        Float(1e-300),
        Float(1e308),
        Float(-1e308),
        Float(0.0),
        Float(-1.0),
        Float(1e9),
        Integer(0),
        Integer(-1),
        Integer(10_000_000),
        Integer(i64::MAX),
        String("x".into()),
        String(std::string::String::new()),
        Boolean(true),
        Array(vec![]),
        Array(vec![Float(1.0); 7]),
        Table(toml::Table::new()),
    ];
    all[i % all.len()].clone()
}

#[derive(Clone, Debug)]
enum Mutation {
    Replace(usize, usize),
    Scale(usize, f64),
    Delete(usize),
    Unknown(usize),
    Duplicate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<usize>()).prop_map(|(p, v)| Mutation::Replace(p, v)),
        2 => (any::<usize>(), prop::sample::select(vec![-1.0, 0.0, 1e-9, 1e-3, 10.0, 1e6, 1e12]))
            .prop_map(|(p, f)| Mutation::Scale(p, f)),
        1 => any::<usize>().prop_map(Mutation::Delete),
        1 => any::<usize>().prop_map(Mutation::Unknown),
        1 => any::<usize>().prop_map(Mutation::Duplicate),
    ]
}

fn apply(root: &mut toml::Value, m: &Mutation) {
    let mut paths = Vec::new();
    leaves(root, &mut Vec::new(), &mut paths);
    if paths.is_empty() {
        return;
    }
    let pick = |i: usize| paths[i % paths.len()].clone();
    match m {
        Mutation::Replace(p, v) => {
            if let Some(x) = at(root, &pick(*p)) {
                *x = nasty(*v);
            }
        }
        Mutation::Scale(p, f) => {
            if let Some(x) = at(root, &pick(*p)) {
                let scaled = match &*x {
                    toml::Value::Float(y) => Some(y * f),
                    toml::Value::Integer(y) => Some(*y as f64 * f),
                    _ => None,
                };
                if let Some(y) = scaled {
                    *x = toml::Value::Float(y);
                }
            }
        }
        Mutation::Delete(p) | Mutation::Unknown(p) | Mutation::Duplicate(p) => {
            let path = pick(*p);
            let (last, parent) = path.split_last().expect("non-empty path");
            let Some(parent) = at(root, parent) else {
                return;
            };
            match (m, last, parent) {
                (Mutation::Delete(_), Step::Key(k), toml::Value::Table(t)) => {
                    t.remove(k);
                }
                (Mutation::Delete(_), Step::Index(i), toml::Value::Array(a)) => {
                    a.remove(*i);
                }
                (Mutation::Unknown(_), Step::Key(k), toml::Value::Table(t)) => {
                    t.insert(format!("{k}x"), toml::Value::Float(1.0));
                }
                (Mutation::Duplicate(_), Step::Index(i), toml::Value::Array(a)) => {
                    let x = a[*i].clone();
                    a.push(x);
                }
                _ => {}
            }
        }
    }
}

fn check(text: &str) {
    let loaded =
        std::panic::catch_unwind(|| load_str_with(text, Path::new("fuzz.toml"), Some(&BUDGET)));
    let desc = match loaded {
        Err(_) => panic!("the loader panicked on:\n{text}"),
        Ok(Err(e)) => {
            for p in &e.problems {
                assert!(
                    p.field.is_some() || p.line_col.is_some(),
                    "a problem without a location: {p:?}\n{text}"
                );
            }
            return;
        }
        Ok(Ok(d)) => d,
    };
    let stepped = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut sim = Sim::new(
            &desc,
            SimOptions {
                threads: 1,
                ..SimOptions::default()
            },
        );
        sim.run(20);
        let finite = sim.vehicles().iter().all(|v| v.state.rigid.is_finite());
        (sim.fault().is_some(), finite)
    }));
    match stepped {
        Err(_) => panic!("the simulation panicked on an accepted world:\n{text}"),
        Ok((_, finite)) => assert!(finite, "a non-finite state got through:\n{text}"),
    }
}

proptest! {
    #[test]
    fn mutated_shipped_worlds(world in any::<usize>(), ms in prop::collection::vec(mutation(), 1..4)) {
        let all = worlds();
        let (_, table) = &all[world % all.len()];
        let mut root = toml::Value::Table(table.clone());
        for m in &ms {
            apply(&mut root, m);
        }
        let text = match toml::to_string(&root) {
            Ok(t) => t,
            // A mutation TOML cannot write (e.g. a table in an array of numbers).
            Err(_) => return Ok(()),
        };
        check(&text);
    }
}
