//! Built-in vehicle presets. Every number is marked **paper** (stated in the μAUV² paper),
//! **derived** (follows from paper numbers; the derivation is given) or **assumed** (the paper
//! is silent; a documented default a world file can override). See `../shared/spec/uauv2.md`.

use crate::ballast::BallastParams;
use crate::control::{ControlParams, PdDesign};
use crate::math::{Mat3, Mat6, Vec3, Vec6};
use crate::optics::{Led, ModemParams, Receiver};
use crate::rigid_body::BodyParams;
use crate::sensors::{ImuParams, PressureSensorParams};
use crate::thruster::{ThrustCurve, ThrusterParams, TiltParams};
use crate::vehicle_params::VehicleParams;
use std::f64::consts::FRAC_PI_2;

/// Names of the built-in presets.
pub const NAMES: [&str; 1] = ["uauv2"];

/// The preset of that name, if it exists.
pub fn by_name(name: &str) -> Option<VehicleParams> {
    match name {
        "uauv2" => Some(uauv2()),
        _ => None,
    }
}

/// μAUV² C_t⁺ [N/%²] — **paper** Table 2 (its unit is garbled; the heave forces of Sec. 4.3
/// equal 2·C_t⁺·n² with n in percent, which fixes the unit: **derived**).
pub const UAUV2_CT_POS: f64 = 13.2e-6;
/// μAUV² C_t⁻ magnitude [N/%²] — **paper** Table 2 (printed −8.32e-6; the sign says "reverse").
pub const UAUV2_CT_NEG: f64 = 8.32e-6;
/// μAUV² effective heave mass m + A₃₃ \[kg\] — **paper** Table 4 (R² 0.80, poor fit).
pub const UAUV2_HEAVE_MASS: f64 = 1.96;
/// μAUV² effective yaw inertia I_zz + A₆₆ [kg·m²] — **paper** Table 4.
pub const UAUV2_YAW_INERTIA: f64 = 4.9e-3;
/// μAUV² linear heave damping Z_w [N·s/m] — **paper** Table 3.
pub const UAUV2_ZW: f64 = 0.204;
/// μAUV² quadratic heave damping Z_w|w| [N·s²/m²] — **paper** Table 3.
#[expect(
    clippy::approx_constant,
    reason = "the paper's identified value, not 2π"
)]
pub const UAUV2_ZWW: f64 = 6.28;
/// μAUV² linear yaw damping N_r [N·m·s] — **paper** Table 3.
pub const UAUV2_NR: f64 = 2.51e-4;
/// μAUV² quadratic yaw damping N_r|r| [N·m·s²] — **paper** Table 3.
pub const UAUV2_NRR: f64 = 3.54e-3;
/// μAUV² mass \[kg\] — **paper** Sec. 1.
pub const UAUV2_MASS: f64 = 1.2;
/// μAUV² buoyancy pump flow [m³/s] (0.05 ml/s, the same both ways) — **derived** from the
/// calibration run: ≈0.016 N removed between t ≈ 16 s and 51 s (paper Fig. 13).
pub const UAUV2_PUMP_FLOW: f64 = 0.05e-6;

/// Optical power of the μAUV² modem's LED \[W\] — **derived** from the calibration target (a
/// 32-byte on-axis frame delivered half the time at 2.5 m in pool water, c = 0.07 1/m) with the
/// assumed receiver of [`uauv2_modem`]: it needs SNR = 8.14 there (BER 2.16e-3 over 320 line
/// bits), which the thermal-noise-limited photodiode gives at P_t = 48.5 mW.
pub const UAUV2_LED_POWER: f64 = 0.0485;

