//! A small run written to `run.mcap` and read back with the `mcap` crate: the topics, their
//! schemas and encodings, message counts (recorded samples × vehicles, reception attempts),
//! times in order, the ROS 2 profile (every schema a `.msg` definition, every message CDR),
//! every message decoded back to the recorded values (attitudes against hand-computed body
//! axes on a heading that is not a symmetry of the NED↔ENU change), the size estimate of the budget,
//! thinning, and a folder that cannot be written.

use super::foxglove::SceneUpdate;
use super::plain::ReceptionAttempt;
use super::ros2::{self, Float64MultiArray, FluidPressure, Imu, TfMessage};
use super::*;
use crate::output::RunOutput;
use shoal_sim::recorder::FIXED;
use shoal_sim::sim::{Sim, SimOptions};
use shoal_world::cancel::Cancel;
use std::collections::BTreeMap;

/// Three μAUV² in a row heading 200° (south-south-west: a heading whose mirror −ψ, whose
/// swap of north and east and whose ENU angle π/2 − ψ all differ from it) with four modems
/// each, beaconing; a post in the pool.
const WORLD: &str = r#"
name = "mcap test"
seed = 7
duration = 2.0
dt = 0.01
[pool]
size = [6.0, 4.0, 2.0]
[[obstacles]]
name = "post"
shape = "cylinder"
radius = 0.2
height = 2.0
position = [4.5, 3.0, 1.0]
[[vehicles]]
name = "a"
count = 3
grid = { origin = [1.0, 1.0, 0.6], spacing = [0.0, 0.5], columns = 1 }
heading_deg = 200
mission = [{ t = 0, mode = "auto", depth = 0.8, yaw_deg = 200, surge = 0.05 }]
behaviour = { kind = "beacon", period = 0.2, payload_bytes = 20, jitter = 0.1 }
[[vehicles.model.modems]]
name = "front"
position = [0.125, 0.0, 0.0]
direction = [1.0, 0.0, 0.0]
[[vehicles.model.modems]]
name = "right"
position = [0.0, 0.078, 0.0]
direction = [0.0, 1.0, 0.0]
[[vehicles.model.modems]]
name = "back"
position = [-0.125, 0.0, 0.0]
direction = [-1.0, 0.0, 0.0]
[[vehicles.model.modems]]
name = "left"
position = [0.0, -0.078, 0.0]
direction = [0.0, -1.0, 0.0]
[output]
record_hz = 10.0
mcap = true
"#;

