//! The simulated world: a bevy_ecs [`World`] with one entity per vehicle, driven one fixed step
//! at a time by the schedule of [`crate::systems`].

use crate::behaviour::{self, Behave};
use crate::comm::{CommStats, Inbox, Ledger, Link, Medium, Modems, Outbox, comm_rng};
use crate::components::*;
use crate::connectivity::Connectivity;
use crate::fault::{FaultFlag, SimFault};
use crate::fleet::{Fleet, HotVehicle};
use crate::parallel::{Dispatches, Parallel};
use crate::phases::{PhaseClock, PhaseTimes};
use crate::recorder::{self, RecordBatch};
use crate::systems::build_schedule;
use crate::view::VehicleView;
use bevy_ecs::prelude::*;
use shoal_model::math::euler_rpy;
use shoal_model::prelude::*;
use shoal_world::cancel::{Cancel, Interrupted};
use shoal_world::desc::WorldDesc;
use shoal_world::spec::FallbackSpec;
use std::sync::Arc;

/// How a world runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SimOptions {
    /// Working threads for per-vehicle loops (≥ 1).
    pub threads: usize,
    /// Record trajectories at the world's `record_hz`.
    pub record: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            threads: 1,
            record: true,
        }
    }
}

pub use crate::rng::{VehicleRng, stream, vehicle_rng};

/// A read-only copy of one vehicle.
#[derive(Clone, Debug)]
pub struct VehicleSnapshot {
    /// Id.
    pub id: u32,
    /// Name.
    pub name: String,
    /// Model.
    pub model: Arc<VehicleModel>,
    /// Dynamic state.
    pub state: VehicleState,
    /// Latest readings.
    pub sensors: SensorReadings,
    /// Current setpoints.
    pub setpoints: Setpoints,
    /// Commands in force.
    pub commands: ActuatorCommands,
    /// Contact statistics.
    pub contacts: ContactStats,
    /// Optical communication counters.
    pub comm: CommStats,
    /// Results reported by the vehicle's behaviour (name, value).
    pub behaviour: Vec<(&'static str, f64)>,
}

/// A running world.
pub struct Sim {
    world: World,
    schedule: Schedule,
    fault: Option<SimFault>,
}

impl Sim {
    /// Spawns every vehicle of `desc` and prepares the schedule. A recording world
    /// ([`SimOptions::record`]) whose `[output] mcap` is on also logs every reception attempt
    /// for [`Sim::drain`] (`run.mcap` writes them).
    pub fn new(desc: &WorldDesc, opts: SimOptions) -> Self {
        match Self::new_until(desc, opts, &Cancel::new()) {
            Ok(sim) => sim,
            Err(Interrupted) => unreachable!("a private Cancel is never requested"),
        }
    }

