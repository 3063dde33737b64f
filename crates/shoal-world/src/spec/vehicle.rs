//! The vehicle model schema shared by world files and `vehicle.toml` files (hull, tilt drives,
//! thrusters, ballast, sensors, controller, modems, effects) and its conversions to and from
//! [`VehicleParams`].

use super::{ModemSpec, a3, a6, unit_or_x, v3};
use serde::{Deserialize, Serialize};
use shoal_model::ballast::BallastParams;
use shoal_model::prelude::*;
use std::collections::BTreeMap;

fn d_max_command() -> f64 {
    100.0
}

/// A 3×3 matrix: its diagonal, or all rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Mat3Spec {
    /// Diagonal.
    Diagonal([f64; 3]),
    /// Rows.
    Full([[f64; 3]; 3]),
}

/// A 6×6 matrix: its diagonal, or all rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Mat6Spec {
    /// Diagonal.
    Diagonal([f64; 6]),
    /// Rows.
    Full(Box<[[f64; 6]; 6]>),
}

/// A complete vehicle model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// Name of the vehicle kind.
    pub name: String,
    /// Hull.
    pub body: BodySpec,
    /// Tilt drives.
    #[serde(default)]
    pub tilts: Vec<TiltSpec>,
    /// Thrusters.
    #[serde(default)]
    pub thrusters: Vec<ThrusterSpec>,
    /// Buoyancy tank.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ballast: Option<BallastSpec>,
    /// Pressure sensor.
    pub pressure: PressureSpec,
    /// IMU.
    pub imu: ImuSpec,
    /// Controller.
    pub control: ControlSpec,
    /// Optical modems.
    #[serde(default)]
    pub modems: Vec<ModemSpec>,
    /// Model extensions switched on (catalogue in `shoal_model::effects`), e.g. as found and
    /// fitted by `shoal validate`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<EffectSpec>,
}

/// A model extension with its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectSpec {
    /// Catalogue name (e.g. `thruster_lag`).
    pub name: String,
    /// Form of the family (e.g. `second_order`; `shoal effects` lists them); absent: the
    /// family's default form.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form: Option<String>,
    /// Every parameter of the effect by name, each in the unit its name ends with (e.g.
    /// `tau_s` in seconds); `shoal validate` writes them, `shoal check` lists the bounds.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// Hull parameters (see [`BodyParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Dry mass \[kg\].
    pub mass: f64,
    /// Inertia about the dry CG [kg·m²].
    pub inertia: Mat3Spec,
    /// Dry centre of gravity, body frame \[m\].
    pub cog: [f64; 3],
    /// Centre of buoyancy, body frame \[m\].
    pub cob: [f64; 3],
    /// Displaced volume \[m³\].
    pub volume: f64,
    /// Added mass M_A [kg, kg·m, kg·m²].
    pub added_mass: Mat6Spec,
    /// Linear damping (X_u, Y_v, Z_w [N·s/m], K_p, M_q, N_r [N·m·s]).
    pub damping_linear: [f64; 6],
    /// Quadratic damping (X_u|u|, Y_v|v|, Z_w|w| [N·s²/m²], K_p|p|, M_q|q|, N_r|r| [N·m·s²]).
    pub damping_quadratic: [f64; 6],
    /// Hull length, width, height \[m\].
    pub hull_size: [f64; 3],
}

/// Tilt drive (see [`TiltParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TiltSpec {
    /// Name.
    pub name: String,
    /// Body-frame axis (normalised on load).
    pub axis: [f64; 3],
    /// Lower limit \[deg\].
    pub min_deg: f64,
    /// Upper limit \[deg\].
    pub max_deg: f64,
    /// Rate limit [deg/s].
    pub rate_deg_s: f64,
}

/// Thrust curve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CurveSpec {
    /// f = C⁺n² (n ≥ 0), −C⁻n² (n < 0), n in %.
    Quadratic {
        /// C⁺ [N/%²].
        ct_pos: f64,
        /// C⁻ magnitude [N/%²].
        ct_neg: f64,
    },
    /// Table of [command %, thrust N] pairs, increasing in command.
    Table {
        /// The pairs.
        points: Vec<[f64; 2]>,
    },
}

