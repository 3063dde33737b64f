//! ECS components and resources of the simulated world, and the parts of a vehicle's hot state
//! ([`crate::fleet::HotVehicle`]) that wrap shoal-model types. Components are thin wrappers
//! around shoal-model types; resources hold the world-wide settings.

use bevy_ecs::prelude::*;
use shoal_model::prelude::*;
use shoal_world::geometry::Geometry;
use std::sync::Arc;

/// Stable index of a vehicle (its position in the world file's expansion order).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VehicleId(pub u32);

/// The entity of every vehicle, by id (so that a system can reach the few vehicles a step
/// concerns without visiting all of them).
#[derive(Resource, Clone, Debug, Default)]
pub struct VehicleEntities(pub Vec<Entity>);

impl VehicleEntities {
    /// The entities of vehicles `ids` (distinct, each below the vehicle count), as a set the
    /// ECS can fetch mutable components of, in the order of `ids` (an index set: its entity
    /// hash is a multiplication, where an ordered set costs a tree and loses that order).
    pub fn set_of(&self, ids: &[u32]) -> bevy_ecs::entity::index_set::EntityIndexSet {
        ids.iter().map(|&i| self.0[i as usize]).collect()
    }
}

/// The unique names of all vehicles, by id, back to back in one buffer: a name per entity
/// would cost a heap block, a `String` and its change ticks per vehicle (≈ 60 B, 3 % of a
/// quiet vehicle).
#[derive(Resource, Clone, Debug, Default)]
pub struct VehicleNames {
    text: String,
    /// End of each name in `text` \[bytes\].
    ends: Vec<usize>,
}

impl VehicleNames {
    /// Room for `n` names.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            text: String::new(),
            ends: Vec::with_capacity(n),
        }
    }

    /// Appends the name of the next vehicle (id = the number of names before the call).
    pub fn push(&mut self, name: &str) {
        self.text.push_str(name);
        self.ends.push(self.text.len());
    }

    /// The name of vehicle `id`, if there is such a vehicle.
    pub fn get(&self, id: usize) -> Option<&str> {
        let end = *self.ends.get(id)?;
        let start = id.checked_sub(1).map_or(0, |k| self.ends[k]);
        self.text.get(start..end)
    }

    /// Number of names.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// Whether there are no names.
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }
}

/// Dynamic state, and what became of it if it stopped being finite.
#[derive(Clone, Debug)]
pub struct Physics {
    /// The state.
    pub state: VehicleState,
    /// Set when the state stopped being finite (boxed: almost always `None`).
    pub fault: Option<Box<crate::fault::NonFinite>>,
}

/// The built-in controller with its mission.
#[derive(Clone, Debug)]
pub struct Control {
    /// Controller internal state.
    pub state: ControllerState,
    /// Current setpoints.
    pub setpoints: Setpoints,
    /// The mission.
    pub mission: Arc<Mission>,
    /// Position in the mission.
    pub cursor: MissionCursor,
    /// Control period in physics steps.
    pub every: u64,
}

/// The earliest time at which some vehicle's mission still has a step to apply \[s\] (+∞ when
/// every mission is done): before it the mission system has nothing to do and looks at no
/// vehicle. Code that changes a vehicle's mission or cursor sets it back to its default (−∞),
/// so that the next step looks at every vehicle again.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct MissionClock(pub f64);

impl Default for MissionClock {
    fn default() -> Self {
        Self(f64::NEG_INFINITY)
    }
}

/// Hull contacts with the static world.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactStats {
    /// Steps spent in contact.
    pub steps_in_contact: u64,
    /// Number of separate impacts (contact after a free step).
    pub impacts: u64,
    /// Deepest penetration resolved \[m\].
    pub max_depth: f64,
    /// Whether the hull touched something in the last step.
    pub touching: bool,
}

/// Recorded trajectory rows of every vehicle since the last drain, by id (flat,
/// `Recorder::stride` values per row); empty when the world does not record, so that a
/// world without recording carries nothing per vehicle for it.
#[derive(Resource, Clone, Debug, Default)]
pub struct Tracks(pub Vec<Vec<f64>>);

/// Simulation clock.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Clock {
    /// Steps completed.
    pub step: u64,
    /// Physics step \[s\].
    pub dt: f64,
}

impl Clock {
    /// Simulated time at the start of the current step \[s\].
    pub fn t(&self) -> f64 {
        self.step as f64 * self.dt
    }
}

/// Water and integrator settings.
#[derive(Resource, Clone, Debug)]
pub struct Physical {
    /// Water and gravity.
    pub env: Environment,
    /// Integrator.
    pub integrator: Integrator,
}

/// Pool and obstacles.
#[derive(Resource, Clone, Debug)]
pub struct StaticGeometry(pub Geometry);

/// Trajectory recording settings.
#[derive(Resource, Clone, Copy, Debug)]
pub struct RecordConfig {
    /// Record every this many steps (0 = never).
    pub every: u64,
}

/// Marks a vehicle driven by an external agent.
#[derive(Component, Clone, Debug)]
pub struct External {
    /// Index of its agent in [`shoal_world::desc::AgentsDesc::names`].
    pub agent: usize,
    /// Whether the fallback is in force (the agent is absent, hung or dead).
    pub fallback: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_come_back_by_id() {
        let mut n = VehicleNames::with_capacity(3);
        for name in ["a", "", "bc-2"] {
            n.push(name);
        }
        assert_eq!(n.len(), 3);
        assert_eq!(
            (0..4).map(|i| n.get(i)).collect::<Vec<_>>(),
            [Some("a"), Some(""), Some("bc-2"), None]
        );
    }
}
