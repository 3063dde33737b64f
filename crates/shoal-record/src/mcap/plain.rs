//! shoal's own messages in `run.mcap`, as ROS 2 types of the package `shoal_msgs` in CDR with
//! their definitions in the file (so ROS 2 tools and `rosbags` decode them without the
//! package): `shoal_msgs/msg/VehicleState` (`/<vehicle>/state`: one recorded trajectory row,
//! its fields named like the columns of `trajectories.csv`, [`shoal_sim::recorder::FIXED`])
//! and `shoal_msgs/msg/ReceptionAttempt` (`/optical/frames`: one reception attempt). Each
//! field's comment in the definition gives its unit, so Foxglove's plots can be read without
//! this page.

use super::msgdef::MsgDef;
use crate::link_key::style;
use serde::ser::SerializeStruct;
use serde::{Deserialize, Serialize};
use shoal_sim::comm::Heard;
use shoal_sim::recorder::{FIXED, col, mode_of_code};

/// Name of the state's type.
pub const VEHICLE_STATE: &str = "shoal_msgs/msg/VehicleState";
/// Name of the attempt's type.
pub const RECEPTION_ATTEMPT: &str = "shoal_msgs/msg/ReceptionAttempt";

/// The definitions of shoal's two message types.
pub const DEFS: &[MsgDef] = &[
    MsgDef {
        name: VEHICLE_STATE,
        text: "# One recorded sample of a vehicle, as a row of trajectories.csv: the true state (NED world,
# FRD body), the depth sensor's reading, control mode, setpoints, ballast and the controller's
# demands. NaN: no value.
float64 t_s # simulated time [s]
float64 x_m # position north of the pool's corner (NED x) [m]
float64 y_m # position east of the pool's corner (NED y) [m]
float64 z_m # depth of the body origin below the surface (NED z) [m]
float64 roll_rad # roll, NED/FRD ZYX Euler angle [rad]
float64 pitch_rad # pitch, NED/FRD ZYX Euler angle, nose up positive [rad]
float64 yaw_rad # heading, NED/FRD ZYX Euler angle, 0 north, pi/2 east [rad]
float64 u_m_s # surge velocity through the water, body x forward [m/s]
float64 v_m_s # sway velocity through the water, body y starboard [m/s]
float64 w_m_s # heave velocity through the water, body z down [m/s]
float64 p_rad_s # roll rate about body x (FRD) [rad/s]
float64 q_rad_s # pitch rate about body y (FRD) [rad/s]
float64 r_rad_s # yaw rate about body z (FRD) [rad/s]
float64 depth_reading_m # the pressure sensor's depth reading (noise and quantisation included) [m]
float64 ballast_m3 # ballast water in the tank [m^3]
float64 pump # pump command: -1 out, 0 off, 1 in [dimensionless]
string mode # control mode (name)
float64 depth_setpoint_m # depth setpoint [m]
float64 yaw_setpoint_rad # heading setpoint [rad]
float64 heave_force_n # vertical force the controller demands [N]
float64 yaw_torque_nm # yaw torque the controller demands [N m]
float64 in_contact # 1 while touching a wall, the floor or an obstacle, else 0 [dimensionless]
",
        uses: &[],
    },
    MsgDef {
        name: RECEPTION_ATTEMPT,
        text: "# One reception attempt of an optical frame: a sender's frame at one receiver, and its outcome.
float64 t_s # end of the frame, when the outcome was decided (simulated time) [s]
string sender # sending vehicle's name
string receiver # receiving vehicle's name
uint32 sender_id # sending vehicle's id (index in the world) [count]
uint32 receiver_id # receiving vehicle's id [count]
string outcome # delivered, collided, occluded, out of budget or half-duplex
uint32 bytes # payload length, without the link-layer header [bytes]
bool ack # whether the frame was an acknowledgement (the link layer's answer to a unicast it received)
",
        uses: &[],
    },
];

