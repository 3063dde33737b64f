//! The per-vehicle quantities ([`Quantity`]) and reading one of every vehicle into a flat
//! slice in a single query pass ([`Sim::read_f64`], [`Sim::read_i64`], [`Sim::read_bool`]).

use super::commands::mode_code;
use super::error::CommandError;
use crate::comm::{CommStats, Modems};
use crate::components::*;
use crate::sim::Sim;
use shoal_model::math::euler_rpy;

/// How many columns the per-actuator quantities have: the most any vehicle has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BatchShape {
    /// Vehicles.
    pub vehicles: usize,
    /// Most thrusters of any vehicle.
    pub thrusters: usize,
    /// Most tilt drives of any vehicle.
    pub tilts: usize,
    /// Most modems of any vehicle.
    pub modems: usize,
}

/// The element type of a [`Quantity`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// 64-bit float.
    F64,
    /// 64-bit signed integer.
    I64,
    /// Boolean.
    Bool,
}

/// A per-vehicle quantity readable for every vehicle at once. Per-actuator and per-modem
/// quantities have [`BatchShape`] columns, 0 (false) beyond a vehicle's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// True position of the body origin, world frame (north, east, down) \[m\].
    Position,
    /// True attitude quaternion body → world (w, x, y, z).
    Attitude,
    /// True roll, pitch, yaw \[rad\].
    Euler,
    /// Velocity relative to the water, body frame: u, v, w [m/s], p, q, r [rad/s].
    Velocity,
    /// Velocity over ground, world frame [m/s].
    WorldVelocity,
    /// Depth reading of the pressure sensor (quantised, noisy) \[m\].
    DepthReading,
    /// Roll, pitch, yaw from the IMU's attitude estimate \[rad\].
    ImuEuler,
    /// Body rates from the gyros [rad/s].
    Gyro,
    /// Specific force from the accelerometer, body frame [m/s²].
    Accel,
    /// Tilt angles from the potentiometers, per tilt drive \[rad\].
    TiltReading,
    /// The tank's full switch.
    TankFull,
    /// Actual thrust per thruster \[N\].
    Thrust,
    /// Actual tilt angle per tilt drive \[rad\].
    TiltAngle,
    /// Water in the buoyancy tank \[m³\].
    Ballast,
    /// Thruster commands in force [% of full scale].
    ThrusterCommand,
    /// Controller mode code ([`MODES`]; 6: raw).
    Mode,
    /// Setpoints in force: depth \[m\], heading \[rad\], surge \[N\], sway \[N\].
    Setpoint,
    /// Frames waiting in each modem's transmit queue.
    ModemQueued,
    /// Frames put on the air since the start.
    FramesSent,
    /// Frames delivered to the vehicle since the start.
    FramesReceived,
    /// Receptions lost since the start: to range or angle, occlusion, collision, half-duplex.
    FramesLost,
    /// Whether the hull touched a wall, the floor or an obstacle in the last step.
    Touching,
}

impl Quantity {
    /// Every quantity.
    pub const ALL: [Quantity; 22] = [
        Self::Position,
        Self::Attitude,
        Self::Euler,
        Self::Velocity,
        Self::WorldVelocity,
        Self::DepthReading,
        Self::ImuEuler,
        Self::Gyro,
        Self::Accel,
        Self::TiltReading,
        Self::TankFull,
        Self::Thrust,
        Self::TiltAngle,
        Self::Ballast,
        Self::ThrusterCommand,
        Self::Mode,
        Self::Setpoint,
        Self::ModemQueued,
        Self::FramesSent,
        Self::FramesReceived,
        Self::FramesLost,
        Self::Touching,
    ];