fn desc() -> WorldDesc {
    shoal_world::load::load_str(WORLD, Path::new("mcap-test.toml")).unwrap()
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-mcap-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The run: every drained batch (drained every 37 steps, so samples and attempts cross
/// batch boundaries) and the file's bytes; `every` overrides the plan's sample thinning.
fn run(name: &str, every: Option<u64>) -> (WorldDesc, Vec<RecordBatch>, McapSummary, Vec<u8>) {
    run_on(name, every, 1)
}

/// [`run`] on `threads` threads (every loop split over them).
fn run_on(
    name: &str,
    every: Option<u64>,
    threads: usize,
) -> (WorldDesc, Vec<RecordBatch>, McapSummary, Vec<u8>) {
    let desc = desc();
    let (batches, summary, bytes, _) = run_world(&desc, name, every, threads);
    (desc, batches, summary, bytes)
}

/// [`run_on`] with the world `desc`; the simulation too, at its end.
fn run_world(
    desc: &WorldDesc,
    name: &str,
    every: Option<u64>,
    threads: usize,
) -> (Vec<RecordBatch>, McapSummary, Vec<u8>, Sim) {
    let opts = SimOptions {
        threads,
        record: true,
    };
    let mut sim = Sim::new(desc, opts);
    sim.set_min_parallel(1);
    let path = dir(name).join(FILE_NAME);
    let mut out = McapOutput::create(&path, desc).unwrap();
    if let Some(k) = every {
        out.plan.sample_every = k;
        out.summary.sample_every = k;
    }
    let mut batches = Vec::new();
    while sim.step_count() < desc.steps() {
        sim.run(37.min(desc.steps() - sim.step_count()));
        let b = sim.drain();
        out.write(&b).unwrap();
        batches.push(b);
    }
    let done = out.finish().unwrap();
    let summary = done.summary.clone();
    assert!(!path.exists(), "the file appears only when committed");
    assert_eq!(done.commit().unwrap(), path);
    let bytes = std::fs::read(&path).unwrap();
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
    (batches, summary, bytes, sim)
}

/// Every recorded row: `rows[vehicle][sample]`.
fn rows(desc: &WorldDesc, batches: &[RecordBatch]) -> Vec<Vec<Vec<f64>>> {
    (0..desc.vehicles.len())
        .map(|i| {
            let s = recorder::stride(&desc.vehicles[i].model);
            batches
                .iter()
                .flat_map(|b| b.rows[i].chunks(s).map(<[f64]>::to_vec))
                .collect()
        })
        .collect()
}

/// One message as read back.
struct Read {
    topic: String,
    schema: String,
    schema_encoding: String,
    schema_data: Vec<u8>,
    encoding: String,
    log_time: u64,
    publish_time: u64,
    data: Vec<u8>,
}

fn read(bytes: &[u8]) -> Vec<Read> {
    mcap::MessageStream::new(bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            let s = m.channel.schema.as_ref().unwrap();
            Read {
                topic: m.channel.topic.clone(),
                schema: s.name.clone(),
                schema_encoding: s.encoding.clone(),
                schema_data: s.data.to_vec(),
                encoding: m.channel.message_encoding.clone(),
                log_time: m.log_time,
                publish_time: m.publish_time,
                data: m.data.to_vec(),
            }
        })
        .collect()
}

fn on<'a>(msgs: &'a [Read], topic: &str) -> std::vec::IntoIter<&'a Read> {
    let all: Vec<&Read> = msgs.iter().filter(|m| m.topic == topic).collect();
    all.into_iter()
}

#[test]
fn every_topic_has_a_message_per_sample_and_vehicle_in_time_order() {
    let (desc, batches, summary, bytes) = run("counts", None);
    let msgs = read(&bytes);
    let rows = rows(&desc, &batches);
    let samples = rows[0].len();
    assert_eq!(samples, 21, "t = 0 … 2 s at 10 Hz");
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for m in &msgs {
        *counts.entry(m.topic.as_str()).or_default() += 1;
    }
    for v in &desc.vehicles {
        for t in topics::TOPICS {
            assert_eq!(counts[format!("/{}/{t}", v.name).as_str()], samples, "{t}");
        }
    }
    let attempts: usize = batches.iter().map(|b| b.frames.len()).sum();
    assert!(attempts > 50, "the beacons are heard: {attempts}");
    assert_eq!(counts["/tf"], samples);
    assert_eq!(counts["/scene"], 1);
    assert_eq!(counts["/optical/frames"], attempts);
    assert_eq!(counts.len(), 4 + 7 * desc.vehicles.len());
    // Time order, simulated time in ns; every sample's time is on its messages.
    assert!(msgs.windows(2).all(|w| w[0].log_time <= w[1].log_time));
    assert!(msgs.iter().all(|m| m.publish_time == m.log_time));
    let tf: Vec<u64> = on(&msgs, "/tf").map(|m| m.log_time).collect();
    let want: Vec<u64> = rows[0].iter().map(|r| ns(r[col::T])).collect();
    assert_eq!(tf, want);
    assert_eq!(*tf.last().unwrap(), 2_000_000_000);
    // The links draw every attempt, each at the end of its sample interval.
    let lines: usize = on(&msgs, "/links")
        .map(|m| ros2::decode::<SceneUpdate>(&m.data).unwrap().entities.len())
        .sum();
    assert_eq!(lines, attempts);
    assert!(on(&msgs, "/links").all(|m| want.contains(&m.log_time)));
    let n = desc.vehicles.len();
    assert_eq!(
        (
            summary.messages as usize,
            summary.samples_recorded,
            summary.samples_written
        ),
        (msgs.len(), 21, 21)
    );
    assert_eq!((summary.vehicles, summary.vehicles_in_world), (n, n));
    assert_eq!(summary.frames_written as usize, attempts);
    assert_eq!(summary.bytes as usize, bytes.len());
    assert_eq!(summary.dropped(), None);
}

