//! The optical link budget of an LED modem under water (the μAUV²'s 530 nm OptCom).
//!
//! Transmitter: a Lambertian LED of optical power P_t \[W\] and half-power half-angle Φ½, so
//! its order is `m = −ln 2 / ln cos Φ½`. Receiver: a photodiode of area A_r \[m²\], field of view
//! (half-angle) Ψ_c and responsivity R [A/W]. Channel (line of sight, Beer–Lambert):
//!
//! ```text
//! H = (m+1)/(2π d²) · cos^m φ · A_r · cos ψ · e^(−c d)      for ψ ≤ Ψ_c and φ < 90°, else 0
//! P_r = P_t · H,   I_s = R · P_r
//! ```
//!
//! with φ the angle off the LED axis, ψ the angle off the photodiode normal and c the beam
//! attenuation of the water. Noise (variance of the photocurrent \[A²\] in bandwidth B):
//!
//! ```text
//! σ² = i_n² B                              thermal (input-referred amplifier noise density i_n)
//!    + 2 q (I_s + I_bg + I_dark) B         shot noise of signal, ambient light and dark current
//!    + Σ (R P_j)² / 4                      other transmitters' OOK signals (random bits)
//! I_bg = R · E(z) · A_r · sin² Ψ_c,        E(z) = E₀ e^(−K_d z)  (ambient light, decays with depth)
//! ```
//!
//! Bit errors, **convention**: on-off keying with a mid-level threshold and equiprobable bits,
//! `BER = Q(√SNR)` with `SNR = I_s² / σ²` (electrical SNR of the "on" level). A frame of `L`
//! bytes costs `10 L` bits on the line (UART 8N1: start, 8 data, stop); it fails if any bit
//! fails: `FER = 1 − (1 − BER)^(10 L)`.

use crate::math::{Quat, Vec3};
use nalgebra::Unit;

/// Elementary charge \[C\].
pub const Q_E: f64 = 1.602_176_634e-19;

/// The Gaussian tail function Q(x) = P(N(0,1) > x).
#[inline]
pub fn q_function(x: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(x / std::f64::consts::SQRT_2)
}

/// Lambertian order of an LED with half-power half-angle `half_angle` \[rad\] (0 < · < π/2).
#[inline]
pub fn lambertian_order(half_angle: f64) -> f64 {
    -std::f64::consts::LN_2 / half_angle.cos().ln()
}

/// LED transmitter.
#[derive(Clone, Debug, PartialEq)]
pub struct Led {
    /// Optical output power \[W\].
    pub power: f64,
    /// Half-power half-angle Φ½ \[rad\].
    pub half_angle: f64,
}

/// Photodiode receiver with its amplifier.
#[derive(Clone, Debug, PartialEq)]
pub struct Receiver {
    /// Active area A_r \[m²\].
    pub area: f64,
    /// Field of view, half-angle Ψ_c \[rad\].
    pub fov: f64,
    /// Responsivity at the LED's wavelength [A/W].
    pub responsivity: f64,
    /// Input-referred noise current density of the amplifier [A/√Hz].
    pub noise_density: f64,
    /// Noise bandwidth B \[Hz\].
    pub bandwidth: f64,
    /// Dark current \[A\].
    pub dark_current: f64,
}

/// Ambient light in the water.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ambient {
    /// Ambient irradiance just below the surface within the receiver's optical band [W/m²].
    pub surface_irradiance: f64,
    /// Diffuse attenuation coefficient K_d of that light with depth [1/m].
    pub diffuse_attenuation: f64,
}

impl Ambient {
    /// Irradiance at depth `z` \[m\] [W/m²].
    #[inline]
    pub fn irradiance(&self, z: f64) -> f64 {
        self.surface_irradiance * (-self.diffuse_attenuation * z.max(0.0)).exp()
    }
}

/// One optical modem on a hull: an LED and a photodiode looking the same way.
#[derive(Clone, Debug, PartialEq)]
pub struct ModemParams {
    /// Name (e.g. `front`).
    pub name: String,
    /// Position on the hull, body frame \[m\].
    pub position: Vec3,
    /// Axis of the LED and normal of the photodiode, body frame.
    pub direction: Unit<Vec3>,
    /// Transmitter.
    pub led: Led,
    /// Receiver.
    pub rx: Receiver,
    /// Line rate [bit/s].
    pub bit_rate: f64,
    /// Bits on the line per byte (10 for UART 8N1).
    pub bits_per_byte: u32,
    /// Link-layer header added to every frame \[bytes\] (source, sequence, length, CRC).
    pub header_bytes: usize,
    /// Largest payload \[bytes\].
    pub max_payload: usize,
    /// Transmit queue length \[frames\]; a frame arriving at a full queue is dropped and counted.
    pub queue_frames: usize,
    /// Capture ratio (linear power ratio ≥ 1): a frame survives an overlapping one only if
    /// its received power is at least this many times stronger.
    pub capture_ratio: f64,
}

