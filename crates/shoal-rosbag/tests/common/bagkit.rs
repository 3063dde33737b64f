//! A rosbag2-like MCAP file written in Rust for the reader's tests and benchmark: six
//! topics of a logged μAUV² with the standard types of `run.mcap` (`shoal_sim`'s ROS 2
//! messages and definitions), each at its own rate, header-stamped with a jitter, and a
//! mapping that reads them.
//!
//! | topic | type | rate | first message |
//! |---|---|---|---|
//! | `/auv/imu` | sensor_msgs/msg/Imu | 100 Hz | 1 ms |
//! | `/auv/pressure` | sensor_msgs/msg/FluidPressure | 40 Hz | 1 ms |
//! | `/auv/thrusters` | std_msgs/msg/Float64MultiArray (3, %) | 20 Hz | 1 ms |
//! | `/auv/tilts` | std_msgs/msg/Float64MultiArray (2, rad) | 20 Hz | 1 ms |
//! | `/auv/pump` | std_msgs/msg/Float64MultiArray (1) | 1 Hz | 0.5 s (late: "on change") |
//! | `/auv/camera_info` | std_msgs/msg/Float64MultiArray (64 values, not mapped) | 30 Hz | 1 ms |
//!
//! The truth the messages are written from is public ([`schedule`], [`attitude_enu`],
//! [`rates_flu`], [`depth_m`], [`array`]) so that tests compute what a reader must give by
//! their own formulas. The IMU writes ROS's frames (REP 103: FLU body, ENU world) from explicit
//! formulas ([`quaternion_zyx`]), never through shoal's frame conversions. Stamps are the
//! header's; the bag's log time is [`LOG_DELAY_NS`] later (the arrays have no header, so a
//! reader places them at their log time).

#![allow(dead_code)]

use super::cdr::{self, Body};
use shoal_record::mcap::definition;
use shoal_record::mcap::ros2::{
    Float64MultiArray, FluidPressure, Header, Imu, Quaternion, Time, Vector3, encode,
};
use std::collections::BTreeMap;
use std::io::Cursor;

/// The mapping of the kit's bags.
pub const MAPPING: &str = r#"
[defaults]
namespace = "/auv"
[inputs]
"u.top"   = { topic = "thrusters", field = "data[0]" }
"u.port"  = { topic = "thrusters", field = "data[1]" }
"u.stbd"  = { topic = "thrusters", field = "data[2]" }
"u.alpha" = { topic = "tilts", field = "data[0]" }
"u.beta"  = { topic = "tilts", field = "data[1]" }
"u.pump"  = { topic = "pump", field = "data[0]" }
[channels]
"y.depth" = { topic = "pressure", field = "fluid_pressure", depth_from_pressure = { density_kg_m3 = 1000.0 } }
"y.roll"  = { topic = "imu", field = "orientation" }
"y.pitch" = { topic = "imu", field = "orientation" }
"y.yaw"   = { topic = "imu", field = "orientation" }
"y.p"     = { topic = "imu", field = "angular_velocity.x" }
"y.q"     = { topic = "imu", field = "angular_velocity.y" }
"y.r"     = { topic = "imu", field = "angular_velocity.z" }
"#;

/// Topic numbers (index into [`TOPICS`]).
pub const IMU: usize = 0;
pub const PRESSURE: usize = 1;
pub const THRUSTERS: usize = 2;
pub const TILTS: usize = 3;
pub const PUMP: usize = 4;
pub const CAMERA: usize = 5;

/// Topic, type and rate \[Hz\] of each topic.
pub const TOPICS: [(&str, &str, u64); 6] = [
    ("/auv/imu", "sensor_msgs/msg/Imu", 100),
    ("/auv/pressure", "sensor_msgs/msg/FluidPressure", 40),
    ("/auv/thrusters", "std_msgs/msg/Float64MultiArray", 20),
    ("/auv/tilts", "std_msgs/msg/Float64MultiArray", 20),
    ("/auv/pump", "std_msgs/msg/Float64MultiArray", 1),
    ("/auv/camera_info", "std_msgs/msg/Float64MultiArray", 30),
];

/// The dimension labels of the array topics (thrusters, tilts, pump, camera_info).
const LABELS: [&str; 4] = ["top,port,stbd", "alpha,beta", "pump", "k"];

/// The bag receives a message this long after its stamp \[ns\].
pub const LOG_DELAY_NS: u64 = 500_000;

