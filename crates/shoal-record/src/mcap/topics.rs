//! The topics of one vehicle in `run.mcap` and the messages of one recorded sample on them:
//! `/<vehicle>/state` ([`super::plain::VehicleState`]), `/<vehicle>/pressure`,
//! `/<vehicle>/imu`, `/<vehicle>/thrusters`, `/<vehicle>/tilts` (the commanded angles),
//! `/<vehicle>/tilt_angles` (the drives' angles) and `/<vehicle>/pump` (ROS 2
//! messages in CDR, [`super::ros2`]), each sample's values read from its trajectory row
//! ([`shoal_sim::recorder`]).

use super::file::McapFile;
use super::plain::VehicleState;
use super::ros2::{
    self, Float64MultiArray, FluidPressure, Header, Imu, Quaternion, SURFACE_PRESSURE_PA, Vector3,
};
use shoal_model::frames as enu;
use shoal_model::prelude::*;
use shoal_output::files::FileError;
use shoal_sim::recorder::{FIXED, col};

/// The schemas the vehicles' topics share (ids in the file).
#[derive(Clone, Copy, Debug)]
pub struct Schemas {
    /// `shoal_msgs/msg/VehicleState`.
    pub state: u16,
    /// `sensor_msgs/msg/FluidPressure` (ros2msg).
    pub pressure: u16,
    /// `sensor_msgs/msg/Imu` (ros2msg).
    pub imu: u16,
    /// `std_msgs/msg/Float64MultiArray` (ros2msg).
    pub array: u16,
}

impl Schemas {
    /// Adds the schemas to `file`.
    pub fn add(file: &mut McapFile) -> Result<Self, FileError> {
        Ok(Self {
            state: file.ros2_schema(super::plain::VEHICLE_STATE)?,
            pressure: file.ros2_schema("sensor_msgs/msg/FluidPressure")?,
            imu: file.ros2_schema("sensor_msgs/msg/Imu")?,
            array: file.ros2_schema("std_msgs/msg/Float64MultiArray")?,
        })
    }
}

/// One vehicle's topics.
pub struct VehicleTopics {
    name: String,
    /// Channels: state, pressure, IMU, thrusters, tilts, tilt angles, pump.
    channels: [u16; 7],
    /// The thrusters' names, comma-separated (the label of the array's dimension).
    thrusters: String,
    /// The tilt drives' names, comma-separated.
    tilts: String,
    /// Thrusters \[count\].
    n_thrusters: usize,
    /// Tilt drives \[count\].
    n_tilts: usize,
    /// Water density \[kg/m³\] times gravity \[m/s²\]: pressure per metre of depth \[Pa/m\].
    rho_g: f64,
}

/// The last part of each topic's name, in the order of [`VehicleTopics::channels`].
pub const TOPICS: [&str; 7] = [
    "state",
    "pressure",
    "imu",
    "thrusters",
    "tilts",
    "tilt_angles",
    "pump",
];

impl VehicleTopics {
    /// Adds the topics of vehicle `id` named `name` with `model` to `file`; `env` gives the
    /// water's density and gravity for the pressure.
    pub fn add(
        file: &mut McapFile,
        schemas: &Schemas,
        id: usize,
        name: &str,
        model: &VehicleModel,
        env: &Environment,
    ) -> Result<Self, FileError> {
        let s = schemas;
        let kinds = [
            s.state, s.pressure, s.imu, s.array, s.array, s.array, s.array,
        ];
        // The id keeps two vehicles of the same name on channels of their own.
        let meta = [
            ("vehicle", name.to_string()),
            ("vehicle_id", id.to_string()),
        ];
        let mut channels = [0u16; 7];
        for ((c, schema), topic) in channels.iter_mut().zip(kinds).zip(TOPICS) {
            *c = file.channel(schema, &format!("/{name}/{topic}"), false, &meta)?;
        }
        let p = &model.params;
        let join = |names: Vec<&str>| names.join(",");
        Ok(Self {
            name: name.to_string(),
            channels,
            thrusters: join(p.thrusters.iter().map(|t| t.name.as_str()).collect()),
            tilts: join(p.tilts.iter().map(|t| t.name.as_str()).collect()),
            n_thrusters: p.thrusters.len(),
            n_tilts: p.tilts.len(),
            rho_g: env.density * env.gravity,
        })
    }

