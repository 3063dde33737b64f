//! Small linear-algebra helpers and type aliases shared by the whole model.
//!
//! Conventions (Fossen / SNAME): world frame NED (x north, y east, z down), body frame
//! x forward, y starboard, z down. Attitude is a unit quaternion that maps body-frame vectors
//! into the world frame. Angles are in radians everywhere in code.

use nalgebra::{Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};

/// 3-vector of `f64`.
pub type Vec3 = Vector3<f64>;
/// 6-vector of `f64` (generalised forces or velocities: linear part first).
pub type Vec6 = Vector6<f64>;
/// 3×3 matrix of `f64`.
pub type Mat3 = Matrix3<f64>;
/// 6×6 matrix of `f64`.
pub type Mat6 = Matrix6<f64>;
/// Unit quaternion (attitude: body → world).
pub type Quat = UnitQuaternion<f64>;

/// One value per actuator of a vehicle (per thruster or per tilt drive), stored inline for up
/// to four and on the heap beyond: a swarm's actuator data then lies in its vehicles' own
/// component rows instead of in small heap blocks of its own.
pub type PerActuator = smallvec::SmallVec<[f64; 4]>;

/// Standard gravitational acceleration [m/s²].
pub const GRAVITY: f64 = 9.81;

/// The skew-symmetric cross-product matrix: `skew(a) * b == a.cross(&b)`.
#[inline]
pub fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Wraps an angle \[rad\] into (−π, π].
#[inline]
pub fn wrap_pi(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut r = a.rem_euclid(two_pi);
    if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

/// Roll, pitch, yaw (ZYX Euler angles) \[rad\] of an attitude quaternion.
#[inline]
pub fn euler_rpy(q: &Quat) -> (f64, f64, f64) {
    q.euler_angles()
}

/// Attitude quaternion from roll, pitch, yaw (ZYX) \[rad\].
#[inline]
pub fn quat_from_rpy(roll: f64, pitch: f64, yaw: f64) -> Quat {
    Quat::from_euler_angles(roll, pitch, yaw)
}

/// Splits a 6-vector into its linear and angular 3-vectors.
#[inline]
pub fn split6(v: &Vec6) -> (Vec3, Vec3) {
    (
        v.fixed_rows::<3>(0).into_owned(),
        v.fixed_rows::<3>(3).into_owned(),
    )
}

/// Joins linear and angular 3-vectors into a 6-vector.
#[inline]
pub fn join6(a: &Vec3, b: &Vec3) -> Vec6 {
    Vec6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross_product() {
        let a = Vec3::new(1.0, -2.0, 0.5);
        let b = Vec3::new(0.3, 0.7, -1.1);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
    }

    #[test]
    fn wrap_pi_range() {
        use std::f64::consts::PI;
        assert!((wrap_pi(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_pi(-PI) - PI).abs() < 1e-12);
        assert!((wrap_pi(0.25) - 0.25).abs() < 1e-15);
        assert!((wrap_pi(-0.25 - 2.0 * PI) + 0.25).abs() < 1e-12);
    }

    #[test]
    fn euler_roundtrip() {
        let q = quat_from_rpy(0.1, -0.2, 2.5);
        let (r, p, y) = euler_rpy(&q);
        assert!((r - 0.1).abs() < 1e-12 && (p + 0.2).abs() < 1e-12 && (y - 2.5).abs() < 1e-12);
    }
}