    /// [`Sim::new`] that gives up once `cancel` asks it to (it looks before each vehicle).
    pub fn new_until(
        desc: &WorldDesc,
        opts: SimOptions,
        cancel: &Cancel,
    ) -> Result<Self, Interrupted> {
        let mut world = World::new();
        world.insert_resource(Clock {
            step: 0,
            dt: desc.dt,
        });
        world.insert_resource(Physical {
            env: desc.env,
            integrator: desc.integrator,
        });
        world.insert_resource(StaticGeometry(desc.geometry.clone()));
        world.insert_resource(FaultFlag::default());
        world.insert_resource(MissionClock::default());
        world.insert_resource(Parallel::new(opts.threads));
        let link: Vec<_> = desc.vehicles.iter().map(|v| v.link.clone()).collect();
        world.insert_resource(Medium::new(
            desc.vehicles.iter().map(|v| v.model.clone()).collect(),
            &link,
            desc.seed,
            desc.attenuation,
            desc.ambient,
        ));
        world.insert_resource(Connectivity::new(desc.dt));
        let mut ledger = Ledger::default();
        if opts.record && desc.output.mcap {
            // run.mcap writes the frames as the rows are drained (RecordBatch::frames).
            ledger.log_for_drain();
        }
        world.insert_resource(ledger);
        let every = if opts.record {
            (1.0 / (desc.output.record_hz * desc.dt)).round().max(1.0) as u64
        } else {
            0
        };
        world.insert_resource(RecordConfig { every });
        let mut fleet = Fleet::with_capacity(desc.vehicles.len());
        let mut names = VehicleNames::with_capacity(desc.vehicles.len());
        let mut tracks = Tracks(Vec::with_capacity(if every > 0 {
            desc.vehicles.len()
        } else {
            0
        }));
        // One batch, so that the ECS tables are sized once for the whole swarm instead of
        // doubling (and briefly holding the old and the new column) as it grows.
        let entities: Vec<Entity> = world
            .spawn_batch(desc.vehicles.iter().enumerate().map_while(|(i, v)| {
                cancel.check().ok()?;
                let id = i as u32;
                let (hot, track) = new_vehicle(desc, id, every);
                fleet.push(hot);
                tracks.0.extend(track);
                names.push(&v.name);
                let m = &v.model;
                Some((
                    VehicleId(id),
                    (
                        Modems::new(m.params.modems.len()),
                        Outbox::default(),
                        Inbox::default(),
                        comm_rng(desc.seed, id),
                        CommStats::default(),
                        Link::default(),
                    ),
                ))
            }))
            .collect();
        cancel.check()?;
        let ids: std::collections::HashMap<&str, u32> = desc
            .vehicles
            .iter()
            .enumerate()
            .filter(|(_, v)| {
                matches!(
                    v.behaviour,
                    Some(
                        shoal_world::spec::BehaviourSpec::Poisson { .. }
                            | shoal_world::spec::BehaviourSpec::Leader { .. }
                    )
                )
            })
            .map(|(i, v)| (v.name.as_str(), i as u32))
            .collect();
        let by_name: std::collections::HashMap<&str, u32> = if ids.is_empty() {
            ids
        } else {
            desc.vehicles
                .iter()
                .enumerate()
                .map(|(i, v)| (v.name.as_str(), i as u32))
                .collect()
        };
        let id_of = |n: &str| by_name.get(n).copied();
        for (id, (v, &e)) in desc.vehicles.iter().zip(&entities).enumerate() {
            if let Some(a) = &v.agent {
                let agent = desc.agents.names.iter().position(|n| n == a).unwrap_or(0);
                world.entity_mut(e).insert(External {
                    agent,
                    fallback: false,
                });
            }
            if let Some(b) = &v.behaviour {
                world.entity_mut(e).insert(Behave::new(
                    behaviour::build(b, &id_of),
                    vehicle_rng(desc.seed, id as u32, stream::BEHAVIOUR),
                    fleet.get(VehicleId(id as u32)).control.every,
                ));
            }
        }
        world.insert_resource(fleet);
        world.insert_resource(names);
        world.insert_resource(tracks);
        world.insert_resource(VehicleEntities(entities));
        let mut sim = Self {
            world,
            schedule: build_schedule(false, false),
            fault: None,
        };
        // Until their agent attaches, agent-driven vehicles hold depth and heading.
        for a in 0..desc.agents.names.len() {
            sim.set_fallback(a, FallbackSpec::Hold);
        }
        Ok(sim)
    }

    /// Puts every vehicle of `agent` under `fallback` (`Hold`: auto mode at its current depth
    /// reading and heading, no surge; `Surface`: the same towards depth 0; `Stop` holds too —
    /// ending the run is the caller's decision). Vehicles already in fallback keep theirs.
    pub fn set_fallback(&mut self, agent: usize, fallback: FallbackSpec) {
        self.world_mut()
            .resource_scope(|world, mut fleet: Mut<Fleet>| {
                let mut q = world.query::<(&VehicleId, &mut External)>();
                for (id, mut ext) in q.iter_mut(world) {
                    if ext.agent != agent || ext.fallback {
                        continue;
                    }
                    ext.fallback = true;
                    hold(fleet.get_mut(*id), fallback);
                }
            });
    }

    /// Advances one physics step. A vehicle whose state stops being finite is reported by
    /// [`Self::fault`]; the caller should stop the run there.
    pub fn step(&mut self) {
        self.schedule.run(&mut self.world);
        self.world.resource_mut::<Clock>().step += 1;
        if self.fault.is_none()
            && self
                .world
                .resource::<FaultFlag>()
                .0
                .load(std::sync::atomic::Ordering::Relaxed)
        {
            self.fault = self.first_fault();
        }
    }