#[test]
fn the_file_is_a_ros_2_bag_every_schema_a_msg_definition_every_message_cdr() {
    let (_, _, _, bytes) = run("schemas", None);
    let msgs = read(&bytes);
    // The header's profile: after the magic (8 bytes), opcode 1, record length (u64), then
    // the profile as a u32-prefixed string.
    assert_eq!(bytes[8], 0x01);
    let len = u32::from_le_bytes(bytes[17..21].try_into().unwrap()) as usize;
    assert_eq!(&bytes[21..21 + len], b"ros2");
    let kind = |topic: &str| {
        let m = msgs.iter().find(|m| m.topic == topic).unwrap();
        (
            m.schema.as_str(),
            m.schema_encoding.as_str(),
            m.encoding.as_str(),
        )
    };
    let ros = |t| (t, "ros2msg", "cdr");
    assert_eq!(kind("/tf"), ros("tf2_msgs/msg/TFMessage"));
    assert_eq!(kind("/scene"), ros("foxglove_msgs/msg/SceneUpdate"));
    assert_eq!(kind("/links"), ros("foxglove_msgs/msg/SceneUpdate"));
    assert_eq!(
        kind("/optical/frames"),
        ros("shoal_msgs/msg/ReceptionAttempt")
    );
    assert_eq!(kind("/a-1/state"), ros("shoal_msgs/msg/VehicleState"));
    assert_eq!(kind("/a-1/pressure"), ros("sensor_msgs/msg/FluidPressure"));
    assert_eq!(kind("/a-1/imu"), ros("sensor_msgs/msg/Imu"));
    for t in ["thrusters", "tilts", "tilt_angles", "pump"] {
        assert_eq!(
            kind(&format!("/a-1/{t}")),
            ros("std_msgs/msg/Float64MultiArray")
        );
    }
    // Every schema is its type's complete definition, every message CDR.
    for m in &msgs {
        let text = String::from_utf8(m.schema_data.clone()).unwrap();
        assert_eq!(Some(text), definition(&m.schema), "{}", m.topic);
        assert_eq!(&m.data[..4], &ros2::CDR_LE, "{}", m.topic);
    }
}

/// The body axes of an ENU/FLU attitude `q` against the row's NED/FRD roll φ, pitch θ and
/// yaw ψ by hand (REP 103): forward = (sin ψ cos θ, cos ψ cos θ, sin θ) in (east, north, up),
/// up = FRD's −z: (−b, −a, cos θ cos φ) with a = cos ψ sin θ cos φ + sin ψ sin φ and
/// b = sin ψ sin θ cos φ − cos ψ sin φ. A mirrored heading, north and east swapped, or a
/// sign of roll or pitch lost fails.
fn assert_attitude(q: &ros2::Quaternion, row: &[f64], what: &str) {
    let (x, y, z, w) = (q.x, q.y, q.z, q.w);
    let forward = [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + w * z),
        2.0 * (x * z - w * y),
    ];
    let up = [
        2.0 * (x * z + w * y),
        2.0 * (y * z - w * x),
        1.0 - 2.0 * (x * x + y * y),
    ];
    let (phi, theta, psi) = (row[col::ROLL], row[col::PITCH], row[col::YAW]);
    let a = psi.cos() * theta.sin() * phi.cos() + psi.sin() * phi.sin();
    let b = psi.sin() * theta.sin() * phi.cos() - psi.cos() * phi.sin();
    let want_forward = [
        psi.sin() * theta.cos(),
        psi.cos() * theta.cos(),
        theta.sin(),
    ];
    let want_up = [-b, -a, theta.cos() * phi.cos()];
    for j in 0..3 {
        assert!(
            (forward[j] - want_forward[j]).abs() < 1e-12 && (up[j] - want_up[j]).abs() < 1e-12,
            "{what}: forward {forward:?} up {up:?}, want {want_forward:?} {want_up:?} \
             (roll {phi}, pitch {theta}, yaw {psi})"
        );
    }
}

