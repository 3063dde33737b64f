//! The pool, its water (density, attenuation, current, ambient light) and the static
//! obstacles in it.

use serde::{Deserialize, Serialize};

fn d_density() -> f64 {
    1000.0
}
fn d_pool() -> [f64; 3] {
    [10.0, 10.0, 3.0]
}

/// A rectangular pool: corner at the origin on the surface, x north, y east, z down.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoolSpec {
    /// Length (x), width (y) and depth (z) \[m\].
    #[serde(default = "d_pool")]
    pub size: [f64; 3],
}

impl Default for PoolSpec {
    fn default() -> Self {
        Self { size: d_pool() }
    }
}

/// Beam attenuation of the water: a named water type or a number [1/m].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum AttenuationSpec {
    /// Beam attenuation coefficient c [1/m].
    Coefficient(f64),
    /// `pure_sea`, `clear_ocean`, `coastal`, `turbid_harbour` or `pool`.
    Named(String),
}

impl Default for AttenuationSpec {
    fn default() -> Self {
        AttenuationSpec::Named("pool".into())
    }
}

/// Named water types and their beam attenuation c = a + b at ≈530 nm [1/m] (Mobley via Hanson
/// & Radic 2008; `pool`: clean fresh water, near the pure-water value).
pub const WATER_TYPES: [(&str, f64); 5] = [
    ("pure_sea", 0.056),
    ("clear_ocean", 0.151),
    ("coastal", 0.398),
    ("turbid_harbour", 2.19),
    ("pool", 0.07),
];

/// The water.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaterSpec {
    /// Density [kg/m³].
    #[serde(default = "d_density")]
    pub density: f64,
    /// Beam attenuation: a water type name or a coefficient [1/m].
    #[serde(default)]
    pub attenuation: AttenuationSpec,
    /// Constant current in the world frame (north, east, down) [m/s].
    #[serde(default)]
    pub current: [f64; 3],
    /// Ambient light just below the surface within the modems' optical band [W/m²]
    /// (0.5: an indoor pool; ≈50: daylight outdoors).
    #[serde(default = "d_ambient")]
    pub ambient_irradiance: f64,
    /// Diffuse attenuation of the ambient light with depth [1/m].
    #[serde(default = "d_kd")]
    pub diffuse_attenuation: f64,
}

fn d_ambient() -> f64 {
    0.5
}
fn d_kd() -> f64 {
    0.1
}

impl Default for WaterSpec {
    fn default() -> Self {
        Self {
            density: d_density(),
            attenuation: AttenuationSpec::default(),
            current: [0.0; 3],
            ambient_irradiance: d_ambient(),
            diffuse_attenuation: d_kd(),
        }
    }
}

/// Obstacle shape kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeKind {
    /// Box with full extents `size`.
    Box,
    /// Sphere of `radius`.
    Sphere,
    /// Cylinder of `radius` and full `height` along its local z axis.
    Cylinder,
    /// Capsule of `radius` whose straight part has full `height` along its local z axis.
    Capsule,
}

/// One static obstacle.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// Optional name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Shape kind.
    pub shape: ShapeKind,
    /// Full extents of a box (x, y, z) \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 3]>,
    /// Radius of a sphere, cylinder or capsule \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Full height of a cylinder, or of a capsule's straight part \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Centre in the world frame \[m\].
    pub position: [f64; 3],
    /// Roll, pitch, yaw of the shape \[deg\].
    #[serde(default)]
    pub rotation_deg: [f64; 3],
}
