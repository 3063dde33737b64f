//! The kit's bag (`common/bagkit.rs`) read back through its mapping gives what the kit wrote,
//! computed here by hand from the kit's truth, not by the reader's code:
//!
//! * the run's times: every mapped topic's times (header stamps for the IMU and the pressure,
//!   log times for the arrays, which have no header) from the last input's first message on —
//!   the pump's, half a second after the others — counted from that message; every earlier
//!   sample dropped;
//! * the channels, each at its own messages' times: depth from absolute pressure
//!   ((p − 101 325 Pa)/(1000 kg/m³ · 9.806 65 m/s²)); roll, pitch, yaw from an ENU/FLU
//!   quaternion by REP 103 (roll = roll_ENU, pitch = −pitch_ENU, yaw = π/2 − yaw_ENU), with all
//!   three angles clearly away from zero so that a lost sign or a swapped axis shows; p, q, r
//!   from FLU rates (p, −q, −r);
//! * the inputs u.top, u.port, u.stbd, u.alpha, u.beta, u.pump: on every row, exactly the
//!   value of the topic's last message at or before it;
//! * references mapped in a `[references]` section (`r.depth` from the tilts, `r.mode` from a
//!   thruster command shifted into mode codes): held as the inputs are, and a reference whose
//!   topic starts late (the pump's, mapped as `r.surge` instead of `u.pump`) starts the run.

mod common;

use common::bagkit::{self, IMU, PRESSURE, PUMP, Sample, TOPICS};
use shoal_rosbag::{Mapping, read_bag};
use shoal_sysid::log::run::{ChannelKind, MeasuredRun, ReferenceKind};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

const SECONDS: u64 = 3;

/// The kit's bag read through the kit's mapping.
fn kit_run() -> MeasuredRun {
    kit_run_with(bagkit::MAPPING)
}

