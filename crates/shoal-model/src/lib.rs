//! # shoal-model
//!
//! Pure physics of small underwater vehicles, with the DFKI μAUV² as the default preset:
//! 6-DOF Fossen rigid-body dynamics with added mass, Coriolis, damping and restoring forces
//! ([`rigid_body`], [`dynamics`]); tilting thrusters ([`thruster`]); the buoyancy tank
//! ([`ballast`]); pressure sensor and IMU ([`sensors`]); the paper's controllers and modes
//! ([`control`]); shoal's frames and ROS's ([`frames`]); the description of a vehicle kind ([`vehicle_params`]), model extensions
//! ([`effects`]), a whole vehicle ([`vehicle`]) and presets ([`presets`]).
//!
//! This crate does no IO and knows nothing of ECS: every function takes plain data and the
//! caller's RNG. SI units throughout; angles in radians.

pub mod ballast;
pub mod control;
pub mod dynamics;
pub mod effects;
pub mod frames;
pub mod lanes;
pub mod math;
pub mod optics;
pub mod presets;
pub mod rigid_body;
pub mod sensors;
pub mod thruster;
pub mod vehicle;
pub mod vehicle_params;

/// The commonly used types.
pub mod prelude {
    pub use crate::ballast::{BallastParams, Pump};
    pub use crate::control::{
        ActuatorCommands, ControlParams, ControllerState, Mission, MissionCursor, MissionStep,
        Mode, PdDesign, SensorReadings, Setpoints,
    };
    pub use crate::dynamics::{Integrator, RigidState};
    pub use crate::math::{Mat3, Mat6, PerActuator, Quat, Vec3, Vec6, quat_from_rpy, wrap_pi};
    pub use crate::presets;
    pub use crate::rigid_body::{BodyParams, Environment, MassProperties};
    pub use crate::sensors::{ImuParams, PressureSensorParams};
    pub use crate::thruster::{ThrustCurve, ThrusterParams, TiltParams};
    pub use crate::vehicle::{
        VehicleModel, VehicleState, actuate_vehicle, integrate_vehicle, sense, step,
    };
    pub use crate::vehicle_params::VehicleParams;
}