/// Thruster (see [`ThrusterParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThrusterSpec {
    /// Name.
    pub name: String,
    /// Body-frame position \[m\].
    pub position: [f64; 3],
    /// Thrust direction at tilt 0, body frame (normalised on load).
    pub direction: [f64; 3],
    /// Name of the tilt drive that turns it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tilt: Option<String>,
    /// Thrust curve.
    pub curve: CurveSpec,
    /// Command limit [%].
    #[serde(default = "d_max_command")]
    pub max_command: f64,
    /// First-order thrust lag time constant \[s\] (0 = none).
    #[serde(default)]
    pub lag: f64,
}

/// Buoyancy tank (see [`BallastParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallastSpec {
    /// Capacity \[m³\].
    pub capacity: f64,
    /// Pump flow [m³/s].
    pub flow: f64,
    /// Tank water centre, body frame \[m\].
    pub position: [f64; 3],
    /// Water aboard at the start \[m³\].
    pub initial_volume: f64,
}

/// Pressure sensor (see [`PressureSensorParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSpec {
    /// C₁ [m/V].
    pub c1: f64,
    /// C₂ \[m\].
    pub c2: f64,
    /// Depth per ADC step \[m\].
    pub depth_step: f64,
    /// ADC bits.
    pub bits: u32,
    /// Noise standard deviation \[m\].
    pub noise_std: f64,
    /// Port position, body frame \[m\].
    pub position: [f64; 3],
}

/// IMU (see [`ImuParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImuSpec {
    /// Attitude noise per axis \[deg\].
    pub attitude_noise_deg: f64,
    /// Gyro noise [rad/s].
    pub gyro_noise: f64,
    /// Gyro bias [rad/s].
    pub gyro_bias: [f64; 3],
    /// Accelerometer noise [m/s²].
    pub accel_noise: f64,
}

/// PD design (see [`PdDesign`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdSpec {
    /// Natural frequency [rad/s].
    pub omega: f64,
    /// Damping ratio [-].
    pub zeta: f64,
    /// Explicit K_P [N/m or N·m/rad].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kp: Option<f64>,
    /// Explicit K_D [N·s/m or N·m·s/rad].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kd: Option<f64>,
}

/// Controller (see [`ControlParams`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// Control period \[s\].
    pub period: f64,
    /// Heave PD (diving, auto).
    pub heave: PdSpec,
    /// Heave PD (buoyancy mode).
    pub heave_buoyancy: PdSpec,
    /// Yaw PD.
    pub yaw: PdSpec,
    /// Pump dead zone \[m\].
    pub dead_zone: f64,
    /// Moving-average window \[samples\].
    pub filter_window: usize,
    /// Largest |β| in auto mode \[deg\].
    pub auto_tilt_max_deg: f64,
    /// Depth-rate filter time constant \[s\].
    pub rate_filter: f64,
}

impl Mat3Spec {
    fn to_matrix(&self) -> Mat3 {
        match self {
            Mat3Spec::Diagonal(d) => Mat3::from_diagonal(&v3(*d)),
            Mat3Spec::Full(r) => Mat3::from_fn(|i, j| r[i][j]),
        }
    }
    fn from_matrix(m: &Mat3) -> Self {
        if m.is_diagonal(0.0) {
            Mat3Spec::Diagonal([m[(0, 0)], m[(1, 1)], m[(2, 2)]])
        } else {
            Mat3Spec::Full(std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])))
        }
    }
}

trait IsDiagonal {
    fn is_diagonal(&self, eps: f64) -> bool;
}
impl<const N: usize> IsDiagonal for nalgebra::SMatrix<f64, N, N> {
    fn is_diagonal(&self, eps: f64) -> bool {
        (0..N).all(|i| (0..N).all(|j| i == j || self[(i, j)].abs() <= eps))
    }
}

impl Mat6Spec {
    fn to_matrix(&self) -> Mat6 {
        match self {
            Mat6Spec::Diagonal(d) => Mat6::from_diagonal(&Vec6::from_row_slice(d)),
            Mat6Spec::Full(r) => Mat6::from_fn(|i, j| r[i][j]),
        }
    }
    fn from_matrix(m: &Mat6) -> Self {
        if m.is_diagonal(0.0) {
            Mat6Spec::Diagonal(std::array::from_fn(|i| m[(i, i)]))
        } else {
            Mat6Spec::Full(Box::new(std::array::from_fn(|i| {
                std::array::from_fn(|j| m[(i, j)])
            })))
        }
    }
}