#[test]
fn messages_decode_to_the_recorded_values() {
    let (desc, batches, _, bytes) = run("values", None);
    let msgs = read(&bytes);
    let rows = rows(&desc, &batches);
    let rho_g = desc.env.density * desc.env.gravity;
    for (i, v) in desc.vehicles.iter().enumerate() {
        let topic = |t: &str| format!("/{}/{t}", v.name);
        let n_thr = v.model.params.thrusters.len();
        let pressure = on(&msgs, &topic("pressure"));
        let imu = on(&msgs, &topic("imu"));
        let thr = on(&msgs, &topic("thrusters"));
        let tilts = on(&msgs, &topic("tilts"));
        let angles = on(&msgs, &topic("tilt_angles"));
        let pump = on(&msgs, &topic("pump"));
        let state = on(&msgs, &topic("state"));
        let all = pressure
            .zip(imu)
            .zip(thr)
            .zip(tilts)
            .zip(angles)
            .zip(pump)
            .zip(state);
        let mut k = 0;
        for ((((((p, m), th), ti), an), pu), st) in all {
            let row = &rows[i][k];
            let stamp = ros2::Time::from_ns(ns(row[col::T]));
            let p: FluidPressure = ros2::decode(&p.data).unwrap();
            assert_eq!(p.header.stamp, stamp);
            assert_eq!(p.header.frame_id, v.name);
            assert_eq!(
                p.fluid_pressure,
                101_325.0 + rho_g * row[col::DEPTH_READING]
            );
            assert_eq!(p.variance, 0.0);
            let m: Imu = ros2::decode(&m.data).unwrap();
            assert_eq!(m, topics::imu_of(p.header.clone(), row));
            assert_attitude(&m.orientation, row, "imu");
            assert_eq!(m.angular_velocity.y, -row[col::Q]);
            assert_eq!(m.linear_acceleration_covariance[0], -1.0);
            // The commands in force from this sample on: the next row's (the last, its own).
            let next = &rows[i][(k + 1).min(rows[i].len() - 1)];
            let th: Float64MultiArray = ros2::decode(&th.data).unwrap();
            assert_eq!(th.data, next[FIXED.len()..FIXED.len() + n_thr]);
            assert_eq!(th.layout.dim[0].label, "top,port,stbd");
            let ti: Float64MultiArray = ros2::decode(&ti.data).unwrap();
            assert_eq!(ti.layout.dim[0].label, "alpha,beta");
            assert_eq!(ti.data, next[FIXED.len() + n_thr + 2..]);
            let an: Float64MultiArray = ros2::decode(&an.data).unwrap();
            assert_eq!(an.layout.dim[0].label, "alpha,beta");
            assert_eq!(an.data, row[FIXED.len() + n_thr..FIXED.len() + n_thr + 2]);
            let pu: Float64MultiArray = ros2::decode(&pu.data).unwrap();
            assert_eq!(pu.data, [next[col::PUMP]]);
            let st: StateMsg = ros2::decode(&st.data).unwrap();
            let mode = recorder::mode_of_code(row[col::MODE]);
            assert_eq!(st.mode, mode.name());
            let numbers: Vec<f64> = st.before.iter().chain(&st.after).copied().collect();
            let want: Vec<f64> = (0..FIXED.len())
                .filter(|&j| j != col::MODE)
                .map(|j| row[j])
                .collect();
            assert_eq!(numbers.len(), want.len());
            for (a, b) in numbers.iter().zip(&want) {
                assert!(a == b || (a.is_nan() && b.is_nan()), "{a} {b}");
            }
            k += 1;
        }
        assert_eq!(k, rows[i].len());
    }
    // The poses in /tf are the rows' in ENU.
    for (k, m) in on(&msgs, "/tf").enumerate() {
        let tf: TfMessage = ros2::decode(&m.data).unwrap();
        for (i, t) in tf.transforms.iter().enumerate() {
            assert_eq!(t.child_frame_id, desc.vehicles[i].name);
            assert_eq!(
                t,
                &scene::transform(t.header.stamp, &desc.vehicles[i].name, &rows[i][k])
            );
            // ENU: x east, y north, z up.
            let (tr, row) = (&t.transform.translation, &rows[i][k]);
            assert_eq!([tr.x, tr.y, tr.z], [row[col::Y], row[col::X], -row[col::Z]]);
            assert_attitude(&t.transform.rotation, row, "/tf");
        }
    }
    // Every attempt as the medium decided it, with the vehicles' names.
    let frames: Vec<ReceptionAttempt> = on(&msgs, "/optical/frames")
        .map(|m| ros2::decode(&m.data).unwrap())
        .collect();
    let names: Vec<String> = desc.vehicles.iter().map(|v| v.name.clone()).collect();
    let mut want: Vec<ReceptionAttempt> = batches
        .iter()
        .flat_map(|b| b.frames.iter().map(|h| ReceptionAttempt::of(h, &names)))
        .collect();
    want.sort_by(|a, b| {
        a.t_s
            .total_cmp(&b.t_s)
            .then(a.sender_id.cmp(&b.sender_id))
            .then(a.receiver_id.cmp(&b.receiver_id))
    });
    assert_eq!(frames, want);
    assert!(
        frames
            .iter()
            .any(|f| f.outcome == "delivered" && f.bytes == 20)
    );
}

