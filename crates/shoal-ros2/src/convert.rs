//! Between the world and ROS 2's messages: observations as `Imu`, `FluidPressure`,
//! `Odometry` and `/tf` in ROS's axes (ENU world, FLU body, REP 103 — the conversions of
//! `run.mcap`, [`shoal_model::frames`]), received frames as `OpticalFrame` and the ends of
//! acknowledged unicasts as `FrameOutcome`, with vehicles by their ROS names ([`Names`]), and
//! an agent's `Setpoint` or `Actuators` with its `modem/tx` frames as a world command.

use crate::msgs::{
    self, ALL_MODEMS, Actuators, FluidPressure, Header, Imu, Odometry, OpticalFrame, Point, Pose,
    PoseWithCovariance, Quaternion, Setpoint, Time, Transform, TransformStamped, Twist,
    TwistWithCovariance, Vector3, mode, stamp,
};
use crate::names::Names;
use shoal_model::ballast::Pump;
use shoal_model::control::Mode;
use shoal_model::frames as enu;
use shoal_model::math::{Quat, Vec3, euler_rpy};
use shoal_record::mcap::ros2::SURFACE_PRESSURE_PA;
use shoal_sim::agents::{self, Observation, Order, Rejections};
use shoal_sim::comm::{FrameEvent, FrameOutcome, Received};
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

/// A frame received by vehicle `me` (its ROS name) as its `modem/rx` publishes it: the
/// sender by name, `to` = `me` for a unicast (only its destination receives one), empty for a
/// broadcast.
pub fn received(f: &Received, me: &str, names: &Names) -> OpticalFrame {
    OpticalFrame {
        stamp: stamp(f.t),
        sender: names.name(f.from).to_string(),
        to: if f.unicast {
            me.to_string()
        } else {
            String::new()
        },
        ack: false,
        tag: 0,
        seq: f.seq,
        modem: i32::try_from(f.modem).unwrap_or(i32::MAX),
        power: f.power,
        snr: f.snr,
        delay: 0.0,
        payload: f.payload.to_vec(),
    }
}

/// The end of an acknowledged unicast as its sender's `modem/outcome` publishes it.
pub fn outcome(e: &FrameEvent, names: &Names) -> msgs::FrameOutcome {
    msgs::FrameOutcome {
        stamp: stamp(e.t),
        to: names.name(e.to).to_string(),
        tag: e.tag,
        seq: e.seq,
        transmissions: e.transmissions,
        acknowledged: match e.outcome {
            FrameOutcome::Acknowledged => true,
            FrameOutcome::GaveUp => false,
        },
        sent: stamp(e.sent),
    }
}

/// A `modem/tx` frame as the world's order: `None` (a bad frame) for a modem index below
/// [`ALL_MODEMS`] or a destination that is no vehicle's ROS name (empty: a broadcast). The
/// rest (payload, destination, `ack` without one) is checked by
/// [`shoal_sim::orders::check_frame`].
pub fn frame_order(f: OpticalFrame, names: &Names) -> Option<FrameOrder> {
    let modem = match f.modem {
        ALL_MODEMS => None,
        m => Some(usize::try_from(m).ok()?),
    };
    let to = match f.to.as_str() {
        "" => None,
        name => Some(names.id(name)?),
    };
    Some(FrameOrder {
        modem,
        payload: f.payload,
        delay: f.delay,
        to,
        ack: f.ack,
        tag: f.tag,
    })
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
    /// frame that [`frame_order`] refuses is dropped (counted in `rej`). Numbers, and the
    /// frames' payloads and destinations, are checked by
    /// [`shoal_sim::sim::Sim::command_vehicle`].
    pub fn into_command(
        self,
        id: u32,
        names: &Names,
        rej: &mut Rejections,
    ) -> Option<agents::Command> {
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
            match frame_order(f, names) {
                Some(o) => orders.push(o),
                None => rej.bad_frames += 1,
            }
        }
        Some(agents::Command {
            id,
            order,
            frames: orders,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn names() -> Names {
        Names::new(["auv-0", "auv-1", "beacon"], "pool").unwrap()
    }

    fn tx(to: &str, ack: bool, modem: i32) -> OpticalFrame {
        OpticalFrame {
            to: to.into(),
            ack,
            tag: 42,
            modem,
            delay: 0.01,
            payload: vec![1, 2],
            ..Default::default()
        }
    }

    #[test]
    fn a_tx_frame_names_its_destination_by_ros_name_and_keeps_ack_and_tag() {
        let n = names();
        let o = frame_order(tx("beacon", true, 1), &n).unwrap();
        assert_eq!(
            (o.modem, o.to, o.ack, o.tag, o.delay, o.payload),
            (Some(1), Some(2), true, 42, 0.01, vec![1, 2])
        );
        let b = frame_order(tx("", false, ALL_MODEMS), &n).unwrap();
        let want = FrameOrder {
            tag: 42,
            ..FrameOrder::broadcast(None, vec![1, 2], 0.01)
        };
        assert_eq!(b, want);
        // Not a vehicle's ROS name (the world's spelling `auv-1` included), or a modem below
        // ALL_MODEMS: a bad frame.
        for f in [
            tx("nobody", true, 0),
            tx("auv-1", false, 0),
            tx("auv_1", false, -2),
        ] {
            assert_eq!(frame_order(f, &n), None);
        }
    }

    #[test]
    fn bad_frames_are_counted_and_the_command_goes_on() {
        let a = Answer::Setpoint(
            Setpoint::default(),
            vec![tx("auv_1", true, 0), tx("nobody", true, 0)],
        );
        let mut rej = Rejections::default();
        let cmd = a.into_command(0, &names(), &mut rej).unwrap();
        assert_eq!(rej.bad_frames, 1);
        assert_eq!(cmd.frames.len(), 1);
        assert_eq!((cmd.frames[0].to, cmd.frames[0].ack), (Some(1), true));
    }

    #[test]
    fn rx_names_the_sender_and_a_unicast_its_destination() {
        let n = names();
        let mut f = Received {
            t: 1.5,
            from: 2,
            seq: 9,
            modem: 0,
            power: 1e-7,
            snr: 30.0,
            sent: 1.49,
            payload: Arc::from(&b"hi"[..]),
            unicast: true,
        };
        let m = received(&f, "auv_0", &n);
        assert_eq!(
            (m.stamp, m.sender.as_str(), m.to.as_str(), m.seq, m.payload),
            (stamp(1.5), "beacon", "auv_0", 9, b"hi".to_vec())
        );
        f.unicast = false;
        assert_eq!(received(&f, "auv_0", &n).to, "");
    }

    #[test]
    fn an_outcome_names_its_destination() {
        let e = FrameEvent {
            t: 2.25,
            to: 1,
            seq: 4,
            tag: 7,
            payload: Arc::from(&b"x"[..]),
            sent: 2.0,
            transmissions: 3,
            outcome: FrameOutcome::GaveUp,
        };
        let m = outcome(&e, &names());
        assert_eq!(
            m,
            msgs::FrameOutcome {
                stamp: stamp(2.25),
                to: "auv_1".into(),
                tag: 7,
                seq: 4,
                transmissions: 3,
                acknowledged: false,
                sent: stamp(2.0),
            }
        );
        let ok = FrameEvent {
            outcome: FrameOutcome::Acknowledged,
            ..e
        };
        assert!(outcome(&ok, &names()).acknowledged);
    }
}
