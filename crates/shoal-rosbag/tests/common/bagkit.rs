//! A rosbag2-like MCAP file written in Rust for the reader's fuzz test and benchmark: six
//! topics of a logged μAUV² with the standard types of `run.mcap` (`shoal_sim`'s ROS 2
//! messages and definitions), each at its own rate, header-stamped with a jitter, and a
//! mapping that reads them.
//!
//! | topic | type | rate |
//! |---|---|---|
//! | `/auv/imu` | sensor_msgs/msg/Imu | 100 Hz |
//! | `/auv/pressure` | sensor_msgs/msg/FluidPressure | 40 Hz |
//! | `/auv/thrusters` | std_msgs/msg/Float64MultiArray (3, %) | 20 Hz |
//! | `/auv/tilts` | std_msgs/msg/Float64MultiArray (2, rad) | 20 Hz |
//! | `/auv/pump` | std_msgs/msg/Float64MultiArray (1) | 1 Hz |
//! | `/auv/camera_info` | std_msgs/msg/Float64MultiArray (64 values, not mapped) | 30 Hz |

#![allow(dead_code)]

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

const TOPICS: [(&str, &str, u64); 6] = [
    ("/auv/imu", "sensor_msgs/msg/Imu", 100),
    ("/auv/pressure", "sensor_msgs/msg/FluidPressure", 40),
    ("/auv/thrusters", "std_msgs/msg/Float64MultiArray", 20),
    ("/auv/tilts", "std_msgs/msg/Float64MultiArray", 20),
    ("/auv/pump", "std_msgs/msg/Float64MultiArray", 1),
    ("/auv/camera_info", "std_msgs/msg/Float64MultiArray", 30),
];

fn header(ns: u64) -> Header {
    Header {
        stamp: Time::from_ns(ns),
        frame_id: "auv".into(),
    }
}

/// The k-th message of topic `i` at `ns`: smooth signals, depth 1 m ± 0.5 m.
fn message(i: usize, k: u64, ns: u64) -> Vec<u8> {
    let t = ns as f64 * 1e-9;
    let out = match i {
        0 => {
            let yaw = 0.3 * (0.2 * t).sin();
            encode(&Imu {
                header: header(ns),
                orientation: Quaternion {
                    x: 0.01,
                    y: 0.02,
                    z: (yaw / 2.0).sin(),
                    w: (yaw / 2.0).cos(),
                },
                orientation_covariance: [0.0; 9],
                angular_velocity: Vector3 {
                    x: 0.01,
                    y: -0.02,
                    z: 0.06 * (0.2 * t).cos(),
                },
                angular_velocity_covariance: [0.0; 9],
                linear_acceleration: Vector3 {
                    x: 0.0,
                    y: 0.0,
                    z: 9.81,
                },
                linear_acceleration_covariance: [0.0; 9],
            })
        }
        1 => encode(&FluidPressure {
            header: header(ns),
            fluid_pressure: 101_325.0 + 9806.65 * (1.0 + 0.5 * (0.1 * t).sin()),
            variance: 0.0,
        }),
        2 => encode(&Float64MultiArray::vector(
            "top,port,stbd",
            vec![30.0 * (0.1 * t).sin(), 20.0, 20.0 + (k % 7) as f64],
        )),
        3 => encode(&Float64MultiArray::vector("alpha,beta", vec![0.0, -1.2])),
        4 => encode(&Float64MultiArray::vector("pump", vec![0.0])),
        _ => encode(&Float64MultiArray::vector(
            "k",
            (0..64).map(|j| (j as f64 + t).sin()).collect(),
        )),
    };
    out.expect("a message serialises into memory")
}

/// An MCAP file of `seconds` of the six topics, in log-time order as a recorder writes it.
pub fn bag(seconds: u64) -> Vec<u8> {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).expect("an MCAP writer in memory");
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
    let mut events: Vec<(u64, usize, u64)> = Vec::new();
    for (i, (_, _, hz)) in TOPICS.iter().enumerate() {
        let period = 1_000_000_000 / hz;
        for k in 0..seconds * hz {
            // Stamps jitter by up to ±0.2 ms around the nominal sample time.
            let jitter = (k * 7919 + i as u64 * 104_729) % 400_000;
            events.push((1_000_000 + k * period + jitter, i, k));
        }
    }
    events.sort();
    for (seq, (ns, i, k)) in events.into_iter().enumerate() {
        let data = message(i, k, ns);
        let header = mcap::records::MessageHeader {
            channel_id: ids[i],
            sequence: seq as u32,
            log_time: ns + 500_000,
            publish_time: ns,
        };
        w.write_to_known_channel(&header, &data).expect("a message");
    }
    w.finish().expect("the summary");
    w.into_inner().into_inner()
}