/// `a` sends acknowledged unicasts to `b` 1.25 m ahead of it, facing it; `b` beacons to
/// everyone besides (the replay's test world, `shoal-sim/tests/support`).
const ACKED: &str = include_str!("../../../shoal-sim/tests/support/acked_pair.toml");

/// The attempts tell acknowledgements from other frames: an acknowledgement carries no
/// payload, data frames and beacons do, so an attempt is flagged exactly when it has no
/// payload; every flagged one goes from `b` back to `a`, one for each acknowledgement `b`
/// put on the air (the last may not have ended).
#[test]
fn acknowledgements_are_marked_and_go_back_to_the_sender() {
    let text = format!("{ACKED}[output]\nrecord_hz = 10.0\nmcap = true\n");
    let desc = shoal_world::load::load_str(&text, Path::new("acked.toml")).unwrap();
    let (_, _, bytes, mut sim) = run_world(&desc, "acked", None, 1);
    sim.fold_comm();
    let msgs = read(&bytes);
    let frames: Vec<ReceptionAttempt> = on(&msgs, "/optical/frames")
        .map(|m| ros2::decode(&m.data).unwrap())
        .collect();
    assert!(frames.iter().all(|f| f.ack == (f.bytes == 0)), "{frames:?}");
    let acks: Vec<_> = frames.iter().filter(|f| f.ack).collect();
    assert!(
        acks.iter()
            .all(|f| (f.sender.as_str(), f.receiver.as_str()) == ("b", "a"))
    );
    let (flagged, sent) = (acks.len() as u64, sim.vehicle(1).comm.acks_sent);
    assert!(
        sent > 10 && flagged <= sent && flagged + 1 >= sent,
        "{flagged} acknowledgements in run.mcap, {sent} sent"
    );
}