/// Surface pressure \[Pa\] and ρ·g of the kit's water (1000 kg/m³, standard gravity) \[Pa/m\].
pub const SURFACE_PA: f64 = 101_325.0;
pub const RHO_G: f64 = 1000.0 * 9.80665;

/// The nominal time of topic `i`'s first message \[ns\]: the pump, published on change,
/// starts half a second after the others.
pub fn first_ns(i: usize) -> u64 {
    if i == PUMP { 500_000_000 } else { 1_000_000 }
}

/// One message of the kit: topic, number within the topic, header stamp and log time \[ns\].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sample {
    pub topic: usize,
    pub k: u64,
    pub stamp_ns: u64,
    pub log_ns: u64,
}

/// Every message of `seconds` of the kit, in the order the bag stores them (log time).
pub fn schedule(seconds: u64) -> Vec<Sample> {
    let mut out = Vec::new();
    for (i, (_, _, hz)) in TOPICS.iter().enumerate() {
        let period = 1_000_000_000 / hz;
        for k in 0..seconds * hz {
            // Stamps jitter by up to 0.4 ms after the nominal sample time.
            let jitter = (k * 7919 + i as u64 * 104_729) % 400_000;
            let stamp_ns = first_ns(i) + k * period + jitter;
            if stamp_ns >= seconds * 1_000_000_000 {
                continue;
            }
            out.push(Sample {
                topic: i,
                k,
                stamp_ns,
                log_ns: stamp_ns + LOG_DELAY_NS,
            });
        }
    }
    out.sort_by_key(|s| (s.log_ns, s.topic, s.k));
    out
}

/// The IMU's attitude in ROS's frames at `t` \[s\]: ZYX Euler angles roll, pitch, yaw of the
/// FLU body in the ENU world \[rad\], each clearly away from zero.
pub fn attitude_enu(t: f64) -> [f64; 3] {
    [
        0.25 + 0.1 * (0.7 * t).sin(),
        -0.2 + 0.1 * (0.5 * t).sin(),
        0.8 + 0.3 * (0.2 * t).sin(),
    ]
}

/// The IMU's angular velocity about its FLU axes at `t` \[rad/s\], each clearly away from
/// zero and from the others.
pub fn rates_flu(t: f64) -> [f64; 3] {
    [
        0.1 + 0.02 * (0.9 * t).sin(),
        0.05 + 0.02 * (0.6 * t).cos(),
        -0.03 + 0.01 * (0.2 * t).cos(),
    ]
}

/// The depth at `t` \[m\]: 1 m ± 0.5 m.
pub fn depth_m(t: f64) -> f64 {
    1.0 + 0.5 * (0.1 * t).sin()
}

/// The values of the `k`-th message of array topic `i` stamped `t` \[s\]: thruster commands
/// \[%\] (top, port, stbd), tilt angles \[rad\] (alpha, beta), the pump (+1, 0, −1 in turn) and
/// 64 values nobody maps.
pub fn array(i: usize, k: u64, t: f64) -> Vec<f64> {
    match i {
        THRUSTERS => vec![
            30.0 * (0.1 * t).sin(),
            20.0 - (k % 5) as f64,
            20.0 + (k % 7) as f64,
        ],
        TILTS => vec![0.5 * (0.3 * t).sin(), -1.2 + 0.1 * (k % 3) as f64],
        PUMP => vec![[1.0, 0.0, -1.0][(k % 3) as usize]],
        CAMERA => (0..64).map(|j| (j as f64 + t).sin()).collect(),
        _ => panic!("topic {i} is not an array"),
    }
}

/// The unit quaternion (x, y, z, w) of the ZYX Euler angles: R = Rz(yaw)·Ry(pitch)·Rx(roll),
/// by the half-angle formulas.
pub fn quaternion_zyx(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (sr, cr) = (roll / 2.0).sin_cos();
    let (sp, cp) = (pitch / 2.0).sin_cos();
    let (sy, cy) = (yaw / 2.0).sin_cos();
    [
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    ]
}

fn header(ns: u64) -> Header {
    Header {
        stamp: Time::from_ns(ns),
        frame_id: "auv".into(),
    }
}

