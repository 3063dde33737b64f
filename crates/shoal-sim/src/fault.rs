//! The run-time guard against non-finite states. Valid parameters can still meet a state the
//! model cannot continue from (an agent's extreme command, a numerical blow-up): the dynamics
//! system checks every vehicle's state after integrating it, and a state that is no longer
//! finite is put back to the last finite one and recorded, so that NaN never reaches the
//! collision geometry or the outputs. [`crate::sim::Sim::step`] then reports the first such
//! vehicle as a [`SimFault`], and the caller stops the run.

use bevy_ecs::prelude::*;
use shoal_model::prelude::*;
use std::fmt;
use std::sync::atomic::AtomicBool;

/// What a vehicle's state was when it stopped being finite.
#[derive(Clone, Debug, PartialEq)]
pub struct NonFinite {
    /// Simulated time at the end of the step that produced the non-finite state \[s\].
    pub time: f64,
    /// The last finite state, before that step.
    pub last: RigidState,
}

/// Set when any vehicle's state became non-finite in the last step.
#[derive(Resource, Debug, Default)]
pub struct FaultFlag(pub AtomicBool);

/// The first vehicle (lowest id) whose state became non-finite.
#[derive(Clone, Debug, PartialEq)]
pub struct SimFault {
    /// Vehicle id (index in the world file's expansion order).
    pub vehicle: usize,
    /// Vehicle name.
    pub name: String,
    /// When it happened and the last finite state.
    pub state: NonFinite,
}

/// A state component for messages: fixed point when readable, else scientific.
fn num(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:.4e}")
    } else {
        format!("{x:.4}")
    }
}

impl fmt::Display for SimFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.state.last;
        let (r, p, y) = s.attitude.euler_angles();
        let v = |a: &[f64]| a.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ");
        write!(
            f,
            "the state of vehicle `{}` (id {}) became non-finite at t = {} s; last finite state: \
             position ({}) m, roll/pitch/yaw ({:.2}, {:.2}, {:.2}) deg, velocity ({}) m/s, \
             rates ({}) rad/s",
            self.name,
            self.vehicle,
            self.state.time,
            v(s.position.as_slice()),
            r.to_degrees(),
            p.to_degrees(),
            y.to_degrees(),
            v(&s.nu.as_slice()[..3]),
            v(&s.nu.as_slice()[3..]),
        )
    }
}
