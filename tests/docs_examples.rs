//! The world-file examples in README.md must load: documentation cannot drift from the format.

use shoal::world::load::load_str;
use std::path::Path;

#[test]
fn readme_world_example_loads() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let blocks: Vec<&str> = readme
        .split("```toml")
        .skip(1)
        .map(|b| b.split("```").next().unwrap())
        .collect();
    assert!(!blocks.is_empty(), "README has a TOML example");
    for b in blocks {
        let w = load_str(b, Path::new("README.md")).unwrap_or_else(|e| panic!("{e}\n{b}"));
        assert!(!w.vehicles.is_empty());
        // An example must not teach a mistake the loader warns about (e.g. vehicles that sink).
        assert!(w.warnings.is_empty(), "{:?}\n{b}", w.warnings);
    }
}
