//! A world from world-file text, for tests that build their scenes inline.

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