/// The μAUV²'s optical modem (paper 3.2.6: 530 nm LED, IrDA PHY MAX3120, half-duplex, UART,
/// 19.2 kbit/s, ≈2.5 m), mounted behind the front dome looking forward. Only the rate, the
/// framing and the range are from the paper; the optics and electronics are assumed typical
/// values (a BPW34-class silicon photodiode and a transimpedance amplifier).
pub fn uauv2_modem() -> ModemParams {
    ModemParams {
        name: "front".into(),
        position: Vec3::new(0.125, 0.0, 0.0), // assumed: behind the front dome
        direction: Vec3::x_axis(),            // assumed: looking forward
        led: Led {
            power: UAUV2_LED_POWER,         // derived (calibration, see the constant)
            half_angle: 60f64.to_radians(), // assumed (Lambertian, m = 1)
        },
        rx: Receiver {
            area: 7e-6,              // assumed: 7 mm² photodiode
            fov: 60f64.to_radians(), // assumed
            responsivity: 0.25,      // assumed: silicon at 530 nm [A/W]
            noise_density: 4e-12,    // assumed: amplifier [A/√Hz]
            bandwidth: 1e5,          // assumed: ≈5× the bit rate (IrDA pulses are 3/16 bit)
            dark_current: 1e-9,      // assumed [A]
        },
        bit_rate: 19_200.0, // paper 3.2.6
        bits_per_byte: 10,  // paper: UART compatible → 8N1, derived
        header_bytes: 6,    // assumed: source 2, sequence 1, length 1, CRC 2
        max_payload: 58,    // assumed: 64-byte frames
        queue_frames: 8,    // assumed
        capture_ratio: 2.0, // assumed: 2× optical power = 6 dB electrical
    }
}

