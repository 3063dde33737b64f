//! The mapping files shipped in `examples/rosbag2/` are valid and say what their comments say.

use shoal_rosbag::Mapping;
use shoal_rosbag::mapping::{Clock, Feeds, Frame};
use shoal_sysid::log::run::ChannelKind;
use std::path::Path;

fn shipped(name: &str) -> Mapping {
    let p = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/rosbag2"
    ))
    .join(name);
    Mapping::read(&p).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_uauv2_run_mapping_reads_a_runs_own_topics() {
    let m = shipped("uauv2_run.toml");
    assert_eq!(
        m.topics(),
        [
            "/uauv2/pressure",
            "/uauv2/pump",
            "/uauv2/thrusters",
            "/uauv2/tilts"
        ]
    );
    let inputs: Vec<&str> = m
        .entries
        .iter()
        .filter(|e| e.feeds == Feeds::Input)
        .map(|e| e.key.as_str())
        .collect();
    assert_eq!(
        inputs,
        ["u.alpha", "u.beta", "u.port", "u.pump", "u.stbd", "u.top"]
    );
    let depth = m
        .entries
        .iter()
        .find(|e| e.feeds == Feeds::Channel(ChannelKind::Depth))
        .unwrap();
    // 1 m of fresh water under the standard atmosphere: 101 325 + 1000 · 9.81 Pa.
    assert!((depth.scale * 111_135.0 + depth.offset - 1.0).abs() < 1e-12);
}

#[test]
fn the_bluerov_mapping_reads_pwm_and_an_enu_imu() {
    let m = shipped("bluerov_mavros.toml");
    let t1 = m.entries.iter().find(|e| e.key == "u.t1").unwrap();
    // ArduSub's pulse widths: 1900 µs full ahead, 1500 µs stopped, 1100 µs full astern.
    for (pwm, pct) in [(1900.0, 100.0), (1500.0, 0.0), (1100.0, -100.0)] {
        assert_eq!(pwm * t1.scale + t1.offset, pct);
    }
    assert!(
        m.entries
            .iter()
            .all(|e| e.frame == Frame::Enu && e.clock.is_none())
    );
    assert!(m.entries.iter().all(|e| e.clock != Some(Clock::Log)));
    assert_eq!(m.entries.len(), 13);
}
