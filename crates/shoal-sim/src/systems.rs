//! One step of the world as a chained sequence of system sets (see ARCHITECTURE.md):
//! Ingest → Vehicle (control → actuation → dynamics → collisions → sensors, fused into one
//! pass per vehicle) → Comm → Record. Systems are thin wrappers over shoal-model functions;
//! per-vehicle work runs in parallel on the world's [`Parallel`] pool and never reads another
//! vehicle's data, so the order of vehicles and the number of threads cannot change the
//! result.

use crate::behaviour::{Behave, BehaviourIo};
use crate::comm::{Inbox, Outbox, comm_deliver_system, comm_snapshot_system, comm_transmit_system};
use crate::components::*;
use crate::connectivity::connectivity_system;
use crate::fault::{FaultFlag, NonFinite};
use crate::parallel::{Loop, Parallel};
use crate::phases::{Phase, phase_end, phase_start};
use crate::recorder;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::SingleThreadedExecutor;
use bevy_ecs::schedule::{LogLevel, ScheduleBuildSettings};
use shoal_model::control::step_due;
use shoal_model::dynamics::integrate;
use shoal_model::lanes::{DynConsts, LANES, Lanes, rk4_group};
use shoal_model::prelude::*;
use shoal_world::geometry::{hull_shape, to_pose};
use std::sync::Arc;
use std::sync::atomic::Ordering;

/// The phases of one step, run in this order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StepSet {
    /// Commands from missions (and, later, external agents) become setpoints.
    Ingest,
    /// Each vehicle in one pass: built-in controllers turn setpoints and sensor readings into
    /// actuator commands, pumps, tilt drives and thrusters turn commands into forces, the
    /// rigid body is integrated, the hull is kept out of walls, floor and obstacles, and the
    /// sensors are sampled.
    Vehicle,
    /// Optical communication (airtime, collisions, delivery).
    Comm,
    /// Trajectories are recorded.
    Record,
}

/// Builds the schedule of one step. `detect_ambiguity` turns any pair of conflicting
/// unordered systems into a build error; `time_phases` adds a marker after each phase that
/// adds its wall time to the world's [`crate::phases::PhaseClock`] (which must then exist).
pub fn build_schedule(detect_ambiguity: bool, time_phases: bool) -> Schedule {
    let mut s = Schedule::default();
    s.set_executor(SingleThreadedExecutor::new());
    if detect_ambiguity {
        s.set_build_settings(ScheduleBuildSettings {
            ambiguity_detection: LogLevel::Error,
            ..Default::default()
        });
    }
    s.configure_sets(
        (
            StepSet::Ingest,
            StepSet::Vehicle,
            StepSet::Comm,
            StepSet::Record,
        )
            .chain(),
    );
    if !time_phases {
        s.add_systems((
            (mission_system, behaviour_system, inbox_clear_system)
                .chain()
                .in_set(StepSet::Ingest),
            vehicle_system.in_set(StepSet::Vehicle),
            (
                comm_snapshot_system,
                comm_transmit_system,
                comm_deliver_system,
            )
                .chain()
                .in_set(StepSet::Comm),
            (
                record_system,
                connectivity_system,
                crate::replay::capture::replay_system,
            )
                .chain()
                .in_set(StepSet::Record),
        ));
        return s;
    }
    const fn at(p: Phase) -> usize {
        p as usize
    }
    s.add_systems((
        (
            phase_start,
            mission_system,
            behaviour_system,
            inbox_clear_system,
            phase_end::<{ at(Phase::Ingest) }>,
        )
            .chain()
            .in_set(StepSet::Ingest),
        (vehicle_system, phase_end::<{ at(Phase::Vehicles) }>)
            .chain()
            .in_set(StepSet::Vehicle),
        (
            comm_snapshot_system,
            phase_end::<{ at(Phase::MediumSnapshot) }>,
            comm_transmit_system,
            phase_end::<{ at(Phase::MediumTransmit) }>,
            comm_deliver_system,
            phase_end::<{ at(Phase::MediumDelivery) }>,
        )
            .chain()
            .in_set(StepSet::Comm),
        (
            record_system,
            connectivity_system,
            crate::replay::capture::replay_system,
            phase_end::<{ at(Phase::Recorder) }>,
        )
            .chain()
            .in_set(StepSet::Record),
    ));
    s
}

