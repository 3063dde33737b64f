//! The hot state of the swarm: everything the fused vehicle pass reads and writes, per vehicle,
//! in one contiguous array in vehicle-id order ([`Fleet`]).
//!
//! The pass walks it in groups of [`shoal_model::lanes::LANES`] consecutive vehicles, which the
//! lane kernel integrates together, and hands runs of groups to the world's thread pool as
//! plain slices: no per-step list of ECS component references is built (with seven components
//! per vehicle that list cost about 30 ns per vehicle, on the calling thread while the workers
//! waited), and a vehicle's data sits in one place instead of seven tables. The ECS entity of
//! a vehicle keeps what the pass does not touch (modems and their queues, inbox, outbox,
//! communication counters, behaviour, agent) and its [`VehicleId`], the index into the fleet;
//! names ([`crate::components::VehicleNames`]) and trajectory buffers
//! ([`crate::components::Tracks`]) are arrays by id beside it, and the model is read here (the
//! medium keeps its own array of models, [`crate::comm::Medium::kinds`]).
//!
//! Vehicles are never added or removed after the world is built, so id `i` is always entry `i`.

use crate::components::{ContactStats, Control, Physics, VehicleId};
use crate::rng::VehicleRng;
use bevy_ecs::prelude::Resource;
use shoal_model::control::ActuatorCommands;
use shoal_model::prelude::SensorReadings;
use shoal_model::vehicle::VehicleModel;
use std::sync::Arc;

/// What the vehicle pass touches of one vehicle.
#[derive(Clone, Debug)]
pub struct HotVehicle {
    /// Its kind's model (shared by the vehicles of a kind).
    pub model: Arc<VehicleModel>,
    /// Dynamic state.
    pub physics: Physics,
    /// The built-in controller, its setpoints and mission.
    pub control: Control,
    /// Actuator commands in force (written by the controller or an agent).
    pub commands: ActuatorCommands,
    /// The latest sensor readings.
    pub sensors: SensorReadings,
    /// The vehicle's own random stream for sensor noise (from the world seed and its id).
    pub sensor_rng: VehicleRng,
    /// Hull contacts with the static world.
    pub contacts: ContactStats,
}

/// The hot state of every vehicle, entry `i` for vehicle id `i`.
#[derive(Resource, Clone, Debug, Default)]
pub struct Fleet {
    vehicles: Vec<HotVehicle>,
}

impl Fleet {
    /// An empty fleet with room for `n` vehicles (so that building a large world does not
    /// hold the array twice while it grows).
    pub fn with_capacity(n: usize) -> Self {
        Self {
            vehicles: Vec::with_capacity(n),
        }
    }

    /// Appends the vehicle with the next id (its id is the fleet's length before the call).
    pub fn push(&mut self, v: HotVehicle) {
        self.vehicles.push(v);
    }

    /// Number of vehicles.
    pub fn len(&self) -> usize {
        self.vehicles.len()
    }

    /// Whether the fleet has no vehicles.
    pub fn is_empty(&self) -> bool {
        self.vehicles.is_empty()
    }

    /// Vehicle `id`.
    ///
    /// # Panics
    /// If `id` is not a vehicle of this world.
    pub fn get(&self, id: VehicleId) -> &HotVehicle {
        &self.vehicles[id.0 as usize]
    }

    /// Vehicle `id`, mutably.
    ///
    /// # Panics
    /// If `id` is not a vehicle of this world.
    pub fn get_mut(&mut self, id: VehicleId) -> &mut HotVehicle {
        &mut self.vehicles[id.0 as usize]
    }

    /// Every vehicle in id order.
    pub fn as_slice(&self) -> &[HotVehicle] {
        &self.vehicles
    }

    /// Every vehicle in id order, mutably.
    pub fn as_mut_slice(&mut self) -> &mut [HotVehicle] {
        &mut self.vehicles
    }

    /// The vehicles with the given ids (strictly increasing), mutably, in that order.
    ///
    /// # Panics
    /// If the ids are not strictly increasing or one is not a vehicle of this world.
    pub fn select_mut(&mut self, ids: impl IntoIterator<Item = u32>) -> Vec<&mut HotVehicle> {
        let mut rest = self.vehicles.as_mut_slice();
        let mut base = 0usize;
        let mut out = Vec::new();
        for id in ids {
            let skip = (id as usize)
                .checked_sub(base)
                .expect("vehicle ids strictly increasing");
            let (v, tail) = std::mem::take(&mut rest)[skip..]
                .split_first_mut()
                .expect("a vehicle of this world");
            out.push(v);
            rest = tail;
            base = id as usize + 1;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::prelude::*;

    fn fleet(n: usize) -> Fleet {
        let m = Arc::new(VehicleModel::new(presets::uauv2(), 1000.0));
        let env = Environment::default();
        let mut f = Fleet::default();
        for i in 0..n {
            let rest = RigidState::at_rest(Vec3::zeros(), Quat::identity());
            let state = VehicleState::new(&m, rest, &env);
            f.push(HotVehicle {
                model: m.clone(),
                physics: Physics { state, fault: None },
                control: Control {
                    state: m.controller(),
                    setpoints: Setpoints::default(),
                    mission: Arc::new(Mission::default()),
                    cursor: MissionCursor::default(),
                    every: i as u64 + 1,
                },
                commands: m.zero_commands(),
                sensors: SensorReadings::zeros(m.params.tilts.len()),
                sensor_rng: crate::rng::vehicle_rng(1, i as u32, crate::rng::stream::SENSORS),
                contacts: ContactStats::default(),
            });
        }
        f
    }

    #[test]
    fn select_mut_gives_the_vehicles_asked_for_in_order() {
        let mut f = fleet(6);
        let got: Vec<u64> = f
            .select_mut([0, 2, 5])
            .iter()
            .map(|v| v.control.every - 1)
            .collect();
        assert_eq!(got, [0, 2, 5]);
        assert!(f.select_mut([]).is_empty());
        assert_eq!(f.get(VehicleId(3)).control.every, 4);
    }

    #[test]
    #[should_panic(expected = "strictly increasing")]
    fn select_mut_refuses_ids_out_of_order() {
        let mut f = fleet(4);
        let _ = f.select_mut([2, 1]);
    }
}
