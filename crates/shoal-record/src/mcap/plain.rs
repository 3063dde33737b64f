//! The plain-number messages of `run.mcap`, in JSON with JSON Schemas of shoal's own:
//! `shoal.VehicleState` (`/<vehicle>/state`: one recorded trajectory row, its fields named
//! like the columns of `trajectories.csv`, [`shoal_sim::recorder::FIXED`]) and
//! `shoal.OpticalFrame` (`/optical/frames`: one reception attempt). Each schema field's
//! description gives its unit, so Foxglove's plots can be read without this page.

use shoal_sim::comm::Heard;
use crate::link_key::{LINK_KEY, style};
use shoal_sim::recorder::{FIXED, col, mode_of_code};
use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

/// What each column of a trajectory row means, with its unit, in [`FIXED`] order (a test
/// keeps the two in step).
const STATE_FIELDS: [(&str, &str); 22] = [
    ("t_s", "simulated time [s]"),
    ("x_m", "position north of the pool's corner (NED x) [m]"),
    ("y_m", "position east of the pool's corner (NED y) [m]"),
    (
        "z_m",
        "depth of the body origin below the surface (NED z) [m]",
    ),
    ("roll_rad", "roll, NED/FRD ZYX Euler angle [rad]"),
    (
        "pitch_rad",
        "pitch, NED/FRD ZYX Euler angle, nose up positive [rad]",
    ),
    (
        "yaw_rad",
        "heading, NED/FRD ZYX Euler angle, 0 north, π/2 east [rad]",
    ),
    (
        "u_m_s",
        "surge velocity through the water, body x forward [m/s]",
    ),
    (
        "v_m_s",
        "sway velocity through the water, body y starboard [m/s]",
    ),
    (
        "w_m_s",
        "heave velocity through the water, body z down [m/s]",
    ),
    ("p_rad_s", "roll rate about body x (FRD) [rad/s]"),
    ("q_rad_s", "pitch rate about body y (FRD) [rad/s]"),
    ("r_rad_s", "yaw rate about body z (FRD) [rad/s]"),
    (
        "depth_reading_m",
        "the pressure sensor's depth reading (noise and quantisation included) [m]",
    ),
    ("ballast_m3", "ballast water in the tank [m³]"),
    ("pump", "pump command: -1 out, 0 off, 1 in [dimensionless]"),
    ("mode", "control mode (name)"),
    ("depth_setpoint_m", "depth setpoint [m]"),
    ("yaw_setpoint_rad", "heading setpoint [rad]"),
    ("heave_force_n", "vertical force the controller demands [N]"),
    ("yaw_torque_nm", "yaw torque the controller demands [N·m]"),
    (
        "in_contact",
        "1 while touching a wall, the floor or an obstacle, else 0 [dimensionless]",
    ),
];

/// One trajectory row (its fixed columns) as a `shoal.VehicleState` message: an object with
/// a field per column of [`FIXED`]; `mode` by name, numbers that are not finite as `null`.
pub struct VehicleState<'a>(pub &'a [f64]);

impl Serialize for VehicleState<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(FIXED.len()))?;
        for (j, name) in FIXED.iter().enumerate() {
            let x = self.0.get(j).copied().unwrap_or(f64::NAN);
            if j == col::MODE {
                m.serialize_entry(name, mode_of_code(x).name())?;
            } else if x.is_finite() {
                m.serialize_entry(name, &x)?;
            } else {
                m.serialize_entry(name, &())?;
            }
        }
        m.end()
    }
}

/// The JSON Schema of `shoal.VehicleState`.
pub fn vehicle_state_schema() -> Value {
    let mut props = serde_json::Map::new();
    for (name, what) in STATE_FIELDS {
        let kind = if name == "mode" {
            json!("string")
        } else {
            json!(["number", "null"])
        };
        props.insert(name.into(), json!({ "type": kind, "description": what }));
    }
    json!({
        "title": "shoal.VehicleState",
        "description": "One recorded sample of a vehicle, as a row of trajectories.csv: the true state (NED world, FRD body), the depth sensor's reading, control mode, setpoints, ballast and the controller's demands. null: not a finite number.",
        "type": "object",
        "properties": props,
        "required": FIXED,
    })
}

/// One reception attempt as a `shoal.OpticalFrame` message.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OpticalFrame {
    /// End of the frame, when the receiver's outcome was decided \[s\].
    pub t_s: f64,
    /// Sending vehicle's name.
    pub sender: String,
    /// Receiving vehicle's name.
    pub receiver: String,
    /// Sending vehicle's id (its index in the world) \[count\].
    pub sender_id: u32,
    /// Receiving vehicle's id \[count\].
    pub receiver_id: u32,
    /// What happened: a label of [`crate::link_key::LINK_KEY`].
    pub outcome: String,
    /// Payload length \[bytes\].
    pub bytes: u32,
}

impl OpticalFrame {
    /// The message of attempt `h`, with the vehicles' `names`.
    pub fn of(h: &Heard, names: &[String]) -> Self {
        let name = |i: u32| names.get(i as usize).cloned().unwrap_or_default();
        Self {
            t_s: h.t,
            sender: name(h.from),
            receiver: name(h.to),
            sender_id: h.from,
            receiver_id: h.to,
            outcome: style(h.outcome).label.to_string(),
            bytes: h.bytes,
        }
    }
}

/// The JSON Schema of `shoal.OpticalFrame`.
pub fn optical_frame_schema() -> Value {
    let outcomes: Vec<&str> = LINK_KEY.iter().map(|s| s.label).collect();
    json!({
        "title": "shoal.OpticalFrame",
        "description": "One reception attempt of an optical frame: a sender's frame at one receiver, and its outcome.",
        "type": "object",
        "properties": {
            "t_s": { "type": "number", "description": "end of the frame, when the outcome was decided (simulated time) [s]" },
            "sender": { "type": "string", "description": "sending vehicle's name" },
            "receiver": { "type": "string", "description": "receiving vehicle's name" },
            "sender_id": { "type": "integer", "minimum": 0, "description": "sending vehicle's id (index in the world) [count]" },
            "receiver_id": { "type": "integer", "minimum": 0, "description": "receiving vehicle's id [count]" },
            "outcome": { "type": "string", "enum": outcomes, "description": "delivered, or why it was lost" },
            "bytes": { "type": "integer", "minimum": 0, "description": "payload length, without the link-layer header [bytes]" },
        },
        "required": ["t_s", "sender", "receiver", "sender_id", "receiver_id", "outcome", "bytes"],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_column_has_a_described_field_with_its_unit() {
        let names: Vec<&str> = STATE_FIELDS.iter().map(|f| f.0).collect();
        assert_eq!(names, FIXED);
        for (name, what) in STATE_FIELDS {
            // Every number's description ends with its unit in brackets.
            assert!(
                name == "mode" || (what.contains(" [") && what.ends_with(']')),
                "{name}: {what}"
            );
        }
    }

    #[test]
    fn a_row_is_an_object_of_its_columns() {
        let mut row = vec![0.0; FIXED.len()];
        row[col::X] = 1.5;
        row[col::MODE] = shoal_sim::recorder::mode_code(shoal_model::control::Mode::Auto);
        row[col::DEPTH_SP] = f64::NAN;
        let v = serde_json::to_value(VehicleState(&row)).unwrap();
        assert_eq!(v["x_m"], 1.5);
        assert_eq!(v["mode"], "auto");
        assert!(v["depth_setpoint_m"].is_null());
        assert_eq!(v.as_object().unwrap().len(), FIXED.len());
    }
}
