//! The rosbag2 reader on broken input: a bag of the kit (`common/bagkit.rs`) cut short,
//! with bytes flipped or a stretch overwritten — every case is a run or an error, never a
//! panic, an abort or a hang. (What the intact bag reads back: `read_back.rs`; mutated message
//! bodies and schemas: `fuzz_messages.rs`.) (CI runs the default 64 cases per property; a long
//! campaign: `PROPTEST_CASES=20000 cargo test --release -p shoal-rosbag --test fuzz_bag`.)

mod common;

use common::bagkit;
use proptest::prelude::*;
use shoal_rosbag::{Mapping, read_bag};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn kit() -> &'static [u8] {
    static BAG: OnceLock<Vec<u8>> = OnceLock::new();
    BAG.get_or_init(|| bagkit::bag(3))
}

fn mapping() -> Mapping {
    Mapping::parse(bagkit::MAPPING, Path::new("kit.toml")).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shoal-fuzz-bag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Reads `bytes` as a bag; a run must be a sane one.
fn read_bytes(bytes: &[u8], name: &str) -> Result<(), String> {
    let path = scratch(name);
    std::fs::write(&path, bytes).unwrap();
    match read_bag(&path, &mapping()) {
        Ok(run) => {
            assert!(run.t.windows(2).all(|w| w[1] > w[0]), "times increase");
            assert!(
                run.channels
                    .iter()
                    .all(|c| c.values.iter().all(|v| v.is_finite()))
            );
            Ok(())
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with(&path.display().to_string()), "{msg}");
            Err(msg)
        }
    }
}

proptest! {
    #[test]
    fn a_cut_bag_is_an_error_or_a_shorter_run(cut in 0usize..60_000) {
        let bytes = kit();
        let cut = cut.min(bytes.len());
        let _ = read_bytes(&bytes[..cut], "cut.mcap");
    }

    #[test]
    fn flipped_bytes_never_panic(flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8)) {
        let mut bytes = kit().to_vec();
        for (at, v) in flips {
            let i = at.index(bytes.len());
            bytes[i] ^= v | 1;
        }
        let _ = read_bytes(&bytes, "flipped.mcap");
    }
}
