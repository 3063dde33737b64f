//! Borrowed views of the vehicles of a running world: what the end-of-run outputs read
//! (final state, readings, setpoints, contacts, optical counters) without copying it.
//!
//! [`crate::sim::Sim::vehicle`] copies one vehicle (about 1.5 KB and a few small heap
//! blocks); a million such copies would double a large world's memory just to write its
//! summary. A [`VehicleView`] is a handful of references (≈ 100 B), so the outputs of a
//! 10⁶-vehicle world cost ≈ 0.1 GB on top of the world itself.

use crate::behaviour::Behave;
use crate::comm::CommStats;
use crate::components::{ContactStats, VehicleId, VehicleNames};
use crate::fleet::Fleet;
use bevy_ecs::prelude::*;
use shoal_model::prelude::*;
use std::sync::Arc;

/// One vehicle as the world holds it, borrowed.
#[derive(Clone, Copy)]
pub struct VehicleView<'a> {
    /// Id (index in the world file's expansion order).
    pub id: u32,
    /// Unique name.
    pub name: &'a str,
    /// Its kind's model.
    pub model: &'a Arc<VehicleModel>,
    /// Dynamic state.
    pub state: &'a VehicleState,
    /// Latest readings.
    pub sensors: &'a SensorReadings,
    /// Current setpoints.
    pub setpoints: &'a Setpoints,
    /// Hull contacts.
    pub contacts: ContactStats,
    /// Optical communication counters (per-sender statistics complete after
    /// [`crate::sim::Sim::fold_comm`]).
    pub comm: &'a CommStats,
    behave: Option<&'a Behave>,
}

impl<'a> VehicleView<'a> {
    /// The view of `entity`, or `None` when it lacks one of a vehicle's components.
    pub fn of(world: &'a World, entity: Entity) -> Option<Self> {
        let e = world.get_entity(entity).ok()?;
        let id = *e.get::<VehicleId>()?;
        let v = world
            .get_resource::<Fleet>()?
            .as_slice()
            .get(id.0 as usize)?;
        Some(Self {
            id: id.0,
            name: world.get_resource::<VehicleNames>()?.get(id.0 as usize)?,
            model: &v.model,
            state: &v.physics.state,
            sensors: &v.sensors,
            setpoints: &v.control.setpoints,
            contacts: v.contacts,
            comm: e.get::<CommStats>()?,
            behave: e.get::<Behave>(),
        })
    }

    /// Results reported by the vehicle's behaviour (name, value); empty without one.
    pub fn behaviour(&self) -> Vec<(&'static str, f64)> {
        self.behave
            .map(|b| b.behaviour.report())
            .unwrap_or_default()
    }
}
