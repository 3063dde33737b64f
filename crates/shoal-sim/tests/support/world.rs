//! A world from world-file text, for tests that build their scenes inline, or from a file of
//! `worlds/`.

use shoal_sim::prelude::*;
use shoal_world::load::load_str;
use std::path::Path;

/// The simulation of a world file's text on one thread, without recording (panics with the
/// loader's message and the text when it does not load).
pub fn world(text: &str) -> Sim {
    let desc = load_str(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}\n{text}"));
    Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    )
}

/// The world file `worlds/<name>.toml` run to its end on one thread without recording, with
/// the medium's statistics folded: its description and the simulation.
pub fn run_world_file(name: &str) -> (shoal_world::desc::WorldDesc, Sim) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../worlds/{name}.toml"));
    let desc = shoal_world::load::load_file(&path).unwrap();
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    sim.run(desc.steps());
    sim.fold_comm();
    (desc, sim)
}
