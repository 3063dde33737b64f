//! Trajectory rows: a flat `f64` layout per vehicle kind, appended by the record system and
//! drained in batches by the run driver (so memory stays bounded on long runs).

use crate::components::{ContactStats, Control};
use shoal_model::control::Mode;
use shoal_model::prelude::*;

/// Fixed columns of every row, with units in their names (SI; angles in radians).
pub const FIXED: [&str; 22] = [
    "t_s",
    "x_m",
    "y_m",
    "z_m",
    "roll_rad",
    "pitch_rad",
    "yaw_rad",
    "u_m_s",
    "v_m_s",
    "w_m_s",
    "p_rad_s",
    "q_rad_s",
    "r_rad_s",
    "depth_reading_m",
    "ballast_m3",
    "pump",
    "mode",
    "depth_setpoint_m",
    "yaw_setpoint_rad",
    "heave_force_n",
    "yaw_torque_nm",
    "in_contact",
];

/// Index of a fixed column.
pub mod col {
    #![allow(missing_docs)]
    pub const T: usize = 0;
    pub const X: usize = 1;
    pub const Y: usize = 2;
    pub const Z: usize = 3;
    pub const ROLL: usize = 4;
    pub const PITCH: usize = 5;
    pub const YAW: usize = 6;
    pub const U: usize = 7;
    pub const V: usize = 8;
    pub const W: usize = 9;
    pub const P: usize = 10;
    pub const Q: usize = 11;
    pub const R: usize = 12;
    pub const DEPTH_READING: usize = 13;
    pub const BALLAST: usize = 14;
    pub const PUMP: usize = 15;
    pub const MODE: usize = 16;
    pub const DEPTH_SP: usize = 17;
    pub const YAW_SP: usize = 18;
    pub const HEAVE_FORCE: usize = 19;
    pub const YAW_TORQUE: usize = 20;
    pub const CONTACT: usize = 21;
}

/// Values per row for a vehicle kind: the fixed columns, one command per thruster [%], one
/// angle per tilt drive \[rad\] and one commanded angle per tilt drive \[rad\].
pub fn stride(model: &VehicleModel) -> usize {
    FIXED.len() + model.params.thrusters.len() + 2 * model.params.tilts.len()
}

/// Column names of a kind's rows.
pub fn columns(model: &VehicleModel) -> Vec<String> {
    let mut c: Vec<String> = FIXED.iter().map(|s| s.to_string()).collect();
    c.extend(
        model
            .params
            .thrusters
            .iter()
            .map(|t| format!("cmd_{}_pct", t.name)),
    );
    c.extend(
        model
            .params
            .tilts
            .iter()
            .map(|t| format!("tilt_{}_rad", t.name)),
    );
    c.extend(
        model
            .params
            .tilts
            .iter()
            .map(|t| format!("cmd_{}_rad", t.name)),
    );
    c
}

/// Numeric code of a mode in rows (its index in [`Mode::ALL`]).
pub fn mode_code(m: Mode) -> f64 {
    Mode::ALL.iter().position(|x| *x == m).unwrap_or(0) as f64
}

/// The mode of a numeric code.
pub fn mode_of_code(c: f64) -> Mode {
    Mode::ALL.get(c as usize).copied().unwrap_or(Mode::Off)
}

/// Appends one row to `out`.
pub fn push_row(
    out: &mut Vec<f64>,
    t: f64,
    model: &VehicleModel,
    st: &VehicleState,
    sensors: &SensorReadings,
    control: &Control,
    cmd: &ActuatorCommands,
    contacts: &ContactStats,
) {
    out.reserve(stride(model));
    let r = &st.rigid;
    let (roll, pitch, yaw) = r.attitude.euler_angles();
    out.extend_from_slice(&[
        t,
        r.position.x,
        r.position.y,
        r.position.z,
        roll,
        pitch,
        yaw,
    ]);
    out.extend(r.nu.iter().copied());
    out.extend_from_slice(&[
        sensors.depth,
        st.ballast_volume,
        cmd.pump.sign(),
        mode_code(control.setpoints.mode),
        control.setpoints.depth,
        control.setpoints.yaw,
        control.state.heave_force,
        control.state.yaw_torque,
        if contacts.touching { 1.0 } else { 0.0 },
    ]);
    let n = model.params.thrusters.len();
    out.extend((0..n).map(|i| cmd.thrusters.get(i).copied().unwrap_or(0.0)));
    out.extend(st.actuators.tilt.iter().copied());
    let k = model.params.tilts.len();
    out.extend((0..k).map(|i| cmd.tilts.get(i).copied().unwrap_or(0.0)));
}

/// Rows drained from every vehicle, in vehicle-id order, and the reception attempts of the
/// same steps.
#[derive(Clone, Debug, Default)]
pub struct RecordBatch {
    /// Per vehicle (index = vehicle id): its flat rows.
    pub rows: Vec<Vec<f64>>,
    /// Every reception attempt decided since the last drain, in the order the medium decided
    /// them — only when the world logs them for the run driver (a world whose
    /// `[output] mcap` is on, [`crate::sim::Sim::new`]); empty otherwise.
    pub frames: Vec<crate::comm::Heard>,
}
