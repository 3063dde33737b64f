//! The rosbag2 reader on broken input: a bag of the kit (`common/bagkit.rs`) cut short,
//! with bytes flipped or a stretch overwritten, and message bodies of random bytes — every
//! case is a run or an error, never a panic, an abort or a hang; and the intact bag reads back
//! the values written into it. (CI runs the default 64 cases per property; a long campaign:
//! `PROPTEST_CASES=20000 cargo test --release -p shoal-rosbag --test fuzz_bag`.)

mod common;

use common::bagkit;
use proptest::prelude::*;
use shoal_rosbag::decode::decode;
use shoal_rosbag::schema::Schema;
use shoal_rosbag::select::Plan;
use shoal_rosbag::{Mapping, read_bag};
use shoal_sysid::log::run::ChannelKind;
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

#[test]
fn the_intact_kit_bag_reads_back_what_was_written() {
    let path = scratch("intact.mcap");
    std::fs::write(&path, kit()).unwrap();
    let run = read_bag(&path, &mapping()).unwrap();
    // The run starts at the last input topic's first message: the pump's, 1 ms + jitter in.
    let depth = run.channel(ChannelKind::Depth).unwrap();
    assert!(depth.values.len() >= 3 * 40 - 1, "{}", depth.values.len());
    let yaw = run.channel(ChannelKind::Yaw).unwrap();
    let r = run.channel(ChannelKind::R).unwrap();
    for (k, &row) in yaw.rows.iter().enumerate().step_by(37) {
        // Times in the run count from its start; the kit's signals from the bag's zero.
        let t0_bag = 1e-9 * (1_000_000.0 + jitter_of_pump());
        let t = run.t[row] + t0_bag;
        let yaw_enu = 0.3 * (0.2 * t).sin();
        // Stamps jitter by < 0.4 ms: the signal moves by < 0.06 rad/s · 0.4 ms.
        let want = std::f64::consts::FRAC_PI_2 - yaw_enu;
        assert!(
            (yaw.values[k] - want).abs() < 2e-3,
            "t {t}: {} vs {want}",
            yaw.values[k]
        );
        assert!(
            (r.values[k] + 0.06 * (0.2 * t).cos()).abs() < 1e-4,
            "FLU z → FRD r"
        );
    }
    for (k, &row) in depth.rows.iter().enumerate().step_by(11) {
        let t = run.t[row] + 1e-9 * (1_000_000.0 + jitter_of_pump());
        let want = 1.0 + 0.5 * (0.1 * t).sin();
        assert!(
            (depth.values[k] - want).abs() < 1e-4,
            "depth at {t}: {}",
            depth.values[k]
        );
    }
    let top = run.input("top").unwrap();
    assert!(top.values.iter().all(|v| v.abs() <= 30.0));
}

/// The kit's first pump message's jitter \[ns\] (topic 4, k = 0).
fn jitter_of_pump() -> f64 {
    ((4u64 * 104_729) % 400_000) as f64
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

    #[test]
    fn random_message_bodies_never_panic(body in proptest::collection::vec(any::<u8>(), 0..400), le in any::<bool>()) {
        let text = shoal_record::mcap::definition("sensor_msgs/msg/Imu").unwrap();
        let schema = Schema::parse("sensor_msgs/msg/Imu", &text).unwrap();
        let mut plan = Plan::new();
        plan.add(&schema, "orientation").unwrap();
        plan.add(&schema, "angular_velocity.z").unwrap();
        let mut data = vec![0u8, u8::from(le), 0, 0];
        data.extend_from_slice(&body);
        let mut out = vec![f64::NAN; plan.slots];
        let _ = decode(&schema, &plan.sel, &data, &mut out);
    }

    #[test]
    fn random_schemas_never_panic(text in "[a-z0-9_/\\[\\]<=# \n]{0,200}") {
        let _ = Schema::parse("pkg/msg/T", &text);
    }
}