    /// The first vehicle (lowest id) whose state stopped being finite, if any: the run's
    /// results are no longer physical from that step on.
    pub fn fault(&self) -> Option<&SimFault> {
        self.fault.as_ref()
    }

    fn first_fault(&mut self) -> Option<SimFault> {
        let fleet = self.world.resource::<Fleet>();
        let (id, f) = fleet
            .as_slice()
            .iter()
            .enumerate()
            .find_map(|(id, v)| Some((id, v.physics.fault.as_ref()?)))?;
        let name = self.name(id).to_owned();
        Some(SimFault {
            vehicle: id,
            name,
            state: (**f).clone(),
        })
    }

    /// Advances `n` steps, or fewer when a vehicle's state stops being finite
    /// ([`Self::fault`]).
    pub fn run(&mut self, n: u64) {
        // Nobody else holds this handle, so the run is never interrupted.
        let _ = self.run_until(n, &Cancel::new());
    }

    /// Advances up to `n` steps, looking at `cancel` before each: stops at a step boundary
    /// with `Err(Interrupted)` once a stop was asked for, and early (with `Ok`) when a
    /// vehicle's state stops being finite ([`Self::fault`]); [`Sim::step_count`] tells how far
    /// it got.
    pub fn run_until(&mut self, n: u64, cancel: &Cancel) -> Result<(), Interrupted> {
        for _ in 0..n {
            cancel.check()?;
            if self.fault.is_some() {
                break;
            }
            self.step();
        }
        Ok(())
    }

    /// Entity of each vehicle, by id.
    pub fn entities(&self) -> &[Entity] {
        &self.world.resource::<VehicleEntities>().0
    }

    /// Size of the pool (x, y, depth) \[m\].
    pub fn pool_size(&self) -> Vec3 {
        self.world.resource::<StaticGeometry>().0.pool
    }

    /// Steps completed.
    pub fn step_count(&self) -> u64 {
        self.world.resource::<Clock>().step
    }

    /// Simulated time \[s\].
    pub fn time(&self) -> f64 {
        self.world.resource::<Clock>().t()
    }

    /// Number of vehicles.
    pub fn len(&self) -> usize {
        self.entities().len()
    }

    /// Whether the world has no vehicles.
    pub fn is_empty(&self) -> bool {
        self.entities().is_empty()
    }

    /// Working threads.
    pub fn threads(&self) -> usize {
        self.world.resource::<Parallel>().threads()
    }

    /// Times every phase of every step from now on ([`crate::phases`]): the schedule gains a
    /// clock read after each phase; results are unchanged.
    pub fn time_phases(&mut self) {
        if !self.world.contains_resource::<PhaseClock>() {
            self.world.insert_resource(PhaseClock::default());
            self.schedule = build_schedule(false, true);
        }
    }

    /// The wall time of each phase of the steps since [`Sim::time_phases`] (all zero if it was
    /// never called).
    pub fn phase_times(&self) -> PhaseTimes {
        self.world
            .get_resource::<PhaseClock>()
            .map_or_else(PhaseTimes::default, PhaseClock::times)
    }

    /// The loops this world split over its thread pool since it was built, per kind: zero on
    /// one thread, and for loops smaller than [`Parallel::min_parallel`] vehicles.
    pub fn parallel_dispatches(&self) -> Dispatches {
        self.world.resource::<Parallel>().dispatches()
    }

    /// Splits loops of at least `vehicles` (≥ 1) vehicles over the thread pool
    /// ([`crate::parallel::MIN_PARALLEL`] by default). Results do not depend on it; tests
    /// lower it to run a small world's loops on the pool.
    pub fn set_min_parallel(&mut self, vehicles: usize) {
        self.world
            .resource_mut::<Parallel>()
            .set_min_parallel(vehicles);
    }

    /// The ECS world (for tools that add systems or read components).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The ECS world, mutably.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// The entity of vehicle `id`.
    pub fn vehicle_entity(&self, id: usize) -> Entity {
        self.entities()[id]
    }

