//! shoal's frames and the ones Foxglove and ROS expect, both ways, written out once (the
//! recorder's `run.mcap`, the ROS 2 bridge and the rosbag2 reader all convert here).
//!
//! shoal's world frame is **NED** (x north, y east, z down, origin at the pool's corner on the
//! surface) and its body frame **FRD** (x forward, y starboard, z down); attitudes are ZYX
//! Euler angles roll, pitch, yaw in them. Foxglove's 3D panel is z-up, and ROS (REP 103)
//! uses **ENU** world frames (x east, y north, z up) and **FLU** body frames (x forward,
//! y port, z up):
//!
//! * position: `(x, y, z)_ENU = (y, x, −z)_NED` — east, north, up; the surface is z = 0, the
//!   pool's floor `z = −depth`;
//! * attitude: `roll_ENU = roll`, `pitch_ENU = −pitch`, `yaw_ENU = π/2 − yaw` (heading north
//!   is `yaw_ENU = π/2`), which is `R_ENU←NED · R(roll, pitch, yaw) · R_FRD←FLU`;
//! * body rates: `(p, −q, −r)`; body velocities `(u, −v, −w)`.
//!
//! Every conversion is its own inverse but the attitude's: [`attitude_to_ned`] undoes
//! [`attitude`].

use crate::math::{Quat, Vec3, wrap_pi};
use std::f64::consts::FRAC_PI_2;

/// A NED position \[m\] in ENU \[m\]: east, north, up.
pub fn position(ned: [f64; 3]) -> [f64; 3] {
    [ned[1], ned[0], -ned[2]]
}

/// The FLU-body-to-ENU-world attitude of a body whose FRD-to-NED attitude has the ZYX Euler
/// angles `roll`, `pitch`, `yaw` \[rad\].
pub fn attitude(roll: f64, pitch: f64, yaw: f64) -> Quat {
    Quat::from_euler_angles(roll, -pitch, FRAC_PI_2 - yaw)
}

/// The ZYX Euler angles roll, pitch, yaw \[rad\] in shoal's NED/FRD frames of an attitude
/// given as a FLU-body-to-ENU-world quaternion (the inverse of [`attitude`]); yaw in (−π, π].
pub fn attitude_to_ned(enu: &Quat) -> (f64, f64, f64) {
    let (roll, pitch, yaw) = enu.euler_angles();
    (roll, -pitch, wrap_pi(FRAC_PI_2 - yaw))
}

/// The rotation that takes NED world vectors to ENU (a proper rotation: 180° about the
/// north-east diagonal).
pub fn ned_to_enu() -> Quat {
    Quat::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vec3::new(1.0, 1.0, 0.0)),
        std::f64::consts::PI,
    )
}