/// A recorded row's fixed columns as a `shoal_msgs/msg/VehicleState` (the mode by name).
pub struct VehicleState<'a>(pub &'a [f64]);

impl Serialize for VehicleState<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("VehicleState", FIXED.len())?;
        for (j, name) in FIXED.iter().enumerate() {
            let x = self.0.get(j).copied().unwrap_or(f64::NAN);
            if j == col::MODE {
                m.serialize_field(name, mode_of_code(x).name())?;
            } else {
                m.serialize_field(name, &x)?;
            }
        }
        m.end()
    }
}

/// `shoal_msgs/msg/ReceptionAttempt`: one reception attempt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReceptionAttempt {
    /// End of the frame (simulated time) \[s\].
    pub t_s: f64,
    /// Sending vehicle's name.
    pub sender: String,
    /// Receiving vehicle's name.
    pub receiver: String,
    /// Sending vehicle's id \[count\].
    pub sender_id: u32,
    /// Receiving vehicle's id \[count\].
    pub receiver_id: u32,
    /// The outcome's label in the shared key ([`crate::link_key`]).
    pub outcome: String,
    /// Payload length \[bytes\].
    pub bytes: u32,
    /// Whether the frame was an acknowledgement.
    pub ack: bool,
}

impl ReceptionAttempt {
    /// The message of attempt `h`; `names` are the vehicles' names by id.
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
            ack: h.ack,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link_key::LINK_KEY;

    /// The fields a definition declares: (type, name, comment).
    fn fields(text: &str) -> Vec<(&str, &str, &str)> {
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| {
                let (decl, comment) = l.split_once(" # ").unwrap_or((l, ""));
                let (ty, name) = decl.split_once(' ').unwrap();
                (ty, name, comment)
            })
            .collect()
    }

    #[test]
    fn every_column_is_a_field_in_order_with_its_unit() {
        let f = fields(DEFS[0].text);
        let names: Vec<&str> = f.iter().map(|x| x.1).collect();
        assert_eq!(names, FIXED);
        for (ty, name, what) in f {
            assert_eq!(ty == "string", name == "mode", "{name}: {ty}");
            // Every number's comment ends with its unit in brackets.
            assert!(
                name == "mode" || (what.contains(" [") && what.ends_with(']')),
                "{name}: {what}"
            );
        }
    }

    #[test]
    fn a_row_encodes_as_its_columns_in_order() {
        let mut row = vec![0.0; FIXED.len()];
        row[col::X] = 1.5;
        row[col::MODE] = shoal_sim::recorder::mode_code(shoal_model::control::Mode::Auto);
        row[col::DEPTH_SP] = f64::NAN;
        let b = super::super::ros2::encode(&VehicleState(&row)).unwrap();
        let f64_at = |k: usize| f64::from_le_bytes(b[4 + 8 * k..12 + 8 * k].try_into().unwrap());
        assert_eq!(f64_at(col::X), 1.5);
        // 16 float64, then the mode as a CDR string ("auto" and its NUL after a u32 length),
        // then the rest aligned to 8 again.
        let s = 4 + 8 * col::MODE;
        assert_eq!(&b[s..s + 4], &5u32.to_le_bytes());
        assert_eq!(&b[s + 4..s + 9], b"auto\0");
        let rest = (s + 9 - 4).next_multiple_of(8) + 4;
        assert!(f64::from_le_bytes(b[rest..rest + 8].try_into().unwrap()).is_nan());
        assert_eq!(b.len(), rest + 8 * (FIXED.len() - col::MODE - 1));
    }

    #[test]
    fn the_attempt_names_each_outcome_as_the_key_does() {
        let text = DEFS[1].text;
        for s in LINK_KEY {
            assert!(text.contains(s.label), "{}", s.label);
        }
        let names: Vec<&str> = fields(text).iter().map(|x| x.1).collect();
        assert_eq!(
            names,
            [
                "t_s",
                "sender",
                "receiver",
                "sender_id",
                "receiver_id",
                "outcome",
                "bytes",
                "ack"
            ]
        );
    }
}