    /// Its name in bindings (snake case).
    pub fn name(self) -> &'static str {
        match self {
            Self::Position => "position",
            Self::Attitude => "attitude",
            Self::Euler => "euler",
            Self::Velocity => "velocity",
            Self::WorldVelocity => "world_velocity",
            Self::DepthReading => "depth_reading",
            Self::ImuEuler => "imu_euler",
            Self::Gyro => "gyro",
            Self::Accel => "accel",
            Self::TiltReading => "tilt_reading",
            Self::TankFull => "tank_full",
            Self::Thrust => "thrust",
            Self::TiltAngle => "tilt_angle",
            Self::Ballast => "ballast",
            Self::ThrusterCommand => "thruster_command",
            Self::Mode => "mode",
            Self::Setpoint => "setpoint",
            Self::ModemQueued => "modem_queued",
            Self::FramesSent => "frames_sent",
            Self::FramesReceived => "frames_received",
            Self::FramesLost => "frames_lost",
            Self::Touching => "touching",
        }
    }

    /// The quantity called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|q| q.name() == name)
    }

    /// Its element type.
    pub fn dtype(self) -> Dtype {
        match self {
            Self::TankFull | Self::Touching => Dtype::Bool,
            Self::Mode
            | Self::ModemQueued
            | Self::FramesSent
            | Self::FramesReceived
            | Self::FramesLost => Dtype::I64,
            _ => Dtype::F64,
        }
    }

    /// Columns per vehicle, `None` for a scalar per vehicle (a 1-D array).
    pub fn width(self, shape: &BatchShape) -> Option<usize> {
        match self {
            Self::Position
            | Self::Euler
            | Self::WorldVelocity
            | Self::ImuEuler
            | Self::Gyro
            | Self::Accel => Some(3),
            Self::Attitude | Self::Setpoint | Self::FramesLost => Some(4),
            Self::Velocity => Some(6),
            Self::TiltReading | Self::TiltAngle => Some(shape.tilts),
            Self::Thrust | Self::ThrusterCommand => Some(shape.thrusters),
            Self::ModemQueued => Some(shape.modems),
            Self::DepthReading
            | Self::TankFull
            | Self::Ballast
            | Self::Mode
            | Self::FramesSent
            | Self::FramesReceived
            | Self::Touching => None,
        }
    }
}

/// The world's [`BatchShape`], once worked out.
#[derive(bevy_ecs::prelude::Resource, Clone, Copy, Debug)]
struct ShapeCache(BatchShape);

/// Copies `xs` into the start of `row` (the rest stays 0).
fn put(row: &mut [f64], xs: &[f64]) {
    row[..xs.len()].copy_from_slice(xs);
}
impl Sim {
    /// The column counts of per-actuator and per-modem quantities (worked out once: a
    /// world's vehicles and their models do not change).
    pub fn batch_shape(&mut self) -> BatchShape {
        if let Some(s) = self.world().get_resource::<ShapeCache>() {
            return s.0;
        }
        let mut s = BatchShape {
            vehicles: self.len(),
            ..Default::default()
        };
        for v in self.fleet().as_slice() {
            let p = &v.model.params;
            s.thrusters = s.thrusters.max(p.thrusters.len());
            s.tilts = s.tilts.max(p.tilts.len());
            s.modems = s.modems.max(p.modems.len());
        }
        self.world_mut().insert_resource(ShapeCache(s));
        s
    }

    /// The shortest control period of any vehicle, in physics steps (1 for a world without
    /// vehicles): the step count of one control tick.
    pub fn control_steps(&mut self) -> u64 {
        self.fleet()
            .as_slice()
            .iter()
            .map(|v| v.control.every)
            .min()
            .unwrap_or(1)
    }

    /// Checks that `out` holds one row of `q` per vehicle; returns the row width.
    fn row_width(&mut self, q: Quantity, want: Dtype, len: usize) -> Result<usize, CommandError> {
        let shape = self.batch_shape();
        let w = q.width(&shape).unwrap_or(1);
        if q.dtype() != want {
            return Err(CommandError::field(
                q.name(),
                format!("is {:?}, not {want:?}", q.dtype()),
            ));
        }
        if len != w * shape.vehicles {
            return Err(CommandError::field(
                q.name(),
                format!(
                    "needs {} values ({} vehicles × {w}), got {len}",
                    w * shape.vehicles,
                    shape.vehicles
                ),
            ));
        }
        Ok(w)
    }

