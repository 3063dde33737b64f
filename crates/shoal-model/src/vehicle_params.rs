//! The description of one kind of vehicle as given ([`VehicleParams`]): hull, thrusters, tilt
//! drives, buoyancy tank, sensors, built-in controller and modems, with the mass properties
//! and weight they imply. It knows nothing of the model extensions that adjust it or of the
//! vehicle model built from it: both build on it (`effects`, `vehicle`).

use crate::ballast::BallastParams;
use crate::control::ControlParams;
use crate::math::Vec3;
use crate::optics::ModemParams;
use crate::rigid_body::{BodyParams, Environment, MassProperties};
use crate::sensors::{ImuParams, PressureSensorParams};
use crate::thruster::{ThrusterParams, TiltParams};

/// Everything that describes one kind of vehicle.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleParams {
    /// Name of the vehicle kind (e.g. `uauv2`).
    pub name: String,
    /// Hull: rigid body, added mass, damping.
    pub body: BodyParams,
    /// Thrusters.
    pub thrusters: Vec<ThrusterParams>,
    /// Tilt drives (thrusters refer to them by index).
    pub tilts: Vec<TiltParams>,
    /// Buoyancy tank, if fitted.
    pub ballast: Option<BallastParams>,
    /// Pressure (depth) sensor.
    pub pressure: PressureSensorParams,
    /// Inertial measurement unit.
    pub imu: ImuParams,
    /// Built-in controller.
    pub control: ControlParams,
    /// Optical modems.
    pub modems: Vec<ModemParams>,
}

impl VehicleParams {
    /// Mass properties with `ballast_volume` \[m³\] of water of `density` [kg/m³] in the tank.
    pub fn mass_properties(&self, ballast_volume: f64, density: f64) -> MassProperties {
        let pos = self.ballast.as_ref().map_or(Vec3::zeros(), |b| b.position);
        MassProperties::new(&self.body, ballast_volume, &pos, density)
    }

    /// Initial ballast water volume \[m³\].
    pub fn initial_ballast(&self) -> f64 {
        self.ballast.as_ref().map_or(0.0, |b| b.initial_volume)
    }

    /// Net downward force at rest, fully submerged, with the initial ballast \[N\]
    /// (positive: the vehicle sinks; negative: it rises).
    pub fn net_weight(&self, env: &Environment) -> f64 {
        let m = self.body.mass + self.initial_ballast() * env.density;
        (m - self.body.volume * env.density) * env.gravity
    }
}
