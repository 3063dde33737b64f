//! One step of the world as a chained sequence of system sets (see ARCHITECTURE.md):
//! Ingest → Vehicle (control → actuation → dynamics → collisions → sensors, fused into one
//! pass per vehicle) → Comm → Record. Systems are thin wrappers over shoal-model functions;
//! per-vehicle work runs in parallel on the world's [`Parallel`] pool and never reads another
//! vehicle's data, so the order of vehicles and the number of threads cannot change the
//! result.

use crate::behaviour::{Behave, BehaviourIo};
use crate::comm::{
    Inbox, Medium, Outbox, comm_deliver_system, comm_snapshot_system, comm_transmit_system,
};
use crate::components::*;
use crate::connectivity::connectivity_system;
use crate::fault::{FaultFlag, NonFinite};
use crate::fleet::{Fleet, HotVehicle};
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
pub fn mission_system(clock: Res<Clock>, mut next: ResMut<MissionClock>, mut fleet: ResMut<Fleet>) {
    let t = clock.t();
    // No vehicle has a step due: a swarm whose missions are done (or far from their next
    // step) costs nothing here.
    if !step_due(next.0, t) {
        return;
    }
    let mut earliest = f64::INFINITY;
    for v in fleet.as_mut_slice() {
        let c = &mut v.control;
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
    mut fleet: ResMut<Fleet>,
    mut q: Query<(&VehicleId, &mut Behave, &mut Inbox, &mut Outbox)>,
) {
    let step = clock.step;
    let t = clock.t();
    let dt = clock.dt;
    let mut ticking: Vec<_> = q
        .iter_mut()
        .filter(|it| step.is_multiple_of(it.1.every))
        .collect();
    if ticking.is_empty() {
        return;
    }
    ticking.sort_unstable_by_key(|it| it.0.0);
    let hot = fleet.select_mut(ticking.iter().map(|it| it.0.0));
    let mut items: Vec<_> = ticking.into_iter().zip(hot).collect();
    par.for_each(
        Loop::Behaviour,
        &mut items,
        |((id, behave, inbox, outbox), v)| {
            let b = &mut **behave;
            // The outbox is marked changed only when the behaviour hands a frame over: the
            // medium visits those vehicles alone.
            let out = outbox.bypass_change_detection();
            let before = out.0.len();
            let mut io = BehaviourIo {
                t,
                id: id.0,
                period: b.every as f64 * dt,
                sensors: &v.sensors,
                inbox: &inbox.frames,
                outcomes: &inbox.outcomes,
                setpoints: &mut v.control.setpoints,
                modems: &v.model.params.modems,
                rng: &mut b.rng,
                outbox: &mut out.0,
            };
            b.behaviour.tick(&mut io);
            if out.0.len() != before {
                outbox.set_changed();
            }
            if !inbox.is_empty() {
                inbox.clear();
            }
        },
    );
}

/// Vehicles without a behaviour or agent drop what they receive each step.
pub fn inbox_clear_system(mut q: Query<&mut Inbox, (Without<Behave>, Without<External>)>) {
    for mut i in &mut q {
        if !i.is_empty() {
            i.clear();
        }
    }
}

/// One step of every vehicle in a single pass over the [`Fleet`] in groups of [`LANES`]
/// consecutive vehicles: control (on its control tick) and actuation per vehicle → the rigid
/// bodies of the group integrated together by the lane kernel ([`shoal_model::lanes`], RK4;
/// vehicles of one kind in one ballast state share its constants) → per vehicle, collisions
/// with the static geometry and the sensors (just before the next control tick). Each
/// vehicle's update reads only its own hot state and the world's constants, and the lane
/// kernel gives every lane the same result as a vehicle alone, so runs of groups go to the
/// world's [`Parallel`] pool as plain slices of the fleet, with results independent of the
/// thread count; fusing the phases walks the vehicles once per step instead of five times.
///
/// A state that is no longer finite after integration is put back to the last finite one
/// and recorded ([`crate::fault`]); the run is then stopped by its caller.
pub fn vehicle_system(
    clock: Res<Clock>,
    par: Res<Parallel>,
    phys: Res<Physical>,
    geo: Res<StaticGeometry>,
    flag: Res<FaultFlag>,
    mut fleet: ResMut<Fleet>,
    mut medium: ResMut<Medium>,
) {
    let step = clock.step;
    let dt = clock.dt;
    let t_end = clock.t() + dt;
    let (env, integ) = (phys.env, phys.integrator);
    let geo = &geo.0;
    let poses = &mut medium.poses;
    let fleet = fleet.as_mut_slice();
    par.for_each_group_with(Loop::Vehicles, fleet, poses, LANES, |group, poses| {
        let mut before: [Option<RigidState>; LANES] = Default::default();
        let mut nu0 = [Vec6::zeros(); LANES];
        let mut prev = [Vec3::zeros(); LANES];
        for (i, v) in group.iter_mut().enumerate() {
            let m = &*v.model;
            if step.is_multiple_of(v.control.every) {
                control_vehicle(m, &v.sensors, &mut v.control, &mut v.commands);
            }
            let p = &mut v.physics;
            actuate_vehicle(m, &mut p.state, &v.commands, &env, dt);
            prev[i] = p.state.rigid.position;
            nu0[i] = p.state.rigid.nu;
            before[i] = Some(p.state.rigid.clone());
        }
        match integ {
            Integrator::Rk4 => integrate_group(group, &env, dt),
            _ => {
                for v in group.iter_mut() {
                    let s = &mut v.physics.state;
                    integrate(
                        integ,
                        &v.model.params.body,
                        &s.mass,
                        &v.model.environment(&env),
                        &mut s.rigid,
                        &s.tau,
                        dt,
                    );
                }
            }
        }
        for (i, v) in group.iter_mut().enumerate() {
            let m = &*v.model;
            let p = &mut v.physics;
            p.state.finish_step(&nu0[i], dt);
            if !p.state.rigid.is_finite()
                && let Some(last) = before[i].take()
            {
                restore_finite(p, last, t_end);
                flag.0.store(true, Ordering::Relaxed);
            }
            collide_vehicle(m, geo, &env, &prev[i], &mut p.state.rigid, &mut v.contacts);
            if (step + 1).is_multiple_of(v.control.every) {
                sense(m, &mut p.state, &env, &mut v.sensor_rng, &mut v.sensors);
            }
            // The medium's copy of the pose, written while the vehicle is in cache.
            if let Some(pose) = poses.get_mut(i) {
                *pose = (p.state.rigid.position, p.state.rigid.attitude);
            }
        }
    });
}

/// RK4 for a group of at most [`LANES`] vehicles: each run of consecutive vehicles of one
/// kind with the same mass properties is integrated in the lanes of one kernel call with
/// their shared constants (unused lanes repeat the run's first vehicle and are dropped).
fn integrate_group(group: &mut [HotVehicle], env: &Environment, dt: f64) {
    let same = |a: &HotVehicle, b: &HotVehicle| {
        Arc::ptr_eq(&a.model, &b.model) && Arc::ptr_eq(&a.physics.state.mass, &b.physics.state.mass)
    };
    let mut i = 0;
    while i < group.len() {
        let j = i
            + 1
            + group[i + 1..]
                .iter()
                .take_while(|v| same(v, &group[i]))
                .count();
        let first = &group[i];
        let consts = DynConsts::new(
            &first.model.params.body,
            &first.physics.state.mass,
            &first.model.environment(env),
        );
        let mut x = Lanes::<LANES>::default();
        for l in 0..LANES {
            let s = &group[i + l.min(j - i - 1)].physics.state;
            x.load(l, &s.rigid, &s.tau);
        }
        rk4_group(&consts, &mut x, dt);
        for l in 0..j - i {
            x.store(l, &mut group[i + l].physics.state.rigid);
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
/// displacement from `prev` (the body origin at the start of the step, world frame \[m\]) to
/// `rigid` (no tunnelling through thin obstacles at any speed), then penetration removal
/// along the contact normals and removal of the velocity component into the surface
/// (inelastic); contacts are counted in `stats`.
fn collide_vehicle(
    m: &VehicleModel,
    geo: &shoal_world::geometry::Geometry,
    env: &Environment,
    prev: &Vec3,
    rigid: &mut RigidState,
    stats: &mut ContactStats,
) {
    let current = m.environment(env).current;
    let hull = hull_shape(&m.params.body.hull_size);
    let prev = *prev;
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
    // A hull whose bounding sphere, with the margin, is clear of every surface's bounding box
    // has no contact (and `contacts` would find none): most of a swarm, most of the time.
    let reach = 0.5 * m.params.body.hull_size.norm() + CONTACT_MARGIN;
    let passes = if !touched && geo.clear_around(&rigid.position, reach) {
        0
    } else {
        4
    };
    let mut contacts = Vec::new();
    for _ in 0..passes {
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
    fleet: Res<Fleet>,
    mut tracks: ResMut<Tracks>,
) {
    let next = clock.step + 1;
    if cfg.every == 0 || !next.is_multiple_of(cfg.every) {
        return;
    }
    let t = next as f64 * clock.dt;
    for (track, v) in tracks.0.iter_mut().zip(fleet.as_slice()) {
        recorder::push_row(
            track,
            t,
            &v.model,
            &v.physics.state,
            &v.sensors,
            &v.control,
            &v.commands,
            &v.contacts,
        );
    }
}