/// Advances each vehicle's mission to the current time.
pub fn mission_system(
    clock: Res<Clock>,
    mut next: ResMut<MissionClock>,
    mut q: Query<&mut Control>,
) {
    let t = clock.t();
    // No vehicle has a step due: a swarm whose missions are done (or far from their next
    // step) costs nothing here.
    if !step_due(next.0, t) {
        return;
    }
    let mut earliest = f64::INFINITY;
    for mut c in &mut q {
        let c = &mut *c;
        c.cursor.advance(&c.mission, t, &mut c.setpoints);
        earliest = earliest.min(c.cursor.next_time(&c.mission));
    }
    next.0 = earliest;
}

/// Runs each vehicle's behaviour on its control tick: it reads the frames received since the
/// last tick and may change setpoints and send frames.
pub fn behaviour_system(
    clock: Res<Clock>,
    par: Res<Parallel>,
    mut q: Query<(
        &VehicleId,
        &Kind,
        &Sensors,
        &mut Control,
        &mut Behave,
        &mut Inbox,
        &mut Outbox,
    )>,
) {
    let step = clock.step;
    let t = clock.t();
    let dt = clock.dt;
    let mut items: Vec<_> = q
        .iter_mut()
        .filter(|it| it.4.behaviour.every_step() || step.is_multiple_of(it.3.every))
        .collect();
    par.for_each(
        Loop::Behaviour,
        &mut items,
        |(id, kind, sensors, control, behave, inbox, outbox)| {
            let b = &mut **behave;
            let mut io = BehaviourIo {
                t,
                id: id.0,
                period: if b.behaviour.every_step() {
                    dt
                } else {
                    control.every as f64 * dt
                },
                sensors: &sensors.0,
                inbox: &inbox.0,
                setpoints: &mut control.setpoints,
                modems: &kind.0.params.modems,
                rng: &mut b.rng,
                outbox: &mut outbox.0,
            };
            b.behaviour.tick(&mut io);
            inbox.0.clear();
        },
    );
}

/// Vehicles without a behaviour or agent drop what they receive each step.
pub fn inbox_clear_system(mut q: Query<&mut Inbox, (Without<Behave>, Without<External>)>) {
    for mut i in &mut q {
        if !i.0.is_empty() {
            i.0.clear();
        }
    }
}

