//! Optical modems: the file form of [`ModemParams`] (every field defaults to the μAUV²'s
//! modem) with the modem's medium access ([`Access`]), and their conversions.

use super::{a3, unit_or_x, v3};
use crate::access::{Access, LinkParams};
use serde::{Deserialize, Serialize};
use shoal_model::optics::{Led, ModemParams, Receiver};
use shoal_model::presets;

/// Medium access as written in files (see [`Access`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AccessSpec {
    /// Unslotted ALOHA.
    Aloha,
    /// Listen before talk.
    CarrierSense,
    /// Slotted ALOHA on the vehicle's own clock.
    SlottedAloha,
    /// Time-division: one slot per vehicle in a cycle.
    Tdma,
    /// CSMA/CA with binary exponential back-off.
    CsmaCa,
}

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
fn dm_access() -> AccessSpec {
    AccessSpec::Aloha
}
fn dm_cs_threshold() -> f64 {
    1e-9
}
fn dm_backoff_max() -> f64 {
    0.05
}
fn dm_slot() -> f64 {
    // The μAUV² modem's longest frame (64 bytes of 10 line bits at 19.2 kbit/s: 33.3 ms) and
    // a guard of 1.7 ms.
    0.035
}
fn dm_tdma_slots() -> u32 {
    1
}
fn dm_backoff_slot() -> f64 {
    0.001
}
fn dm_difs() -> f64 {
    0.003
}
fn dm_cw_min() -> u32 {
    16
}
fn dm_cw_max() -> u32 {
    1024
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
    /// Medium access.
    #[serde(default = "dm_access")]
    pub access: AccessSpec,
    /// Carrier-sense busy threshold \[W\] (carrier_sense only).
    #[serde(default = "dm_cs_threshold")]
    pub cs_threshold: f64,
    /// Longest carrier-sense back-off \[s\] (carrier_sense only).
    #[serde(default = "dm_backoff_max")]
    pub backoff_max: f64,
    /// Slot length \[s\] (slotted_aloha and tdma).
    #[serde(default = "dm_slot")]
    pub slot: f64,
    /// Largest clock rate error of a vehicle \[ppm\] (slotted_aloha only).
    #[serde(default)]
    pub clock_drift_ppm: f64,
    /// Slots per TDMA cycle (tdma only).
    #[serde(default = "dm_tdma_slots")]
    pub tdma_slots: u32,
    /// The vehicles' slot in the TDMA cycle (tdma only; default: each vehicle's id modulo
    /// `tdma_slots`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tdma_slot: Option<u32>,
    /// Back-off slot \[s\] (csma_ca only).
    #[serde(default = "dm_backoff_slot")]
    pub backoff_slot: f64,
    /// Idle time before a back-off count resumes \[s\] (csma_ca only).
    #[serde(default = "dm_difs")]
    pub difs: f64,
    /// Smallest contention window \[slots\] (csma_ca only).
    #[serde(default = "dm_cw_min")]
    pub cw_min: u32,
    /// Largest contention window \[slots\] (csma_ca only).
    #[serde(default = "dm_cw_max")]
    pub cw_max: u32,
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

    /// The modem's medium access (ppm → a fraction).
    pub fn access(&self) -> Access {
        match self.access {
            AccessSpec::Aloha => Access::Aloha,
            AccessSpec::CarrierSense => Access::CarrierSense {
                threshold: self.cs_threshold,
                backoff_max: self.backoff_max,
            },
            AccessSpec::SlottedAloha => Access::SlottedAloha {
                slot: self.slot,
                clock_drift: self.clock_drift_ppm * 1e-6,
            },
            AccessSpec::Tdma => Access::Tdma {
                slot: self.slot,
                slots: self.tdma_slots,
                own: self.tdma_slot,
            },
            AccessSpec::CsmaCa => Access::CsmaCa {
                threshold: self.cs_threshold,
                slot: self.backoff_slot,
                difs: self.difs,
                cw_min: self.cw_min,
                cw_max: self.cw_max,
            },
        }
    }

    /// The modem's link layer.
    pub fn link(&self) -> LinkParams {
        LinkParams {
            access: self.access(),
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
            access: dm_access(),
            cs_threshold: dm_cs_threshold(),
            backoff_max: dm_backoff_max(),
            slot: dm_slot(),
            clock_drift_ppm: 0.0,
            tdma_slots: dm_tdma_slots(),
            tdma_slot: None,
            backoff_slot: dm_backoff_slot(),
            difs: dm_difs(),
            cw_min: dm_cw_min(),
            cw_max: dm_cw_max(),
            arq_retries: dm_arq_retries(),
            ack_timeout: dm_ack_timeout(),
        }
    }
}