    /// A copy of vehicle `id` (its reception statistics complete: the attempts the ledger
    /// has not folded yet are counted in the copy).
    pub fn vehicle(&self, id: usize) -> VehicleSnapshot {
        let mut v = self.vehicle_unfolded(id);
        for ev in self.world.resource::<Ledger>().pending(id as u32) {
            v.comm.apply(&ev);
        }
        v
    }

    /// A copy of vehicle `id` with its statistics as last folded.
    fn vehicle_unfolded(&self, id: usize) -> VehicleSnapshot {
        let e = self.world.entity(self.entities()[id]);
        let v = self.fleet().get(VehicleId(id as u32));
        VehicleSnapshot {
            id: id as u32,
            name: self.name(id).to_owned(),
            model: v.model.clone(),
            state: v.physics.state.clone(),
            sensors: v.sensors.clone(),
            setpoints: v.control.setpoints.clone(),
            commands: v.commands.clone(),
            contacts: v.contacts,
            comm: e.get::<CommStats>().cloned().unwrap_or_default(),
            behaviour: e
                .get::<Behave>()
                .map(|b| b.behaviour.report())
                .unwrap_or_default(),
        }
    }

    /// The name of vehicle `id` (empty if there is no such vehicle).
    pub fn name(&self, id: usize) -> &str {
        self.world
            .resource::<VehicleNames>()
            .get(id)
            .unwrap_or_default()
    }

    /// The hot state of every vehicle ([`crate::fleet`]).
    pub fn fleet(&self) -> &Fleet {
        self.world.resource::<Fleet>()
    }

    /// The hot state of every vehicle, mutably (for tools and tests that set a state).
    pub fn fleet_mut(&mut self) -> Mut<'_, Fleet> {
        self.world.resource_mut::<Fleet>()
    }

    /// Starts gathering the replay of this run (see [`crate::replay`]): poses every frame,
    /// panel values every `panel_dt` (1 s unless the swarm is large), and every reception attempt, which the medium logs from now
    /// on.
    pub fn enable_replay(&mut self, desc: &WorldDesc) {
        let range = self.world.resource::<Medium>().r_cut;
        let has_modems = desc
            .vehicles
            .iter()
            .any(|v| !v.model.params.modems.is_empty());
        self.world
            .insert_resource(crate::replay::capture::ReplayRecorder::new(
                desc,
                if has_modems { range } else { 0.0 },
            ));
        self.world.resource_mut::<Medium>().log_links = true;
    }

    /// The replay gathered since [`Self::enable_replay`] (and stops gathering it).
    pub fn take_replay(&mut self) -> Option<crate::replay::ReplayData> {
        let rec = self
            .world
            .remove_resource::<crate::replay::capture::ReplayRecorder>()?;
        self.world.resource_mut::<Medium>().log_links = false;
        let t = self.time();
        Some(rec.finish(
            t,
            self.world.resource::<Medium>(),
            self.world.resource::<Connectivity>(),
        ))
    }