/// One step of every vehicle in a single pass over groups of [`LANES`] vehicles: control (on
/// its control tick) and actuation per vehicle → the rigid bodies of the group integrated
/// together by the lane kernel ([`shoal_model::lanes`], RK4; vehicles of one kind in one
/// ballast state share its constants) → per vehicle, collisions with the static geometry and
/// the sensors (just before the next control tick). Each vehicle's update reads only its own
/// components and the world's constants, and the lane kernel gives every lane the same
/// result as a vehicle alone, so the groups run in parallel chunks on the world's
/// [`Parallel`] pool with results independent of the thread count; fusing the phases walks
/// the vehicles once per step instead of five times.
///
/// A state that is no longer finite after integration is put back to the last finite one
/// and recorded ([`crate::fault`]); the run is then stopped by its caller.
#[allow(clippy::type_complexity)]
pub fn vehicle_system(
    clock: Res<Clock>,
    par: Res<Parallel>,
    phys: Res<Physical>,
    geo: Res<StaticGeometry>,
    flag: Res<FaultFlag>,
    mut q: Query<(
        &Kind,
        &mut Sensors,
        &mut Control,
        &mut Actuation,
        &mut Physics,
        &mut ContactStats,
        &mut SensorRng,
    )>,
) {
    let step = clock.step;
    let dt = clock.dt;
    let t_end = clock.t() + dt;
    let (env, integ) = (phys.env, phys.integrator);
    let geo = &geo.0;
    // The vehicles in batches of a bounded size, so that the step's working memory does not
    // grow with the swarm.
    let mut vehicles = q.iter_mut();
    let mut items = Vec::with_capacity(BATCH.min(vehicles.len()));
    loop {
        items.extend(vehicles.by_ref().take(BATCH));
        if items.is_empty() {
            break;
        }
        let mut groups: Vec<_> = items.chunks_mut(LANES).collect();
        par.for_each(Loop::Vehicles, &mut groups, |group| {
            let mut before: [Option<RigidState>; LANES] = Default::default();
            let mut nu0 = [Vec6::zeros(); LANES];
            for (i, (kind, sensors, control, act, p, _, _)) in group.iter_mut().enumerate() {
                let m = &kind.0;
                if step.is_multiple_of(control.every) {
                    control_vehicle(m, &sensors.0, control, &mut act.0);
                }
                actuate_vehicle(m, &mut p.state, &act.0, &env, dt);
                p.prev_position = p.state.rigid.position;
                nu0[i] = p.state.rigid.nu;
                before[i] = Some(p.state.rigid.clone());
            }
            match integ {
                Integrator::Rk4 => integrate_group(group, &env, dt),
                _ => {
                    for (kind, _, _, _, p, _, _) in group.iter_mut() {
                        let s = &mut p.state;
                        integrate(
                            integ,
                            &kind.0.params.body,
                            &s.mass,
                            &kind.0.environment(&env),
                            &mut s.rigid,
                            &s.tau,
                            dt,
                        );
                    }
                }
            }
            for (i, (kind, sensors, control, _, p, stats, rng)) in group.iter_mut().enumerate() {
                let m = &kind.0;
                p.state.finish_step(&nu0[i], dt);
                if !p.state.rigid.is_finite()
                    && let Some(last) = before[i].take()
                {
                    restore_finite(p, last, t_end);
                    flag.0.store(true, Ordering::Relaxed);
                }
                collide_vehicle(m, geo, &env, p, stats);
                if (step + 1).is_multiple_of(control.every) {
                    sense(m, &mut p.state, &env, &mut rng.0, &mut sensors.0);
                }
            }
        });
        drop(groups);
        items.clear();
    }
}

/// Vehicles per batch of [`vehicle_system`]: enough for every thread to get several chunks
/// and for worlds of tens of thousands to be split over the pool once per step (each batch is
/// one hand-off to the workers, and its list is collected while they wait: with batches of
/// 8,192 a 20,000-vehicle pass took 3.24 ms on 2 threads, as one batch 2.97 ms), few enough
/// that the batch's list of component references stays under about ten megabytes.
const BATCH: usize = 32_768;

/// RK4 for a group of at most [`LANES`] vehicles: each run of consecutive vehicles of one
/// kind with the same mass properties is integrated in the lanes of one kernel call with
/// their shared constants (unused lanes repeat the run's first vehicle and are dropped).
#[allow(clippy::type_complexity)]
fn integrate_group(
    group: &mut [(
        &Kind,
        Mut<Sensors>,
        Mut<Control>,
        Mut<Actuation>,
        Mut<Physics>,
        Mut<ContactStats>,
        Mut<SensorRng>,
    )],
    env: &Environment,
    dt: f64,
) {
    let mut i = 0;
    while i < group.len() {
        let (kind, mass) = (group[i].0.0.clone(), group[i].4.state.mass.clone());
        let mut j = i + 1;
        while j < group.len()
            && Arc::ptr_eq(&group[j].0.0, &kind)
            && Arc::ptr_eq(&group[j].4.state.mass, &mass)
        {
            j += 1;
        }
        let consts = DynConsts::new(&kind.params.body, &mass, &kind.environment(env));
        let mut x = Lanes::<LANES>::default();
        for l in 0..LANES {
            let s = &group[i + l.min(j - i - 1)].4.state;
            x.load(l, &s.rigid, &s.tau);
        }
        rk4_group(&consts, &mut x, dt);
        for l in 0..j - i {
            x.store(l, &mut group[i + l].4.state.rigid);
        }
        i = j;
    }
}

/// Puts a state that stopped being finite back to `last` (finite, from the start of the
/// step) and records the first such event in `p.fault`.
fn restore_finite(p: &mut Physics, last: RigidState, t_end: f64) {
    if p.fault.is_none() {
        p.fault = Some(Box::new(NonFinite {
            time: t_end,
            last: last.clone(),
        }));
    }
    p.state.rigid = last;
}