impl ModemParams {
    /// Time on the air of a frame with `payload` bytes \[s\].
    #[inline]
    pub fn airtime(&self, payload: usize) -> f64 {
        ((payload + self.header_bytes) * self.bits_per_byte as usize) as f64 / self.bit_rate
    }

    /// Bits on the line for a frame with `payload` bytes.
    #[inline]
    pub fn frame_bits(&self, payload: usize) -> u64 {
        ((payload + self.header_bytes) * self.bits_per_byte as usize) as u64
    }
}

/// Where a modem is in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModemPose {
    /// Position \[m\].
    pub position: Vec3,
    /// Unit axis.
    pub axis: Vec3,
}

impl ModemPose {
    /// World pose of a modem mounted at `m` on a hull at `position` \[m\] with `attitude`.
    #[inline]
    pub fn of(m: &ModemParams, position: &Vec3, attitude: &Quat) -> Self {
        Self {
            position: position + attitude * m.position,
            axis: attitude * m.direction.into_inner(),
        }
    }
}

/// Geometry of one transmitter → receiver link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkGeometry {
    /// Distance \[m\].
    pub distance: f64,
    /// cos φ: angle between the LED axis and the direction to the receiver.
    pub cos_tx: f64,
    /// cos ψ: angle between the photodiode normal and the direction to the transmitter.
    pub cos_rx: f64,
}

impl LinkGeometry {
    /// Geometry between two modem poses.
    #[inline]
    pub fn between(tx: &ModemPose, rx: &ModemPose) -> Self {
        let d = rx.position - tx.position;
        let distance = d.norm();
        if distance <= 0.0 {
            return Self {
                distance: 0.0,
                cos_tx: 1.0,
                cos_rx: 1.0,
            };
        }
        let u = d / distance;
        Self {
            distance,
            cos_tx: tx.axis.dot(&u),
            cos_rx: -rx.axis.dot(&u),
        }
    }

    /// On-axis geometry at `distance` \[m\].
    pub fn on_axis(distance: f64) -> Self {
        Self {
            distance,
            cos_tx: 1.0,
            cos_rx: 1.0,
        }
    }
}

/// Per-modem constants of the link budget, precomputed once per design: the transmitting
/// side ([`ModemConsts::coef`], [`ModemConsts::order`]) and the receiving side
/// ([`ModemConsts::cos_fov`], [`ModemConsts::area`]) of [`received_power`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModemConsts {
    /// P_t (m+1)/(2π) of the LED \[W\].
    pub coef: f64,
    /// Lambertian order m \[1\].
    pub order: f64,
    /// cos of the receiver's field of view \[1\].
    pub cos_fov: f64,
    /// Photodiode area \[m²\].
    pub area: f64,
}

impl ModemConsts {
    /// The constants of a modem.
    pub fn of(m: &ModemParams) -> Self {
        Self::of_parts(&m.led, &m.rx, m.led.power)
    }

    /// The constants of LED `led` driven at optical power `power` \[W\] and receiver `rx`.
    fn of_parts(led: &Led, rx: &Receiver, power: f64) -> Self {
        let order = lambertian_order(led.half_angle);
        Self {
            coef: power * (order + 1.0) / (2.0 * std::f64::consts::PI),
            order,
            cos_fov: rx.fov.cos(),
            area: rx.area,
        }
    }
}

/// Received optical power \[W\] `P_t · H` from a transmitter with constants `tx` to a
/// receiver with constants `rx` over geometry `g` in water of `attenuation` \[1/m\] (see the
/// module doc); 0 outside the LED's forward half-space or the receiver's field of view. The
/// one link budget of the crate: [`channel_gain`] is its value at 1 W.
#[inline]
pub fn received_power(
    tx: &ModemConsts,
    rx: &ModemConsts,
    g: &LinkGeometry,
    attenuation: f64,
) -> f64 {
    if g.cos_tx <= 0.0 || g.cos_rx < rx.cos_fov || g.distance <= 0.0 {
        return 0.0;
    }
    let ct = if (tx.order - 1.0).abs() < 1e-9 {
        g.cos_tx
    } else {
        g.cos_tx.powf(tx.order)
    };
    tx.coef / (g.distance * g.distance)
        * ct
        * rx.area
        * g.cos_rx
        * (-attenuation * g.distance).exp()
}

/// DC channel gain H \[1\] (see the module doc): [`received_power`] of `led` at 1 W; 0
/// outside the LED's forward half-space or the receiver's field of view.
#[inline]
pub fn channel_gain(led: &Led, rx: &Receiver, g: &LinkGeometry, attenuation: f64) -> f64 {
    let c = ModemConsts::of_parts(led, rx, 1.0);
    received_power(&c, &c, g, attenuation)
}

/// Background photocurrent from ambient light at depth `z` \[m\] \[A\].
#[inline]
pub fn background_current(rx: &Receiver, ambient: &Ambient, z: f64) -> f64 {
    rx.responsivity * ambient.irradiance(z) * rx.area * rx.fov.sin().powi(2)
}

