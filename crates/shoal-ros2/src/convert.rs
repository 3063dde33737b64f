//! Between the world and ROS 2's messages: observations as `Imu`, `FluidPressure`,
//! `Odometry` and `/tf` in ROS's axes (ENU world, FLU body, REP 103 — the conversions of
//! `run.mcap`, [`shoal_model::frames`]), received frames as `OpticalFrame`, and an
//! agent's `Setpoint` or `Actuators` with its `modem/tx` frames as a world command.

use crate::msgs::{
    ALL_MODEMS, Actuators, FluidPressure, Header, Imu, Odometry, OpticalFrame, Point, Pose,
    PoseWithCovariance, Quaternion, Setpoint, Time, Transform, TransformStamped, Twist,
    TwistWithCovariance, Vector3, mode, stamp,
};
use shoal_model::ballast::Pump;
use shoal_model::control::Mode;
use shoal_model::frames as enu;
use shoal_model::math::{Quat, Vec3, euler_rpy};
use shoal_record::mcap::ros2::SURFACE_PRESSURE_PA;
use shoal_sim::agents::{self, Observation, Order, Rejections};
use shoal_sim::comm::Received;
use shoal_sim::orders::FrameOrder;

/// A stamp in nanoseconds (for ordering).
pub fn ns(t: Time) -> i64 {
    i64::from(t.sec) * 1_000_000_000 + i64::from(t.nanosec)
}

fn header(t: f64, frame: &str) -> Header {
    Header {
        stamp: stamp(t),
        frame_id: frame.to_string(),
    }
}

fn quaternion(q: &Quat) -> Quaternion {
    Quaternion {
        x: q.i,
        y: q.j,
        z: q.k,
        w: q.w,
    }
}

fn vector(v: [f64; 3]) -> Vector3 {
    Vector3 {
        x: v[0],
        y: v[1],
        z: v[2],
    }
}

fn frd(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The IMU's readings (attitude, gyro rates, specific force) in ENU/FLU, in frame `frame`.
pub fn imu(o: &Observation, frame: &str) -> Imu {
    let (roll, pitch, yaw) = euler_rpy(&o.sensors.attitude);
    Imu {
        header: header(o.t, frame),
        orientation: quaternion(&enu::attitude(roll, pitch, yaw)),
        orientation_covariance: [0.0; 9],
        angular_velocity: vector(enu::body(frd(&o.sensors.gyro))),
        angular_velocity_covariance: [0.0; 9],
        linear_acceleration: vector(enu::body(frd(&o.sensors.accel))),
        linear_acceleration_covariance: [0.0; 9],
    }
}

/// The pressure sensor's reading as an absolute pressure: 101 325 Pa + ρ g · depth reading,
/// in frame `frame`.
pub fn pressure(o: &Observation, density: f64, gravity: f64, frame: &str) -> FluidPressure {
    FluidPressure {
        header: header(o.t, frame),
        fluid_pressure: SURFACE_PRESSURE_PA + density * gravity * o.sensors.depth,
        variance: 0.0,
    }
}

/// The true position (granted) with the IMU's attitude, as `Odometry` and a `/tf` transform
/// from `world` (ENU) to `frame`. The twist is not known to the bridge: its covariance's first
/// element is −1 ("no estimate").
pub fn odometry(o: &Observation, position: Vec3, frame: &str) -> (Odometry, TransformStamped) {
    let (roll, pitch, yaw) = euler_rpy(&o.sensors.attitude);
    let q = quaternion(&enu::attitude(roll, pitch, yaw));
    let p = enu::position(frd(&position));
    let mut twist_cov = [[0.0; 6]; 6];
    twist_cov[0][0] = -1.0;
    let odom = Odometry {
        header: header(o.t, "world"),
        child_frame_id: frame.to_string(),
        pose: PoseWithCovariance {
            pose: Pose {
                position: Point {
                    x: p[0],
                    y: p[1],
                    z: p[2],
                },
                orientation: q,
            },
            covariance: [[0.0; 6]; 6],
        },
        twist: TwistWithCovariance {
            twist: Twist::default(),
            covariance: twist_cov,
        },
    };
    let tf = TransformStamped {
        header: header(o.t, "world"),
        child_frame_id: frame.to_string(),
        transform: Transform {
            translation: vector(p),
            rotation: q,
        },
    };
    (odom, tf)
}

/// A received frame as `modem/rx` publishes it.
pub fn received(f: &Received) -> OpticalFrame {
    OpticalFrame {
        stamp: stamp(f.t),
        sender: f.from,
        seq: f.seq,
        modem: i32::try_from(f.modem).unwrap_or(i32::MAX),
        power: f.power,
        snr: f.snr,
        delay: 0.0,
        payload: f.payload.to_vec(),
    }
}

/// An agent's answer to a tick: setpoints or raw actuators, with the frames it sends.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// Controller setpoints.
    Setpoint(Setpoint, Vec<OpticalFrame>),
    /// Raw actuator commands.
    Actuators(Actuators, Vec<OpticalFrame>),
}