fn pd_to(p: &PdSpec) -> PdDesign {
    PdDesign {
        omega: p.omega,
        zeta: p.zeta,
        kp: p.kp,
        kd: p.kd,
    }
}
fn pd_from(p: &PdDesign) -> PdSpec {
    PdSpec {
        omega: p.omega,
        zeta: p.zeta,
        kp: p.kp,
        kd: p.kd,
    }
}

impl VehicleSpec {
    /// The model parameters (angles converted to radians, directions normalised). Call only
    /// after validation: unknown tilt names map to no tilt.
    pub fn to_params(&self) -> VehicleParams {
        let b = &self.body;
        let tilt_index = |n: &Option<String>| {
            n.as_ref()
                .and_then(|n| self.tilts.iter().position(|t| &t.name == n))
        };
        VehicleParams {
            name: self.name.clone(),
            body: BodyParams {
                mass: b.mass,
                inertia_cg: b.inertia.to_matrix(),
                cog: v3(b.cog),
                cob: v3(b.cob),
                volume: b.volume,
                added_mass: b.added_mass.to_matrix(),
                damping_linear: Vec6::from_row_slice(&b.damping_linear),
                damping_quadratic: Vec6::from_row_slice(&b.damping_quadratic),
                hull_size: v3(b.hull_size),
            },
            thrusters: self
                .thrusters
                .iter()
                .map(|t| ThrusterParams {
                    name: t.name.clone(),
                    position: v3(t.position),
                    direction: unit_or_x(t.direction),
                    tilt: tilt_index(&t.tilt),
                    curve: match &t.curve {
                        CurveSpec::Quadratic { ct_pos, ct_neg } => ThrustCurve::Quadratic {
                            ct_pos: *ct_pos,
                            ct_neg: *ct_neg,
                        },
                        CurveSpec::Table { points } => ThrustCurve::Table {
                            points: points.iter().map(|p| (p[0], p[1])).collect(),
                        },
                    },
                    max_command: t.max_command,
                    lag: t.lag,
                    lag_down: -1.0,
                    lag_stages: 1,
                    ramp: 0.0,
                })
                .collect(),
            tilts: self
                .tilts
                .iter()
                .map(|t| TiltParams {
                    name: t.name.clone(),
                    axis: unit_or_x(t.axis),
                    min: t.min_deg.to_radians(),
                    max: t.max_deg.to_radians(),
                    rate_max: t.rate_deg_s.to_radians(),
                })
                .collect(),
            ballast: self.ballast.as_ref().map(|b| BallastParams {
                capacity: b.capacity,
                flow: b.flow,
                position: v3(b.position),
                initial_volume: b.initial_volume,
            }),
            pressure: PressureSensorParams {
                c1: self.pressure.c1,
                c2: self.pressure.c2,
                depth_step: self.pressure.depth_step,
                bits: self.pressure.bits,
                noise_std: self.pressure.noise_std,
                position: v3(self.pressure.position),
            },
            imu: ImuParams {
                attitude_noise: self.imu.attitude_noise_deg.to_radians(),
                gyro_noise: self.imu.gyro_noise,
                gyro_bias: v3(self.imu.gyro_bias),
                accel_noise: self.imu.accel_noise,
            },
            control: ControlParams {
                period: self.control.period,
                heave: pd_to(&self.control.heave),
                heave_buoyancy: pd_to(&self.control.heave_buoyancy),
                yaw: pd_to(&self.control.yaw),
                dead_zone: self.control.dead_zone,
                filter_window: self.control.filter_window,
                auto_tilt_max: self.control.auto_tilt_max_deg.to_radians(),
                rate_filter: self.control.rate_filter,
            },
            modems: self.modems.iter().map(ModemSpec::to_params).collect(),
        }
    }