/// The message of sample `s`, CDR-encoded as rclcpp writes it.
pub fn message(s: &Sample) -> Vec<u8> {
    let t = s.stamp_ns as f64 * 1e-9;
    let out = match s.topic {
        IMU => {
            let [roll, pitch, yaw] = attitude_enu(t);
            let [x, y, z, w] = quaternion_zyx(roll, pitch, yaw);
            encode(&Imu {
                header: header(s.stamp_ns),
                orientation: Quaternion { x, y, z, w },
                orientation_covariance: [0.0; 9],
                angular_velocity: Vector3::from(rates_flu(t)),
                angular_velocity_covariance: [0.0; 9],
                linear_acceleration: Vector3 {
                    x: 0.0,
                    y: 0.0,
                    z: 9.81,
                },
                linear_acceleration_covariance: [0.0; 9],
            })
        }
        PRESSURE => encode(&FluidPressure {
            header: header(s.stamp_ns),
            fluid_pressure: SURFACE_PA + RHO_G * depth_m(t),
            variance: 0.0,
        }),
        i => encode(&Float64MultiArray::vector(
            LABELS[i - THRUSTERS],
            array(i, s.k, t),
        )),
    };
    out.expect("a message serialises into memory")
}

/// The message of sample `s` written by hand with its layout ([`super::cdr`]): the same
/// bytes as [`message`] (a test checks it), with where each value lies.
pub fn body(s: &Sample) -> Body {
    let t = s.stamp_ns as f64 * 1e-9;
    match s.topic {
        IMU => {
            let [roll, pitch, yaw] = attitude_enu(t);
            let q = quaternion_zyx(roll, pitch, yaw);
            cdr::imu(s.stamp_ns, q, rates_flu(t), [0.0, 0.0, 9.81], &[0.0; 9])
        }
        PRESSURE => cdr::fluid_pressure(s.stamp_ns, SURFACE_PA + RHO_G * depth_m(t), 0.0),
        i => cdr::float64_multi_array(LABELS[i - THRUSTERS], &array(i, s.k, t)),
    }
}

/// How a bag of the kit is written.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Length of the recording \[s\].
    pub seconds: u64,
    /// A new chunk after this many messages (`None`: the writer's own chunks of 1 MiB).
    pub messages_per_chunk: Option<usize>,
    /// zstd-compressed chunks (as `ros2 bag record` writes by default) or plain ones.
    pub compressed: bool,
}

impl Options {
    /// `seconds` of the kit in the writer's own zstd-compressed chunks.
    pub fn new(seconds: u64) -> Options {
        Options {
            seconds,
            messages_per_chunk: None,
            compressed: true,
        }
    }
}

/// An MCAP file of `seconds` of the six topics, in log-time order as a recorder writes it.
pub fn bag(seconds: u64) -> Vec<u8> {
    bag_with(&Options::new(seconds), |_, _| {})
}

/// A bag written as `o` says, each message's bytes passed through `edit` before they are
/// written (a test's mutation; `|_, _| {}` for none).
pub fn bag_with(o: &Options, mut edit: impl FnMut(&Sample, &mut Vec<u8>)) -> Vec<u8> {
    let compression = if o.compressed {
        Some(mcap::Compression::Zstd)
    } else {
        None
    };
    let chunk_size = match o.messages_per_chunk {
        Some(_) => None,
        None => Some(mcap::WriteOptions::DEFAULT_CHUNK_SIZE),
    };
    let mut w = mcap::WriteOptions::new()
        .compression(compression)
        .chunk_size(chunk_size)
        .create(Cursor::new(Vec::new()))
        .expect("an MCAP writer in memory");
    let mut ids = Vec::new();
    for (topic, ty, _) in TOPICS {
        let text = definition(ty).expect("run.mcap defines the kit's types");
        let schema = w
            .add_schema(ty, "ros2msg", text.as_bytes())
            .expect("schema");
        ids.push(
            w.add_channel(schema, topic, "cdr", &BTreeMap::new())
                .expect("channel"),
        );
    }
    for (seq, s) in schedule(o.seconds).iter().enumerate() {
        let mut data = message(s);
        edit(s, &mut data);
        let header = mcap::records::MessageHeader {
            channel_id: ids[s.topic],
            sequence: seq as u32,
            log_time: s.log_ns,
            publish_time: s.stamp_ns,
        };
        w.write_to_known_channel(&header, &data).expect("a message");
        if o.messages_per_chunk.is_some_and(|n| (seq + 1) % n == 0) {
            w.flush().expect("a chunk closed");
        }
    }
    w.finish().expect("the summary");
    w.into_inner().into_inner()
}