/// Noise variance of the photocurrent \[A²\] for signal current `i_s`, background current
/// `i_bg` and total interfering optical power `p_int` \[W\] (treated as random OOK).
#[inline]
pub fn noise_variance(rx: &Receiver, i_s: f64, i_bg: f64, p_int: f64) -> f64 {
    let b = rx.bandwidth;
    rx.noise_density * rx.noise_density * b
        + 2.0 * Q_E * (i_s + i_bg + rx.dark_current) * b
        + (rx.responsivity * p_int).powi(2) / 4.0
}

/// Bit error rate of OOK: `Q(√SNR)`.
#[inline]
pub fn ber_ook(snr: f64) -> f64 {
    q_function(snr.max(0.0).sqrt())
}

/// Frame error rate of a frame of `bits` line bits.
#[inline]
pub fn frame_error_rate(ber: f64, bits: u64) -> f64 {
    if ber <= 0.0 {
        return 0.0;
    }
    // 1 − (1−p)^n, accurate for tiny p.
    -(bits as f64 * (-ber).ln_1p()).exp_m1()
}

/// Everything about one reception.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    /// Channel gain H.
    pub gain: f64,
    /// Received optical power \[W\].
    pub p_rx: f64,
    /// Signal photocurrent \[A\].
    pub i_signal: f64,
    /// Noise standard deviation \[A\].
    pub sigma: f64,
    /// Electrical SNR I_s²/σ².
    pub snr: f64,
    /// Bit error rate.
    pub ber: f64,
    /// Frame error rate.
    pub fer: f64,
}

/// The full budget of a reception: `g` geometry, water `attenuation` [1/m], receiver depth
/// `rx_depth` \[m\] (for ambient light), interfering power `p_int` \[W\], frame of `bits`.
pub fn budget(
    led: &Led,
    rx: &Receiver,
    g: &LinkGeometry,
    attenuation: f64,
    ambient: &Ambient,
    rx_depth: f64,
    p_int: f64,
    bits: u64,
) -> Budget {
    let gain = channel_gain(led, rx, g, attenuation);
    Budget {
        gain,
        ..reception(rx, led.power * gain, ambient, rx_depth, p_int, bits)
    }
}

/// The receiver side of [`budget`] for a known received optical power `p_rx` \[W\] (e.g. the
/// sum of several in-sync copies of a frame); `gain` is left at 0.
pub fn reception(
    rx: &Receiver,
    p_rx: f64,
    ambient: &Ambient,
    rx_depth: f64,
    p_int: f64,
    bits: u64,
) -> Budget {
    let i_signal = rx.responsivity * p_rx;
    let i_bg = background_current(rx, ambient, rx_depth);
    let var = noise_variance(rx, i_signal, i_bg, p_int);
    let snr = if var > 0.0 {
        i_signal * i_signal / var
    } else {
        f64::INFINITY
    };
    let ber = if p_rx > 0.0 { ber_ook(snr) } else { 0.5 };
    let fer = frame_error_rate(ber, bits);
    Budget {
        gain: 0.0,
        p_rx,
        i_signal,
        sigma: var.sqrt(),
        snr,
        ber,
        fer,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn q_function_values() {
        // Reference values from erfc in double precision; statrs' erfc is good to ≈1e-10
        // relative, far below anything a bit error rate needs.
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!((q_function(0.0) - 0.5).abs() < 1e-15);
        assert!(rel(q_function(1.0), 0.158_655_253_931_457_07) < 1e-9);
        assert!(rel(q_function(3.0), 1.349_898_031_630_095_7e-3) < 1e-9);
        assert!(rel(q_function(5.0), 2.866_515_718_791_939e-7) < 1e-9);
    }

    #[test]
    fn lambertian_order_of_60_degrees_is_one() {
        assert!((lambertian_order(60f64.to_radians()) - 1.0).abs() < 1e-12);
        assert!((lambertian_order(30f64.to_radians()) - 4.818_841_679).abs() < 1e-6);
    }

    #[test]
    fn frame_error_rate_small_and_large() {
        assert!((frame_error_rate(1e-9, 320) - 3.2e-7).abs() < 1e-12);
        assert!((frame_error_rate(0.5, 10) - (1.0 - 0.5f64.powi(10))).abs() < 1e-12);
        assert_eq!(frame_error_rate(0.0, 320), 0.0);
    }

    #[test]
    fn geometry_angles() {
        let tx = ModemPose {
            position: Vec3::zeros(),
            axis: Vec3::x(),
        };
        let rx = ModemPose {
            position: Vec3::new(2.0, 2.0, 0.0),
            axis: -Vec3::x(),
        };
        let g = LinkGeometry::between(&tx, &rx);
        assert!((g.distance - 8f64.sqrt()).abs() < 1e-12);
        assert!((g.cos_tx - 45f64.to_radians().cos()).abs() < 1e-12);
        assert!((g.cos_rx - 45f64.to_radians().cos()).abs() < 1e-12);
    }
}