    /// Borrowed views of all vehicles in id order (see [`crate::view`]). Call
    /// [`Self::fold_comm`] first when the reception statistics are needed.
    pub fn views(&self) -> Vec<VehicleView<'_>> {
        let mut views = Vec::with_capacity(self.entities().len());
        views.extend(
            self.entities()
                .iter()
                .filter_map(|e| VehicleView::of(&self.world, *e)),
        );
        views
    }

    /// Folds the reception attempts of the ledger ([`Ledger`]) into every vehicle's
    /// statistics ([`CommStats::rx`], [`CommStats::links`]); before reading them from the world.
    pub fn fold_comm(&mut self) {
        let n = self.entities().len();
        let mut ledger = std::mem::take(&mut *self.world.resource_mut::<Ledger>());
        let mut q = self.world.query::<(&VehicleId, &mut CommStats)>();
        ledger.fold_into(n, q.iter_mut(&mut self.world).map(|(id, c)| (id.0, c)));
        *self.world.resource_mut::<Ledger>() = ledger;
    }

    /// The communication graph over time.
    pub fn connectivity(&self) -> &Connectivity {
        self.world.resource::<Connectivity>()
    }

    /// The optical medium.
    pub fn medium(&self) -> &Medium {
        self.world.resource::<Medium>()
    }

    /// Copies of all vehicles in id order (as [`Self::vehicle`], the ledger read once).
    pub fn vehicles(&self) -> Vec<VehicleSnapshot> {
        let mut all: Vec<VehicleSnapshot> = (0..self.entities().len())
            .map(|i| self.vehicle_unfolded(i))
            .collect();
        for ev in self.world.resource::<Ledger>().events() {
            all[ev.rx as usize].comm.apply(&ev);
        }
        all
    }

    /// Takes the trajectory rows recorded since the last drain, and the reception attempts
    /// decided since then when the world logs them (`[output] mcap`, see
    /// [`RecordBatch::frames`]).
    pub fn drain(&mut self) -> RecordBatch {
        let n = self.len();
        let frames = self.world.resource_mut::<Ledger>().drain_logged();
        let mut tracks = self.world.resource_mut::<Tracks>();
        let rows = if tracks.0.is_empty() {
            vec![Vec::new(); n]
        } else {
            tracks.0.iter_mut().map(std::mem::take).collect()
        };
        RecordBatch { rows, frames }
    }

    /// A 64-bit FNV-1a digest of every vehicle's full state, in id order: equal digests mean
    /// bit-identical runs.
    pub fn digest(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: f64| {
            for b in x.to_bits().to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for v in self.fleet().as_slice() {
            let s = &v.physics.state;
            s.rigid.position.iter().for_each(|x| eat(*x));
            s.rigid.attitude.coords.iter().for_each(|x| eat(*x));
            s.rigid.nu.iter().for_each(|x| eat(*x));
            eat(s.ballast_volume);
            s.actuators.tilt.iter().for_each(|x| eat(*x));
            s.actuators.thrust.iter().for_each(|x| eat(*x));
            eat(v.sensors.depth);
        }
        h
    }
}

/// Vehicle `id` of `desc` at rest where the world file puts it, with its first sensor
/// readings, its mission's steps at t = 0 applied, and (when recording every `every` > 0 steps)
/// its track with the first trajectory row.
fn new_vehicle(desc: &WorldDesc, id: u32, every: u64) -> (HotVehicle, Option<Vec<f64>>) {
    let v = &desc.vehicles[id as usize];
    let m = &v.model;
    let mut state = VehicleState::new(m, RigidState::at_rest(v.position, v.attitude), &desc.env);
    let mut rng = vehicle_rng(desc.seed, id, stream::SENSORS);
    let mut readings = SensorReadings::zeros(m.params.tilts.len());
    sense(m, &mut state, &desc.env, &mut rng, &mut readings);
    let mut control = Control {
        state: m.controller(),
        setpoints: Setpoints {
            raw: m.zero_commands(),
            ..Default::default()
        },
        mission: v.mission.clone(),
        cursor: MissionCursor::default(),
        every: (m.params.control.period / desc.dt).round().max(1.0) as u64,
    };
    // Steps at t = 0 are in force from the first recorded row on.
    control
        .cursor
        .advance(&control.mission, 0.0, &mut control.setpoints);
    let cmd = m.zero_commands();
    let mut track = None;
    if every > 0 {
        // One row: the run driver drains every few steps, and a large world drains after
        // every step, so rows per vehicle stay few.
        let track = track.insert(Vec::with_capacity(recorder::stride(m)));
        recorder::push_row(
            track,
            0.0,
            m,
            &state,
            &readings,
            &control,
            &cmd,
            &ContactStats::default(),
        );
    }
    let hot = HotVehicle {
        model: m.clone(),
        physics: Physics { state, fault: None },
        control,
        commands: cmd,
        sensors: readings,
        sensor_rng: rng,
        contacts: ContactStats::default(),
    };
    (hot, track)
}

/// Puts vehicle `v` under `fallback`: auto mode at its current depth reading (or towards the
/// surface) and heading, no surge or sway.
fn hold(v: &mut HotVehicle, fallback: FallbackSpec) {
    let s = &v.sensors;
    let sp = &mut v.control.setpoints;
    sp.mode = Mode::Auto;
    sp.yaw = euler_rpy(&s.attitude).2;
    sp.surge = 0.0;
    sp.sway = 0.0;
    sp.depth = match fallback {
        FallbackSpec::Surface => 0.0,
        FallbackSpec::Hold | FallbackSpec::Stop => s.depth,
    };
}