    /// The file form of model parameters.
    pub fn from_params(p: &VehicleParams) -> Self {
        let b = &p.body;
        VehicleSpec {
            name: p.name.clone(),
            body: BodySpec {
                mass: b.mass,
                inertia: Mat3Spec::from_matrix(&b.inertia_cg),
                cog: a3(&b.cog),
                cob: a3(&b.cob),
                volume: b.volume,
                added_mass: Mat6Spec::from_matrix(&b.added_mass),
                damping_linear: a6(&b.damping_linear),
                damping_quadratic: a6(&b.damping_quadratic),
                hull_size: a3(&b.hull_size),
            },
            tilts: p
                .tilts
                .iter()
                .map(|t| TiltSpec {
                    name: t.name.clone(),
                    axis: a3(&t.axis),
                    min_deg: t.min.to_degrees(),
                    max_deg: t.max.to_degrees(),
                    rate_deg_s: t.rate_max.to_degrees(),
                })
                .collect(),
            thrusters: p
                .thrusters
                .iter()
                .map(|t| ThrusterSpec {
                    name: t.name.clone(),
                    position: a3(&t.position),
                    direction: a3(&t.direction),
                    tilt: t.tilt.map(|k| p.tilts[k].name.clone()),
                    curve: match &t.curve {
                        ThrustCurve::Quadratic { ct_pos, ct_neg } => CurveSpec::Quadratic {
                            ct_pos: *ct_pos,
                            ct_neg: *ct_neg,
                        },
                        ThrustCurve::Table { points } => CurveSpec::Table {
                            points: points.iter().map(|&(c, f)| [c, f]).collect(),
                        },
                    },
                    max_command: t.max_command,
                    lag: t.lag,
                })
                .collect(),
            ballast: p.ballast.as_ref().map(|b| BallastSpec {
                capacity: b.capacity,
                flow: b.flow,
                position: a3(&b.position),
                initial_volume: b.initial_volume,
            }),
            pressure: PressureSpec {
                c1: p.pressure.c1,
                c2: p.pressure.c2,
                depth_step: p.pressure.depth_step,
                bits: p.pressure.bits,
                noise_std: p.pressure.noise_std,
                position: a3(&p.pressure.position),
            },
            imu: ImuSpec {
                attitude_noise_deg: p.imu.attitude_noise.to_degrees(),
                gyro_noise: p.imu.gyro_noise,
                gyro_bias: a3(&p.imu.gyro_bias),
                accel_noise: p.imu.accel_noise,
            },
            control: ControlSpec {
                period: p.control.period,
                heave: pd_from(&p.control.heave),
                heave_buoyancy: pd_from(&p.control.heave_buoyancy),
                yaw: pd_from(&p.control.yaw),
                dead_zone: p.control.dead_zone,
                filter_window: p.control.filter_window,
                auto_tilt_max_deg: p.control.auto_tilt_max.to_degrees(),
                rate_filter: p.control.rate_filter,
            },
            modems: p.modems.iter().map(ModemSpec::from_params).collect(),
            effects: Vec::new(),
        }
    }

    /// The effects for a vehicle with parameters `params` (from [`VehicleSpec::to_params`]).
    /// Call only after validation: unknown effects are skipped and missing parameters take
    /// their null values.
    pub fn effects(&self, params: &VehicleParams) -> shoal_model::effects::Effects {
        use shoal_model::effects::{EffectInstance, Effects, by_name_form};
        Effects::new(
            self.effects
                .iter()
                .filter_map(|e| {
                    let effect = by_name_form(&e.name, e.form.as_deref())?;
                    let values = effect
                        .params(params)
                        .iter()
                        .map(|p| e.params.get(p.name).copied().unwrap_or(p.null))
                        .collect();
                    Some(EffectInstance {
                        effect,
                        params: values,
                    })
                })
                .collect(),
        )
    }

    /// The file form of a list of effects.
    pub fn effect_specs(
        list: &[shoal_model::effects::EffectInstance],
        params: &VehicleParams,
    ) -> Vec<EffectSpec> {
        list.iter()
            .map(|e| EffectSpec {
                name: e.effect.name().to_string(),
                form: (shoal_model::effects::forms(e.effect.name()).first()
                    != Some(&e.effect.form()))
                .then(|| e.effect.form().to_string()),
                params: e
                    .effect
                    .params(params)
                    .iter()
                    .zip(&e.params)
                    .map(|(p, &x)| (p.name.to_string(), x))
                    .collect(),
            })
            .collect()
    }
}