    /// Reads float quantity `q` of every vehicle into `out` (row-major, one row per vehicle
    /// in id order, zero beyond a vehicle's own actuators).
    pub fn read_f64(&mut self, q: Quantity, out: &mut [f64]) -> Result<(), CommandError> {
        let w = self.row_width(q, Dtype::F64, out.len())?;
        out.fill(0.0);
        let env = self.world().resource::<Physical>().env;
        for (id, v) in self.fleet().as_slice().iter().enumerate() {
            let row = &mut out[id * w..(id + 1) * w];
            let (p, s, c, a) = (&v.physics, &v.sensors, &v.control, &v.commands);
            let r = &p.state.rigid;
            match q {
                Quantity::Position => put(row, r.position.as_slice()),
                Quantity::Attitude => {
                    let v = r.attitude.coords;
                    put(row, &[v.w, v.x, v.y, v.z]);
                }
                Quantity::Euler => {
                    let (a, b, c) = euler_rpy(&r.attitude);
                    put(row, &[a, b, c]);
                }
                Quantity::Velocity => put(row, r.nu.as_slice()),
                Quantity::WorldVelocity => put(row, r.world_velocity(&env).as_slice()),
                Quantity::DepthReading => row[0] = s.depth,
                Quantity::ImuEuler => {
                    let (a, b, c) = euler_rpy(&s.attitude);
                    put(row, &[a, b, c]);
                }
                Quantity::Gyro => put(row, s.gyro.as_slice()),
                Quantity::Accel => put(row, s.accel.as_slice()),
                Quantity::TiltReading => put(row, &s.tilts),
                Quantity::Thrust => put(row, &p.state.actuators.thrust),
                Quantity::TiltAngle => put(row, &p.state.actuators.tilt),
                Quantity::Ballast => row[0] = p.state.ballast_volume,
                Quantity::ThrusterCommand => put(row, &a.thrusters),
                Quantity::Setpoint => {
                    let sp = &c.setpoints;
                    put(row, &[sp.depth, sp.yaw, sp.surge, sp.sway]);
                }
                _ => unreachable!("row_width checked the type"),
            }
        }
        Ok(())
    }

    /// Reads integer quantity `q` of every vehicle into `out` (see [`Self::read_f64`]).
    pub fn read_i64(&mut self, q: Quantity, out: &mut [i64]) -> Result<(), CommandError> {
        let w = self.row_width(q, Dtype::I64, out.len())?;
        out.fill(0);
        if matches!(q, Quantity::FramesReceived | Quantity::FramesLost) {
            // Reception counters are complete once the ledger is folded.
            self.fold_comm();
        }
        let mut query = self
            .world_mut()
            .query::<(&VehicleId, &Modems, &CommStats)>();
        let n = |x: u64| i64::try_from(x).unwrap_or(i64::MAX);
        let fleet = self.fleet();
        for (id, m, st) in query.iter(self.world()) {
            let c = &fleet.get(*id).control;
            let row = &mut out[id.0 as usize * w..(id.0 as usize + 1) * w];
            match q {
                Quantity::Mode => row[0] = mode_code(c.setpoints.mode),
                Quantity::ModemQueued => {
                    for (x, port) in row.iter_mut().zip(&m.ports) {
                        *x = port.queued() as i64;
                    }
                }
                Quantity::FramesSent => row[0] = n(st.sent),
                Quantity::FramesReceived => row[0] = n(st.rx.delivered),
                Quantity::FramesLost => {
                    let rx = &st.rx;
                    row.copy_from_slice(&[
                        n(rx.lost_range),
                        n(rx.lost_occlusion),
                        n(rx.lost_collision),
                        n(rx.lost_half_duplex),
                    ]);
                }
                _ => unreachable!("row_width checked the type"),
            }
        }
        Ok(())
    }

    /// Reads boolean quantity `q` of every vehicle into `out` (see [`Self::read_f64`]).
    pub fn read_bool(&mut self, q: Quantity, out: &mut [bool]) -> Result<(), CommandError> {
        self.row_width(q, Dtype::Bool, out.len())?;
        for (x, v) in out.iter_mut().zip(self.fleet().as_slice()) {
            let (s, c) = (&v.sensors, &v.contacts);
            *x = match q {
                Quantity::TankFull => s.tank_full,
                Quantity::Touching => c.touching,
                _ => unreachable!("row_width checked the type"),
            };
        }
        Ok(())
    }
}