/// The vehicle's controller: setpoints and sensor readings → actuator commands.
fn control_vehicle(
    m: &VehicleModel,
    sensors: &SensorReadings,
    c: &mut Control,
    act: &mut ActuatorCommands,
) {
    c.state.update(
        &m.params.control,
        m.uauv2.as_ref(),
        &m.params.thrusters,
        sensors,
        &c.setpoints,
        act,
    );
}

/// A hull closer than this to a surface is in contact with it [m].
const CONTACT_MARGIN: f64 = 1e-3;

/// Fraction of the way back from the first impact, so that a hull stopped by the swept test
/// rests just short of the surface it hit.
const BACKOFF: f64 = 1e-4;

/// Keeps the vehicle's hull out of walls, floor and obstacles: a swept test along the step's
/// displacement (no tunnelling through thin obstacles at any speed), then penetration
/// removal along the contact normals and removal of the velocity component into the surface
/// (inelastic); contacts are counted in `stats`.
fn collide_vehicle(
    m: &VehicleModel,
    geo: &shoal_world::geometry::Geometry,
    env: &Environment,
    p: &mut Physics,
    stats: &mut ContactStats,
) {
    let current = m.environment(env).current;
    let hull = hull_shape(&m.params.body.hull_size);
    let prev = p.prev_position;
    let rigid = &mut p.state.rigid;
    let mut touched = false;
    let mut max_depth: f64 = 0.0;
    let delta = rigid.position - prev;
    let min_half = 0.5 * m.params.body.hull_size.min();
    if delta.norm() > 0.25 * min_half {
        let from = to_pose(&prev, &rigid.attitude);
        if let Some((toi, n)) = geo.first_hit(&hull, &from, &delta) {
            rigid.position = prev + delta * (toi - BACKOFF).max(0.0);
            remove_inward_velocity(rigid, &n, &current);
            touched = true;
        }
    }
    let mut contacts = Vec::new();
    for _ in 0..4 {
        contacts.clear();
        let pose = to_pose(&rigid.position, &rigid.attitude);
        geo.contacts(&hull, &pose, CONTACT_MARGIN, &mut contacts);
        if contacts.is_empty() {
            break;
        }
        // Within the margin counts as touching; only penetration is corrected.
        touched = true;
        let mut moved = false;
        for c in contacts.iter().filter(|c| c.depth > 0.0) {
            rigid.position += c.normal * c.depth;
            max_depth = max_depth.max(c.depth);
            remove_inward_velocity(rigid, &c.normal, &current);
            moved = true;
        }
        if !moved {
            break;
        }
    }
    if touched {
        stats.steps_in_contact += 1;
        if !stats.touching {
            stats.impacts += 1;
        }
        stats.max_depth = stats.max_depth.max(max_depth);
    }
    stats.touching = touched;
}

/// Removes the component of the ground velocity that points into a surface with outward
/// normal `n` (world frame).
fn remove_inward_velocity(rigid: &mut RigidState, n: &Vec3, current: &Vec3) {
    let v_body = rigid.nu.fixed_rows::<3>(0).into_owned();
    let v_ground = rigid.attitude * v_body + current;
    let vn = v_ground.dot(n);
    if vn < 0.0 {
        let v_new = v_ground - n * vn;
        let v_rel = rigid.attitude.inverse_transform_vector(&(v_new - current));
        rigid.nu.fixed_rows_mut::<3>(0).copy_from(&v_rel);
    }
}

/// Appends a trajectory row every `RecordConfig::every` steps.
pub fn record_system(
    clock: Res<Clock>,
    cfg: Res<RecordConfig>,
    mut q: Query<(
        &Kind,
        &Physics,
        &Sensors,
        &Control,
        &Actuation,
        &ContactStats,
        &mut Track,
    )>,
) {
    let next = clock.step + 1;
    if cfg.every == 0 || !next.is_multiple_of(cfg.every) {
        return;
    }
    let t = next as f64 * clock.dt;
    for (kind, p, s, c, a, stats, mut track) in &mut q {
        recorder::push_row(&mut track.0, t, &kind.0, &p.state, &s.0, c, &a.0, stats);
    }
}