/// The kit's bag read through `mapping`.
fn kit_run_with(mapping: &str) -> MeasuredRun {
    let dir = std::env::temp_dir().join(format!("shoal-read-back-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("kit.mcap");
    std::fs::write(&path, bagkit::bag(SECONDS)).unwrap();
    let mapping = Mapping::parse(mapping, Path::new("kit.toml")).unwrap();
    read_bag(&path, &mapping).unwrap_or_else(|e| panic!("{e}"))
}

/// The time a reader places a sample at \[ns\]: its header stamp if its type has a header
/// (Imu, FluidPressure), else the bag's log time (Float64MultiArray).
fn reader_time(s: &Sample) -> u64 {
    if s.topic == IMU || s.topic == PRESSURE {
        s.stamp_ns
    } else {
        s.log_ns
    }
}

/// The mapped samples (every topic but camera_info) and the run's start: the latest first
/// time over the input topics (thrusters, tilts, pump).
fn mapped_and_start() -> (Vec<Sample>, u64) {
    let all: Vec<Sample> = bagkit::schedule(SECONDS)
        .into_iter()
        .filter(|s| s.topic != bagkit::CAMERA)
        .collect();
    let first = |i: usize| all.iter().filter(|s| s.topic == i).map(reader_time).min();
    let start = [bagkit::THRUSTERS, bagkit::TILTS, PUMP]
        .iter()
        .map(|&i| first(i).unwrap())
        .max()
        .unwrap();
    (all, start)
}

/// The run's rows: every mapped time from the start on, each once \[ns\].
fn rows(all: &[Sample], start: u64) -> Vec<u64> {
    let mut times: Vec<u64> = all
        .iter()
        .map(reader_time)
        .filter(|&t| t >= start)
        .collect();
    times.sort_unstable();
    times.dedup();
    times
}

fn seconds_after(ns: u64, start: u64) -> f64 {
    (ns - start) as f64 * 1e-9
}

#[test]
fn the_run_starts_at_the_late_inputs_first_message_and_drops_earlier_samples() {
    let run = kit_run();
    let (all, start) = mapped_and_start();
    // The kit's pump starts ≥ 0.3 s after every other topic: the rule is visible.
    let pump_first = all.iter().find(|s| s.topic == PUMP).unwrap();
    assert_eq!(
        start, pump_first.log_ns,
        "the pump is the last input to start"
    );
    for (i, (topic, _, _)) in TOPICS.iter().enumerate().take(PUMP) {
        let first = all.iter().find(|s| s.topic == i).unwrap();
        assert!(reader_time(first) + 300_000_000 <= start, "{topic}");
    }
    // Rows: the union of the mapped topics' times from the start on, counted from it.
    let times = rows(&all, start);
    assert_eq!(run.t.len(), times.len(), "rows");
    for (k, (&got, &ns)) in run.t.iter().zip(&times).enumerate() {
        let want = seconds_after(ns, start);
        assert!(
            (got - want).abs() < 1e-12,
            "row {k}: {got} s, want {want} s"
        );
    }
    assert_eq!(run.t[0], 0.0);
    // Depth: only the pressure messages from the start on; the ~20 before it are dropped.
    let kept: Vec<&Sample> = all
        .iter()
        .filter(|s| s.topic == PRESSURE && s.stamp_ns >= start)
        .collect();
    let dropped = all.iter().filter(|s| s.topic == PRESSURE).count() - kept.len();
    assert!(dropped >= 19, "{dropped} pressure samples before the start");
    let depth = run.channel(ChannelKind::Depth).unwrap();
    assert_eq!(depth.values.len(), kept.len());
    assert_eq!(
        run.t[depth.rows[0]],
        seconds_after(kept[0].stamp_ns, start),
        "the first depth sample is the first one at or after the pump's first message"
    );
}

/// The NED/FRD values a reader must give for an IMU sample, by REP 103's hand formulas from
/// the kit's ENU/FLU truth: roll, pitch, yaw, p, q, r.
fn imu_ned(stamp_ns: u64) -> [f64; 6] {
    let t = stamp_ns as f64 * 1e-9;
    let [roll, pitch, yaw] = bagkit::attitude_enu(t);
    let [p, q, r] = bagkit::rates_flu(t);
    let yaw_ned = (FRAC_PI_2 - yaw + PI).rem_euclid(2.0 * PI) - PI;
    [roll, -pitch, yaw_ned, p, -q, -r]
}

#[test]
fn every_channel_reads_back_the_kits_truth_in_neds_axes() {
    let run = kit_run();
    let (all, start) = mapped_and_start();
    let imu: Vec<&Sample> = all
        .iter()
        .filter(|s| s.topic == IMU && s.stamp_ns >= start)
        .collect();
    let kinds = [
        ChannelKind::Roll,
        ChannelKind::Pitch,
        ChannelKind::Yaw,
        ChannelKind::P,
        ChannelKind::Q,
        ChannelKind::R,
    ];
    for (j, kind) in kinds.into_iter().enumerate() {
        let ch = run.channel(kind).unwrap();
        assert_eq!(
            ch.values.len(),
            imu.len(),
            "{kind:?}: one value per IMU message"
        );
        for (k, s) in imu.iter().enumerate() {
            assert_eq!(run.t[ch.rows[k]], seconds_after(s.stamp_ns, start));
            let want = imu_ned(s.stamp_ns)[j];
            // The kit's angles and rates are ≥ 0.01 away from zero: a lost sign is ≥ 0.02 off.
            assert!(want.abs() >= 0.01, "{kind:?}: {want}");
            assert!(
                (ch.values[k] - want).abs() < 1e-9,
                "{kind:?} at {} ns: {} read, {want} expected from the kit",
                s.stamp_ns,
                ch.values[k]
            );
        }
    }
    let depth = run.channel(ChannelKind::Depth).unwrap();
    let pressure = all
        .iter()
        .filter(|s| s.topic == PRESSURE && s.stamp_ns >= start);
    for (k, s) in pressure.enumerate() {
        assert_eq!(run.t[depth.rows[k]], seconds_after(s.stamp_ns, start));
        let want = bagkit::depth_m(s.stamp_ns as f64 * 1e-9);
        assert!(
            (depth.values[k] - want).abs() < 1e-9,
            "depth at {} ns: {} read, {want} expected from the kit",
            s.stamp_ns,
            depth.values[k]
        );
    }
}

#[test]
fn every_input_holds_the_value_of_its_topics_last_message() {
    let run = kit_run();
    let (all, start) = mapped_and_start();
    let times = rows(&all, start);
    assert_eq!(run.t.len(), times.len(), "rows");
    let inputs = [
        ("top", bagkit::THRUSTERS, 0),
        ("port", bagkit::THRUSTERS, 1),
        ("stbd", bagkit::THRUSTERS, 2),
        ("alpha", bagkit::TILTS, 0),
        ("beta", bagkit::TILTS, 1),
        ("pump", PUMP, 0),
    ];
    for (name, topic, index) in inputs {
        let input = run.input(name).unwrap();
        assert_eq!(input.values.len(), run.t.len(), "u.{name}");
        let msgs: Vec<&Sample> = all.iter().filter(|s| s.topic == topic).collect();
        let mut distinct = Vec::new();
        for (row, &ns) in times.iter().enumerate() {
            // The topic's last message at or before the row.
            let last = msgs.iter().rfind(|s| s.log_ns <= ns).unwrap();
            let want = bagkit::array(topic, last.k, last.stamp_ns as f64 * 1e-9)[index];
            assert_eq!(
                input.values[row], want,
                "u.{name} at row {row} ({ns} ns): message {} of {}",
                last.k, TOPICS[topic].0
            );
            if !distinct.contains(&want) {
                distinct.push(want);
            }
        }
        // Every input takes several values, none of them only zero.
        assert!(distinct.len() >= 3, "u.{name}: {distinct:?}");
    }
}

/// The kit's mapping with references: `r.depth` = 2 × alpha + 1 \[m\] from the tilts,
/// `r.mode` = port command − 15 from the thrusters (20 − k mod 5 → codes 1 … 5).
const REFERENCES: &str = r#"
[references]
"r.depth" = { topic = "tilts", field = "data[0]", scale = 2.0, offset = 1.0 }
"r.mode"  = { topic = "thrusters", field = "data[1]", offset = -15.0 }
"#;

#[test]
fn references_hold_the_value_of_their_topics_last_message() {
    let run = kit_run_with(&format!("{}{REFERENCES}", bagkit::MAPPING));
    let (all, start) = mapped_and_start();
    let times = rows(&all, start);
    assert_eq!(run.t.len(), times.len(), "rows: the references add no time");
    let refs = [
        (ReferenceKind::Depth, bagkit::TILTS, 0, 2.0, 1.0),
        (ReferenceKind::Mode, bagkit::THRUSTERS, 1, 1.0, -15.0),
    ];
    assert_eq!(run.references.len(), refs.len());
    for (kind, topic, index, scale, offset) in refs {
        let r = run.reference(kind).unwrap();
        assert_eq!(r.values.len(), run.t.len(), "{kind:?}");
        assert_eq!(r.first_set, 0, "{kind:?}");
        let msgs: Vec<&Sample> = all.iter().filter(|s| s.topic == topic).collect();
        let mut distinct = Vec::new();
        for (row, &ns) in times.iter().enumerate() {
            let last = msgs.iter().rfind(|s| s.log_ns <= ns).unwrap();
            let raw = bagkit::array(topic, last.k, last.stamp_ns as f64 * 1e-9)[index];
            let want = scale * raw + offset;
            assert_eq!(r.values[row], want, "{kind:?} at row {row} ({ns} ns)");
            if !distinct.contains(&want) {
                distinct.push(want);
            }
        }
        assert!(distinct.len() >= 3, "{kind:?}: {distinct:?}");
    }
    // The modes are the codes 1 … 5, each of them taken.
    let mut modes = run.reference(ReferenceKind::Mode).unwrap().values.clone();
    modes.sort_by(f64::total_cmp);
    modes.dedup();
    assert_eq!(modes, [1.0, 2.0, 3.0, 4.0, 5.0]);
    // The inputs and channels are those of the mapping without references.
    let plain = kit_run();
    assert_eq!(run.inputs, plain.inputs);
    assert_eq!(run.channels, plain.channels);
}

#[test]
fn a_reference_whose_topic_starts_late_starts_the_run() {
    // The pump's topic (first message at 0.5 s) mapped as a reference instead of an input:
    // every input starts within a millisecond, so only the reference can hold the start back.
    let mapping = bagkit::MAPPING
        .replace(r#""u.pump"  = { topic = "pump", field = "data[0]" }"#, "")
        + "[references]\n\"r.surge\" = { topic = \"pump\", field = \"data[0]\", scale = 4.0 }\n";
    let run = kit_run_with(&mapping);
    assert!(run.input("pump").is_none());
    let (all, start) = mapped_and_start();
    let pump_first = all.iter().find(|s| s.topic == PUMP).unwrap();
    assert_eq!(start, pump_first.log_ns);
    assert_eq!(
        run.t.len(),
        rows(&all, start).len(),
        "rows from the pump's first message"
    );
    let surge = run.reference(ReferenceKind::Surge).unwrap();
    // The pump's first value, +1, times 4 [N].
    assert_eq!(surge.values[0], 4.0);
    assert_eq!(surge.first_set, 0);
}