#[test]
fn acknowledgement_links_are_dashed_along_the_line() {
    let text = format!("{ACKED}[output]\nrecord_hz = 10.0\nmcap = true\n");
    let desc = shoal_world::load::load_str(&text, Path::new("acked.toml")).unwrap();
    let (_, _, bytes, _) = run_world(&desc, "acked_links", None, 1);
    let msgs = read(&bytes);
    let attempts: Vec<ReceptionAttempt> = on(&msgs, "/optical/frames")
        .map(|m| ros2::decode(&m.data).unwrap())
        .collect();
    let lines: Vec<_> = on(&msgs, "/links")
        .flat_map(|m| ros2::decode::<SceneUpdate>(&m.data).unwrap().entities)
        .collect();
    let frame = |e: &foxglove::SceneEntity| {
        let kv = e.metadata.iter().find(|kv| kv.key == "frame").unwrap();
        kv.value.clone()
    };
    let acks: Vec<_> = lines
        .iter()
        .filter(|e| frame(e) == "acknowledgement")
        .collect();
    // One line per attempt, marked as /optical/frames marks it.
    assert_eq!(lines.len(), attempts.len());
    assert_eq!(acks.len(), attempts.iter().filter(|a| a.ack).count());
    assert!(acks.len() > 10, "{} acknowledgement lines", acks.len());
    for e in &lines {
        let p = &e.lines[0].points;
        if frame(e) == "data" {
            assert_eq!(p.len(), 2);
            continue;
        }
        // Dashes: pairs along the line from the first point to the last, each ending before
        // the next begins (a gap), together covering more than half of it.
        let v = |q: &ros2::Point| shoal_model::math::Vec3::new(q.x, q.y, q.z);
        let (a, b) = (v(&p[0]), v(&p[p.len() - 1]));
        let (d, length) = ((b - a).normalize(), (b - a).norm());
        assert!(p.len() >= 4 && p.len() % 2 == 0, "{} points", p.len());
        let s: Vec<f64> = p.iter().map(|q| (v(q) - a).dot(&d)).collect();
        assert!(p.iter().all(|q| (v(q) - a).cross(&d).norm() < 1e-9));
        assert!(s.windows(2).all(|w| w[1] > w[0]), "{s:?}");
        let drawn: f64 = s.chunks(2).map(|c| c[1] - c[0]).sum();
        assert!(
            drawn > 0.5 * length && drawn < length,
            "{drawn} of {length}"
        );
    }
}

#[test]
fn the_scene_holds_the_hulls_the_pool_and_the_obstacle() {
    let (desc, _, _, bytes) = run("scene", None);
    let msgs = read(&bytes);
    let m = on(&msgs, "/scene").next().unwrap();
    let s: SceneUpdate = ros2::decode(&m.data).unwrap();
    let ids: Vec<&str> = s.entities.iter().map(|e| e.id.as_str()).collect();
    assert_eq!(
        ids,
        ["hull/a-0", "hull/a-1", "hull/a-2", "pool", "obstacle/post"]
    );
    let h = desc.vehicles[0].model.params.body.hull_size;
    let hull = &s.entities[0];
    assert!(hull.frame_locked && hull.frame_id == "a-0");
    assert_eq!(hull.cylinders[0].size, [h.z, h.y, h.x].into());
    // The pool: 12 edges from the surface (z = 0) down to its floor, east 4 m, north 6 m.
    let pool = &s.entities[3].lines[0].points;
    assert_eq!(pool.len(), 24);
    let max = |f: fn(&ros2::Point) -> f64| pool.iter().map(f).fold(f64::MIN, f64::max);
    let min = |f: fn(&ros2::Point) -> f64| pool.iter().map(f).fold(f64::MAX, f64::min);
    assert_eq!((max(|p| p.x), max(|p| p.y), max(|p| p.z)), (4.0, 6.0, 0.0));
    assert_eq!(min(|p| p.z), -2.0);
    // The post stands upright at east 3, north 4.5, its centre 1 m down.
    let post = &s.entities[4].cylinders[0];
    assert_eq!(post.pose.position, [3.0, 4.5, -1.0].into());
    let o = post.pose.orientation;
    let q = shoal_model::math::Quat::from_quaternion(nalgebra::Quaternion::new(o.w, o.x, o.y, o.z));
    assert!(
        (q * shoal_model::math::Vec3::z()).z.abs() > 1.0 - 1e-9,
        "{o:?}"
    );
    assert_eq!(post.size, [0.4, 0.4, 2.0].into());
}