impl Answer {
    /// The tick it answers \[ns\].
    pub fn stamp_ns(&self) -> i64 {
        match self {
            Answer::Setpoint(s, _) => ns(s.stamp),
            Answer::Actuators(a, _) => ns(a.stamp),
        }
    }

    /// How many `modem/tx` frames go with it.
    pub fn frames(&self) -> u32 {
        match self {
            Answer::Setpoint(s, _) => s.frames,
            Answer::Actuators(a, _) => a.frames,
        }
    }

    /// Gives it its frames.
    pub fn attach_frames(&mut self, frames: Vec<OpticalFrame>) {
        match self {
            Answer::Setpoint(_, f) | Answer::Actuators(_, f) => *f = frames,
        }
    }

    /// The world command for vehicle `id`; an unknown mode or pump value rejects it and a
    /// modem index below [`ALL_MODEMS`] rejects the frame (counted in `rej`). Numbers are
    /// checked by [`shoal_sim::sim::Sim::command_vehicle`].
    pub fn into_command(self, id: u32, rej: &mut Rejections) -> Option<agents::Command> {
        let (order, frames) = match self {
            Answer::Setpoint(s, frames) => {
                let m = match s.mode {
                    mode::KEEP => None,
                    mode::OFF => Some(Mode::Off),
                    mode::DIVING => Some(Mode::Diving),
                    mode::BUOYANCY => Some(Mode::Buoyancy),
                    mode::TURNING => Some(Mode::Turning),
                    mode::DRIFT => Some(Mode::Drift),
                    mode::AUTO => Some(Mode::Auto),
                    _ => {
                        rej.invalid += 1;
                        return None;
                    }
                };
                let order = match m {
                    None => Order::Keep,
                    Some(mode) => Order::Mode {
                        mode,
                        depth: s.depth,
                        yaw: s.heading,
                        surge: s.surge,
                        sway: s.sway,
                    },
                };
                (order, frames)
            }
            Answer::Actuators(a, frames) => {
                let pump = match Pump::from_wire(a.pump.into()) {
                    Some(p) => p,
                    None => {
                        rej.invalid += 1;
                        return None;
                    }
                };
                let order = Order::Raw {
                    thrusters: a.thrusters,
                    tilts: a.tilts,
                    pump,
                };
                (order, frames)
            }
        };
        let mut orders = Vec::with_capacity(frames.len());
        for f in frames {
            let modem = match f.modem {
                ALL_MODEMS => None,
                m if m >= 0 => Some(m as usize),
                _ => {
                    rej.bad_frames += 1;
                    continue;
                }
            };
            orders.push(FrameOrder::broadcast(modem, f.payload, f.delay));
        }
        Some(agents::Command {
            id,
            order,
            frames: orders,
        })
    }
}
