//! Optical modems: the file form of [`ModemParams`] (every field defaults to the μAUV²'s
//! modem) with the modem's link layer (medium access: [`Access`]; retries), and their
//! conversions.

use super::{a3, unit_or_x, v3};
use crate::access::{Access, LinkParams};
use serde::{Deserialize, Serialize};
use shoal_model::optics::{Led, ModemParams, Receiver};
use shoal_model::presets;

fn m0() -> ModemParams {
    presets::uauv2_modem()
}
macro_rules! modem_default {
    ($($f:ident: $t:ty = |$m:ident| $e:expr;)*) => { $( fn $f() -> $t { let $m = m0(); $e } )* };
}
modem_default! {
    dm_name: String = |m| m.name;
    dm_position: [f64; 3] = |m| a3(&m.position);
    dm_direction: [f64; 3] = |m| a3(&m.direction);
    dm_led_power: f64 = |m| m.led.power;
    dm_led_half_angle_deg: f64 = |m| m.led.half_angle.to_degrees();
    dm_rx_area: f64 = |m| m.rx.area;
    dm_rx_fov_deg: f64 = |m| m.rx.fov.to_degrees();
    dm_responsivity: f64 = |m| m.rx.responsivity;
    dm_noise_density: f64 = |m| m.rx.noise_density;
    dm_bandwidth: f64 = |m| m.rx.bandwidth;
    dm_dark_current: f64 = |m| m.rx.dark_current;
    dm_bit_rate: f64 = |m| m.bit_rate;
    dm_bits_per_byte: u32 = |m| m.bits_per_byte;
    dm_header_bytes: usize = |m| m.header_bytes;
    dm_max_payload: usize = |m| m.max_payload;
    dm_queue_frames: usize = |m| m.queue_frames;
    dm_capture_ratio: f64 = |m| m.capture_ratio;
}
fn dm_arq_retries() -> u32 {
    3
}
fn dm_ack_timeout() -> f64 {
    // An acknowledgement (a header: 3.1 ms on the air) starts in the step after the frame
    // ended and is decided in the step it ends in: two 10-ms steps and its airtime, doubled.
    0.05
}

/// An optical modem (see [`ModemParams`]); every field defaults to the μAUV²'s modem.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModemSpec {
    /// Name.
    #[serde(default = "dm_name")]
    pub name: String,
    /// Position on the hull, body frame \[m\].
    #[serde(default = "dm_position")]
    pub position: [f64; 3],
    /// LED axis and photodiode normal, body frame (normalised on load).
    #[serde(default = "dm_direction")]
    pub direction: [f64; 3],
    /// LED optical power \[W\].
    #[serde(default = "dm_led_power")]
    pub led_power: f64,
    /// LED half-power half-angle \[deg\].
    #[serde(default = "dm_led_half_angle_deg")]
    pub led_half_angle_deg: f64,
    /// Photodiode area \[m²\].
    #[serde(default = "dm_rx_area")]
    pub rx_area: f64,
    /// Receiver field of view, half-angle \[deg\].
    #[serde(default = "dm_rx_fov_deg")]
    pub rx_fov_deg: f64,
    /// Responsivity [A/W].
    #[serde(default = "dm_responsivity")]
    pub responsivity: f64,
    /// Amplifier noise density [A/√Hz].
    #[serde(default = "dm_noise_density")]
    pub noise_density: f64,
    /// Noise bandwidth \[Hz\].
    #[serde(default = "dm_bandwidth")]
    pub bandwidth: f64,
    /// Dark current \[A\].
    #[serde(default = "dm_dark_current")]
    pub dark_current: f64,
    /// Line rate [bit/s].
    #[serde(default = "dm_bit_rate")]
    pub bit_rate: f64,
    /// Line bits per byte.
    #[serde(default = "dm_bits_per_byte")]
    pub bits_per_byte: u32,
    /// Header per frame \[bytes\].
    #[serde(default = "dm_header_bytes")]
    pub header_bytes: usize,
    /// Largest payload \[bytes\].
    #[serde(default = "dm_max_payload")]
    pub max_payload: usize,
    /// Transmit queue \[frames\].
    #[serde(default = "dm_queue_frames")]
    pub queue_frames: usize,
    /// Capture ratio (optical power ratio ≥ 1).
    #[serde(default = "dm_capture_ratio")]
    pub capture_ratio: f64,
    /// Medium access: a protocol's name, or a table with its `kind` and settings (see
    /// [`Access`]).
    #[serde(default, deserialize_with = "Access::from_file")]
    pub access: Access,
    /// Retransmissions of an unacknowledged unicast frame before giving up.
    #[serde(default = "dm_arq_retries")]
    pub arq_retries: u32,
    /// Wait for an acknowledgement after a frame ended \[s\].
    #[serde(default = "dm_ack_timeout")]
    pub ack_timeout: f64,
}

impl ModemSpec {
    /// Model parameters (degrees → radians, axis normalised).
    pub fn to_params(&self) -> ModemParams {
        ModemParams {
            name: self.name.clone(),
            position: v3(self.position),
            direction: unit_or_x(self.direction),
            led: Led {
                power: self.led_power,
                half_angle: self.led_half_angle_deg.to_radians(),
            },
            rx: Receiver {
                area: self.rx_area,
                fov: self.rx_fov_deg.to_radians(),
                responsivity: self.responsivity,
                noise_density: self.noise_density,
                bandwidth: self.bandwidth,
                dark_current: self.dark_current,
            },
            bit_rate: self.bit_rate,
            bits_per_byte: self.bits_per_byte,
            header_bytes: self.header_bytes,
            max_payload: self.max_payload,
            queue_frames: self.queue_frames,
            capture_ratio: self.capture_ratio,
        }
    }

    /// The modem's link layer.
    pub fn link(&self) -> LinkParams {
        LinkParams {
            access: self.access,
            retries: self.arq_retries,
            ack_timeout: self.ack_timeout,
        }
    }

    /// File form of model parameters, with unslotted ALOHA (the model has no medium access).
    pub fn from_params(m: &ModemParams) -> Self {
        Self {
            name: m.name.clone(),
            position: a3(&m.position),
            direction: a3(&m.direction),
            led_power: m.led.power,
            led_half_angle_deg: m.led.half_angle.to_degrees(),
            rx_area: m.rx.area,
            rx_fov_deg: m.rx.fov.to_degrees(),
            responsivity: m.rx.responsivity,
            noise_density: m.rx.noise_density,
            bandwidth: m.rx.bandwidth,
            dark_current: m.rx.dark_current,
            bit_rate: m.bit_rate,
            bits_per_byte: m.bits_per_byte,
            header_bytes: m.header_bytes,
            max_payload: m.max_payload,
            queue_frames: m.queue_frames,
            capture_ratio: m.capture_ratio,
            access: Access::default(),
            arq_retries: dm_arq_retries(),
            ack_timeout: dm_ack_timeout(),
        }
    }
}