#[test]
fn the_size_estimate_covers_what_a_sample_takes() {
    let (desc, _, summary, bytes) = run("budget", None);
    let msgs = read(&bytes);
    // Each message's record (31 B) and index entry (16 B) with its payload.
    let record = |m: &Read| m.data.len() as u64 + 47;
    let vehicles = desc.vehicles.len() as u64;
    let per_vehicle: u64 = msgs
        .iter()
        .filter(|m| m.topic.starts_with("/a-") || m.topic == "/tf")
        .map(record)
        .sum::<u64>()
        / (summary.samples_written * vehicles);
    let actuators = (desc.vehicles[0].model.params.thrusters.len()
        + desc.vehicles[0].model.params.tilts.len()) as u64;
    let estimate = BYTES_PER_VEHICLE_SAMPLE + BYTES_PER_ACTUATOR * actuators;
    assert!(per_vehicle <= estimate, "{per_vehicle} B > {estimate} B");
    assert!(
        per_vehicle * 3 > estimate * 2,
        "{per_vehicle} B ≪ {estimate} B"
    );
}

#[test]
fn a_thinned_run_keeps_every_kth_sample_and_says_so() {
    let (desc, _, summary, bytes) = run("thinned", Some(3));
    let msgs = read(&bytes);
    // Samples 0, 3, …, 18 of 21.
    assert_eq!(on(&msgs, "/tf").count(), 7);
    assert_eq!(
        on(&msgs, &format!("/{}/imu", desc.vehicles[2].name)).count(),
        7
    );
    assert_eq!(on(&msgs, "/tf").nth(1).unwrap().log_time, 300_000_000);
    assert_eq!((summary.samples_written, summary.samples_recorded), (7, 21));
    assert_eq!(
        summary.dropped().as_deref(),
        Some("kept 1 sample in 3 (7 of 21) (size budget, docs/mcap.md)")
    );
}

#[test]
fn an_unwritable_folder_is_an_error_that_names_the_file() {
    let path = Path::new("/nonexistent-shoal-folder/out/run.mcap");
    let e = McapOutput::create(path, &desc()).err().unwrap();
    assert_eq!(e.path, path);
    assert!(
        e.to_string()
            .starts_with("cannot write /nonexistent-shoal-folder/out/run.mcap: "),
        "{e}"
    );
}

#[test]
fn a_run_output_commits_run_mcap_after_the_tables_and_summarises_it() {
    let desc = desc();
    let d = dir("run-output");
    let mut sim = Sim::new(&desc, SimOptions::default());
    let mut out = RunOutput::create(&d, &desc).unwrap();
    while sim.step_count() < desc.steps() {
        sim.run(50);
        out.write(&sim.drain()).unwrap();
    }
    let s = out.finish(&mut sim, 0.1, &Cancel::new()).unwrap();
    let m = s.mcap.as_ref().unwrap();
    assert_eq!(m.samples_written, 21);
    let files: Vec<String> = s
        .files
        .iter()
        .map(|f| f.rsplit('/').next().unwrap().to_string())
        .collect();
    let at = |n: &str| files.iter().position(|f| f == n).unwrap();
    assert!(at("vehicles.csv") < at("run.mcap") && at("run.mcap") < at("depth.png"));
    assert_eq!(
        std::fs::metadata(d.join("run.mcap")).unwrap().len(),
        m.bytes
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["mcap"]["messages"], m.messages);
    assert!(s.to_text().contains("run.mcap: "), "{}", s.to_text());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_file_is_the_same_on_one_and_two_threads() {
    let (_, _, _, one) = run_on("threads-1", None, 1);
    let (_, _, _, two) = run_on("threads-2", None, 2);
    assert!(one == two, "run.mcap differs between 1 and 2 threads");
}

/// `shoal_msgs/msg/VehicleState` as a reader without shoal's types sees it: the numbers
/// before the mode, the mode's name, the numbers after it.
#[derive(serde::Deserialize)]
struct StateMsg {
    before: [f64; 16],
    mode: String,
    after: [f64; 5],
}