    /// Writes what the vehicle is and measures at the sample `row` (a trajectory row of this
    /// vehicle) at `ns` nanoseconds: its state, pressure, IMU and the drives' tilt angles.
    pub fn write_state(&self, file: &mut McapFile, row: &[f64], ns: u64) -> Result<(), FileError> {
        let [state, pressure, imu, _, _, angles, _] = self.channels;
        file.write_cdr(state, ns, &VehicleState(&row[..FIXED.len()]))?;
        let header = Header {
            stamp: ros2::Time::from_ns(ns),
            frame_id: self.name.clone(),
        };
        file.write_cdr(pressure, ns, &self.pressure(header.clone(), row))?;
        file.write_cdr(imu, ns, &imu_of(header, row))?;
        let (_, angle, _) = self.actuators(row);
        let data = Float64MultiArray::vector(&self.tilts, angle.to_vec());
        file.write_cdr(angles, ns, &data)
    }

    /// Writes the commands `row` holds (thrusters, tilts, pump) at `ns` nanoseconds: the
    /// commands in force over the interval that ends at `row`'s time, written at its start,
    /// as a logger records a command when it is sent.
    pub fn write_commands(
        &self,
        file: &mut McapFile,
        row: &[f64],
        ns: u64,
    ) -> Result<(), FileError> {
        let [_, _, _, thrusters, tilts, _, pump] = self.channels;
        let (thr, _, commanded) = self.actuators(row);
        for (channel, label, data) in [
            (thrusters, self.thrusters.as_str(), thr.to_vec()),
            (tilts, self.tilts.as_str(), commanded.to_vec()),
            (pump, "pump", vec![row[col::PUMP]]),
        ] {
            file.write_cdr(channel, ns, &Float64MultiArray::vector(label, data))?;
        }
        Ok(())
    }

    /// A row's thruster commands, tilt angles and tilt commands.
    fn actuators<'r>(&self, row: &'r [f64]) -> (&'r [f64], &'r [f64], &'r [f64]) {
        let (thr, rest) =
            row[FIXED.len()..].split_at(self.n_thrusters.min(row.len() - FIXED.len()));
        let (angle, commanded) = rest.split_at(self.n_tilts.min(rest.len()));
        (thr, angle, commanded)
    }

    /// The pressure at the sensor: the surface's plus ρ g times the depth reading \[Pa\].
    fn pressure(&self, header: Header, row: &[f64]) -> FluidPressure {
        FluidPressure {
            header,
            fluid_pressure: SURFACE_PRESSURE_PA + self.rho_g * row[col::DEPTH_READING],
            variance: 0.0,
        }
    }
}

/// The IMU message of a trajectory row: the true attitude and body rates (the recorder keeps
/// no IMU readings) in ENU/FLU; no acceleration (covariance element 0 = −1).
pub fn imu_of(header: Header, row: &[f64]) -> Imu {
    let q = enu::attitude(row[col::ROLL], row[col::PITCH], row[col::YAW]);
    let q = q.quaternion();
    let [p, q_, r] = enu::body([row[col::P], row[col::Q], row[col::R]]);
    let mut no_estimate = [0.0; 9];
    no_estimate[0] = -1.0;
    Imu {
        header,
        orientation: Quaternion {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        },
        orientation_covariance: [0.0; 9],
        angular_velocity: Vector3 { x: p, y: q_, z: r },
        angular_velocity_covariance: [0.0; 9],
        linear_acceleration: Vector3::default(),
        linear_acceleration_covariance: no_estimate,
    }
}