/// A FRD body vector (velocity \[m/s\], rates \[rad/s\]) in FLU: `(x, −y, −z)`.
pub fn body(frd: [f64; 3]) -> [f64; 3] {
    [frd[0], -frd[1], -frd[2]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quat_from_rpy;

    fn near(a: &Quat, b: [f64; 4]) {
        let q = a.quaternion();
        let (x, y, z, w) = (q.i, q.j, q.k, q.w);
        // q and −q are the same rotation.
        let s = if (w - b[3]).abs() < 1e-9 { 1.0 } else { -1.0 };
        for (got, want) in [x, y, z, w].iter().zip(b) {
            assert!((s * got - want).abs() < 1e-12, "{a:?} ≠ {b:?}");
        }
    }

    fn apply(q: &Quat, v: [f64; 3]) -> [f64; 3] {
        let r = q * Vec3::from(v);
        [r.x, r.y, r.z]
    }

    fn close(a: [f64; 3], b: [f64; 3]) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-12, "{a:?} ≠ {b:?}");
        }
    }

    #[test]
    fn positions_go_east_north_up() {
        // 1 m north, 2 m east, 3 m deep.
        assert_eq!(position([1.0, 2.0, 3.0]), [2.0, 1.0, -3.0]);
        close(apply(&ned_to_enu(), [1.0, 2.0, 3.0]), [2.0, 1.0, -3.0]);
    }

    #[test]
    fn a_level_vehicle_heading_east_is_the_identity() {
        // ENU's x is east: the body's forward axis.
        near(&attitude(0.0, 0.0, FRAC_PI_2), [0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn heading_north_is_a_quarter_turn_left() {
        let h = std::f64::consts::FRAC_PI_4;
        near(&attitude(0.0, 0.0, 0.0), [0.0, 0.0, h.sin(), h.cos()]);
        // Forward points north (ENU y).
        close(
            apply(&attitude(0.0, 0.0, 0.0), [1.0, 0.0, 0.0]),
            [0.0, 1.0, 0.0],
        );
    }

    #[test]
    fn nose_up_points_forward_up() {
        // Heading east, pitched 30° nose up (positive pitch in NED/FRD): ENU pitch −30°,
        // q = (0, −sin 15°, 0, cos 15°); forward is (cos 30°, 0, sin 30°).
        let a = 30f64.to_radians();
        let q = attitude(0.0, a, FRAC_PI_2);
        near(&q, [0.0, -(a / 2.0).sin(), 0.0, (a / 2.0).cos()]);
        close(apply(&q, [1.0, 0.0, 0.0]), [a.cos(), 0.0, a.sin()]);
    }

    #[test]
    fn starboard_down_lifts_the_port_side() {
        // Heading east, rolled 20° to starboard (positive roll): q = (sin 10°, 0, 0, cos 10°),
        // the port (FLU y) side goes up and the starboard side (south) down.
        let a = 20f64.to_radians();
        let q = attitude(a, 0.0, FRAC_PI_2);
        near(&q, [(a / 2.0).sin(), 0.0, 0.0, (a / 2.0).cos()]);
        close(apply(&q, [0.0, 1.0, 0.0]), [0.0, a.cos(), a.sin()]);
    }

    #[test]
    fn the_euler_formula_is_the_change_of_frames() {
        // R_ENU←NED · R_NED←FRD · R_FRD←FLU for angles all over the sphere.
        let frd_flu = Quat::from_axis_angle(&Vec3::x_axis(), std::f64::consts::PI);
        for (r, p, y) in [
            (0.3, -0.7, 2.9),
            (-2.5, 1.2, -0.4),
            (1.0, 0.1, -3.0),
            (0.0, -1.5, 1.0),
        ] {
            let want = ned_to_enu() * quat_from_rpy(r, p, y) * frd_flu;
            let got = attitude(r, p, y);
            assert!(got.angle_to(&want) < 1e-12, "{r} {p} {y}");
            // A body vector in FLU lands where the FRD one lands in NED, seen in ENU.
            let v = [0.2, -0.5, 0.9];
            close(
                apply(&got, body(v)),
                apply(&ned_to_enu(), apply(&quat_from_rpy(r, p, y), v)),
            );
        }
    }

    #[test]
    fn attitude_to_ned_undoes_attitude() {
        for (r, p, y) in [
            (0.3, -0.7, 2.9),
            (-2.5, 1.2, -0.4),
            (1.0, 0.1, -3.0),
            (0.0, -1.5, 1.0),
        ] {
            let (r2, p2, y2) = attitude_to_ned(&attitude(r, p, y));
            for (a, b) in [(r, r2), (p, p2), (y, y2)] {
                assert!((a - b).abs() < 1e-9, "{r} {p} {y} -> {r2} {p2} {y2}");
            }
        }
        // Heading north in ENU is yaw π/2 there and 0 in NED; 30° nose up in FLU is a
        // negative ENU pitch and a positive NED one.
        let h = std::f64::consts::FRAC_PI_4;
        let north = Quat::from_quaternion(nalgebra::Quaternion::new(h.cos(), 0.0, 0.0, h.sin()));
        let (_, _, yaw) = attitude_to_ned(&north);
        assert!(yaw.abs() < 1e-12);
        let up = Quat::from_euler_angles(0.0, -0.5, FRAC_PI_2);
        let (_, pitch, yaw) = attitude_to_ned(&up);
        assert!((pitch - 0.5).abs() < 1e-12 && yaw.abs() < 1e-12);
    }

    #[test]
    fn body_rates_flip_the_lateral_and_vertical_axes() {
        assert_eq!(body([0.1, 0.2, 0.3]), [0.1, -0.2, -0.3]);
    }
}