/// The DFKI μAUV² with its identified parameters.
pub fn uauv2() -> VehicleParams {
    // Tank: capacity 20 ml (assumed), neutral trim with the tank half full (assumed): the
    // paper's 1.2 kg is the vehicle with 10 ml of water aboard.
    let tank_neutral = 10e-6; // [m³] assumed
    let dry_mass = UAUV2_MASS - tank_neutral * 1000.0; // [kg] derived
    // Rigid-body inertia about the CG, solid-ellipsoid estimate for roll and pitch (assumed):
    // I_xx = m(b²+c²)/5 ≈ 3.5e-3, I_yy = m(a²+c²)/5 ≈ 6.4e-3 with semi-axes 0.135/0.078/0.091 m.
    // Yaw: the paper identifies only I_zz + A₆₆ = 4.9e-3; the split 4.4e-3 + 0.5e-3 is assumed
    // (the ellipsoid's 5.8e-3 exceeds the identified sum, so the real mass is more central).
    let i_zz = 4.4e-3;
    let a66 = UAUV2_YAW_INERTIA - i_zz; // derived from the assumed split
    let a33 = UAUV2_HEAVE_MASS - UAUV2_MASS; // derived: 0.76 kg
    let body = BodyParams {
        mass: dry_mass,
        inertia_cg: Mat3::from_diagonal(&Vec3::new(3.5e-3, 6.4e-3, i_zz)),
        // CG 15 mm below the CB: battery pack below the hull gives passive roll/pitch
        // stability (paper 5.1); the value is assumed.
        cog: Vec3::new(0.0, 0.0, 0.015),
        cob: Vec3::zeros(),
        // Displaced volume for neutral buoyancy in fresh water with the tank half full (derived
        // from the assumed trim): (dry mass + 10 g) / 1000 kg/m³.
        volume: UAUV2_MASS / 1000.0,
        // A₁₁ 0.3 kg, A₂₂ 0.76 kg (as heave: similar cross-section), A₄₄ 0.5e-3, A₅₅ 1.5e-3
        // kg·m² (assumed); A₃₃, A₆₆ derived above.
        added_mass: Mat6::from_diagonal(&Vec6::new(0.3, 0.76, a33, 0.5e-3, 1.5e-3, a66)),
        // Z_w, N_r: paper Table 3. Surge/sway: the heave law scaled by projected area
        // (frontal 0.022 m², side 0.039 m² vs top 0.033 m²) — assumed. Roll/pitch: of the
        // order of the yaw values — assumed.
        damping_linear: Vec6::new(0.14, 0.24, UAUV2_ZW, 1.5e-4, 2.5e-4, UAUV2_NR),
        damping_quadratic: Vec6::new(4.2, 7.3, UAUV2_ZWW, 1.5e-3, 3.5e-3, UAUV2_NRR),
        // L × W × H = 0.270 × 0.156 × 0.182 m — paper.
        hull_size: Vec3::new(0.270, 0.156, 0.182),
    };
    let curve = ThrustCurve::Quadratic {
        ct_pos: UAUV2_CT_POS,
        ct_neg: UAUV2_CT_NEG,
    };
    let thruster = |name: &str, position: Vec3, tilt: usize| ThrusterParams {
        name: name.into(),
        position,
        direction: Vec3::x_axis(),
        tilt: Some(tilt),
        curve: curve.clone(),
        // Commands in percent of full scale — paper (derived unit of C_t).
        max_command: 100.0,
        // Thruster dynamics neglected — paper Sec. 4.2.
        lag: 0.0,
        lag_down: -1.0,
        lag_stages: 1,
        // No slew-rate limit.
        ramp: 0.0,
    };
    VehicleParams {
        name: "uauv2".into(),
        body,
        // Geometry assumed (the paper gives none): sides at y = ±0.10 m, top 0.09 m above.
        thrusters: vec![
            thruster("top", Vec3::new(0.0, 0.0, -0.09), 0),
            thruster("port", Vec3::new(0.0, -0.10, 0.0), 1),
            thruster("stbd", Vec3::new(0.0, 0.10, 0.0), 1),
        ],
        tilts: vec![
            // ±90° — paper 3.1.1. Rate 1 rad/s — assumed ("slow" drives, paper 5.1).
            TiltParams {
                name: "alpha".into(),
                axis: Vec3::z_axis(),
                min: -FRAC_PI_2,
                max: FRAC_PI_2,
                rate_max: 1.0,
            },
            TiltParams {
                name: "beta".into(),
                axis: Vec3::y_axis(),
                min: -FRAC_PI_2,
                max: FRAC_PI_2,
                rate_max: 1.0,
            },
        ],
        ballast: Some(BallastParams {
            capacity: 20e-6,                      // assumed
            flow: UAUV2_PUMP_FLOW,                // derived (see the constant)
            position: Vec3::new(0.0, 0.0, 0.015), // assumed at the CG
            initial_volume: tank_neutral,
        }),
        pressure: PressureSensorParams {
            c1: 1.920,          // paper Table 1 [m/V]
            c2: -0.4864,        // paper Table 1 [m]
            depth_step: 1.8e-3, // paper 3.2.3 (1.8 mm per bit)
            bits: 12,           // paper 3.2.3
            noise_std: 0.5e-3,  // assumed
            // At the top of the hull — assumed: depth 0 then means "just submerged", which
            // is how the paper's runs start and end at the surface.
            position: Vec3::new(0.0, 0.0, -0.091),
        },
        imu: ImuParams {
            attitude_noise: 0.5f64.to_radians(), // assumed
            gyro_noise: 0.01,                    // assumed [rad/s]
            gyro_bias: Vec3::zeros(),            // assumed
            accel_noise: 0.02,                   // assumed [m/s²]
        },
        control: ControlParams {
            period: 0.05, // assumed (20 Hz)
            heave: PdDesign {
                omega: 0.6,
                zeta: 1.0,
                kp: None,
                kd: None,
            }, // paper 5.4
            heave_buoyancy: PdDesign {
                omega: 0.4,
                zeta: 1.0,
                kp: None,
                kd: None,
            }, // paper 5.5
            // ω = 0.6 with K_D raised to 0.016 — paper 5.6 (ζ = 1 nominal).
            yaw: PdDesign {
                omega: 0.6,
                zeta: 1.0,
                kp: None,
                kd: Some(0.016),
            },
            dead_zone: 0.008,                           // paper 5.5
            filter_window: 5,                           // assumed (0.25 s at 20 Hz)
            auto_tilt_max: std::f64::consts::FRAC_PI_4, // paper 5.1
            // Depth-rate filter 0.3 s — assumed: the raw difference of a 1.8 mm-quantised
            // reading at 20 Hz jumps by 0.036 m/s per step, i.e. ±0.085 N through K_D.
            rate_filter: 0.3,
        },
        modems: vec![uauv2_modem()],
    }
}
