//! Sensor models: the differential pressure sensor with the paper's calibration line and ADC
//! quantisation, and an IMU (attitude from the on-board filter, rate gyros, accelerometer).
//! Noise is drawn from a caller-supplied RNG so that each vehicle owns a seeded stream.

use crate::math::{Quat, Vec3};
use rand::{Rng, RngExt};
use rand_distr::StandardNormal;

/// Pressure (depth) sensor: true depth → voltage through the inverse calibration line
/// `d(V) = C₁V + C₂`, additive Gaussian noise, ADC quantisation, and back through the line.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureSensorParams {
    /// Calibration slope C₁ [m/V].
    pub c1: f64,
    /// Calibration offset C₂ \[m\].
    pub c2: f64,
    /// Depth resolution of one ADC step \[m\] (the voltage step is `depth_step / c1`).
    pub depth_step: f64,
    /// ADC resolution \[bits\].
    pub bits: u32,
    /// Standard deviation of the depth noise before quantisation \[m\].
    pub noise_std: f64,
    /// Position of the pressure port in the body frame \[m\].
    pub position: Vec3,
}

impl PressureSensorParams {
    /// Voltage \[V\] that the sensor outputs at true depth `depth` \[m\] (no noise). Above the
    /// surface the differential sensor sees no water column and reads depth 0.
    #[inline]
    pub fn voltage(&self, depth: f64) -> f64 {
        (depth.max(0.0) - self.c2) / self.c1
    }

    /// ADC code for a voltage \[V\].
    #[inline]
    pub fn code(&self, voltage: f64) -> u32 {
        let lsb = self.depth_step / self.c1;
        let max = ((1u64 << self.bits) - 1) as f64;
        (voltage / lsb).round().clamp(0.0, max) as u32
    }

    /// Depth \[m\] the calibrated line assigns to an ADC code.
    #[inline]
    pub fn depth_of_code(&self, code: u32) -> f64 {
        let lsb = self.depth_step / self.c1;
        self.c1 * (code as f64 * lsb) + self.c2
    }

    /// A quantised depth reading \[m\] at true depth `depth` \[m\].
    pub fn read<R: Rng + ?Sized>(&self, depth: f64, rng: &mut R) -> f64 {
        let noise: f64 = if self.noise_std > 0.0 {
            self.noise_std * rng.sample::<f64, _>(StandardNormal)
        } else {
            0.0
        };
        let v = (depth.max(0.0) + noise - self.c2) / self.c1;
        self.depth_of_code(self.code(v))
    }
}

/// IMU noise parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct ImuParams {
    /// Standard deviation of the attitude error of the on-board filter, per axis \[rad\].
    pub attitude_noise: f64,
    /// Standard deviation of the rate-gyro noise per sample [rad/s].
    pub gyro_noise: f64,
    /// Constant rate-gyro bias [rad/s].
    pub gyro_bias: Vec3,
    /// Standard deviation of the accelerometer noise per sample [m/s²].
    pub accel_noise: f64,
}

/// One IMU sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuReading {
    /// Attitude estimate (body → world).
    pub attitude: Quat,
    /// Angular rate, body frame [rad/s].
    pub gyro: Vec3,
    /// Specific force, body frame [m/s²] (reads (0, 0, −g) at rest, upright).
    pub accel: Vec3,
}

fn gauss3<R: Rng + ?Sized>(rng: &mut R, std: f64) -> Vec3 {
    if std <= 0.0 {
        return Vec3::zeros();
    }
    Vec3::new(
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
        rng.sample::<f64, _>(StandardNormal),
    ) * std
}

impl ImuParams {
    /// An IMU sample for true attitude `att`, body rates `omega` [rad/s] and body-frame
    /// linear acceleration `accel_body` [m/s²] (d/dt of the world velocity, in body axes).
    pub fn read<R: Rng + ?Sized>(
        &self,
        att: &Quat,
        omega: &Vec3,
        accel_body: &Vec3,
        gravity: f64,
        rng: &mut R,
    ) -> ImuReading {
        let err = gauss3(rng, self.attitude_noise);
        let attitude = *att * Quat::from_scaled_axis(err);
        let gyro = omega + self.gyro_bias + gauss3(rng, self.gyro_noise);
        let g_body = att.inverse_transform_vector(&Vec3::new(0.0, 0.0, gravity));
        let accel = accel_body - g_body + gauss3(rng, self.accel_noise);
        ImuReading {
            attitude,
            gyro,
            accel,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn imu_at_rest_reads_minus_g() {
        let imu = ImuParams {
            attitude_noise: 0.0,
            gyro_noise: 0.0,
            gyro_bias: Vec3::zeros(),
            accel_noise: 0.0,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let r = imu.read(
            &Quat::identity(),
            &Vec3::zeros(),
            &Vec3::zeros(),
            9.81,
            &mut rng,
        );
        assert!((r.accel - Vec3::new(0.0, 0.0, -9.81)).norm() < 1e-12);
    }
}
