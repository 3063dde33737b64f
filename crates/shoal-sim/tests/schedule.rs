//! The step schedule is unambiguous, and a world gives bit-identical results on 1 and 2
//! threads.

use bevy_ecs::prelude::*;
use shoal_sim::prelude::*;
use shoal_world::load::{default_world, load_str};
use std::path::Path;

/// 600 vehicles (above the parallel threshold) on a grid, each group on its own mission.
fn swarm() -> shoal_world::desc::WorldDesc {
    let mut text = String::from("seed = 3\nduration = 30\n[pool]\nsize = [20.0, 70.0, 3.0]\n");
    for (g, (mode, depth)) in [("auto", 0.8), ("diving", 1.5), ("turning", 1.0)]
        .iter()
        .enumerate()
    {
        text.push_str(&format!(
            "[[vehicles]]\nname = \"g{g}\"\ncount = 200\ngrid = {{ origin = [1.0, {}, {depth}], spacing = [0.5, 0.5], columns = 20 }}\n\
             mission = [{{ t = 0, mode = \"{mode}\", depth = {depth}, yaw_deg = 30 }}, {{ t = 3, surge = 0.02, yaw_deg = -120 }}]\n",
            1.0 + 22.0 * g as f64
        ));
    }
    load_str(&text, Path::new("swarm.toml")).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn schedule_has_no_ambiguous_system_pairs() {
    let mut world = World::new();
    let mut schedule = build_schedule(true, false);
    // With ambiguity detection at `Error`, any pair of systems with conflicting access and no
    // order between them makes initialisation fail.
    schedule
        .initialize(&mut world)
        .expect("no ambiguous system pairs");
    assert!(schedule.systems_len() >= 7);
}

#[test]
fn timed_schedule_is_unambiguous_times_every_phase_and_changes_no_result() {
    use shoal_sim::phases::{Phase, PhaseTimes};
    let mut world = World::new();
    build_schedule(true, true)
        .initialize(&mut world)
        .expect("no ambiguous system pairs with the phase markers");
    // A beaconing swarm, so that every phase has work.
    let desc = shoal_sim::bench::swarm_with(64, 1, true);
    let run = |timed: bool| {
        let mut sim = Sim::new(
            &desc,
            SimOptions {
                threads: 1,
                record: true,
            },
        );
        if timed {
            sim.time_phases();
        }
        sim.run(250);
        let m = sim.medium();
        (
            sim.digest(),
            m.started,
            m.delivered,
            m.per_second.clone(),
            sim.phase_times(),
        )
    };
    let (plain, timed) = (run(false), run(true));
    assert!(timed.2 > 0, "frames were delivered");
    assert_eq!(plain.0, timed.0, "digest");
    assert_eq!(
        (plain.1, plain.2, &plain.3),
        (timed.1, timed.2, &timed.3),
        "medium statistics"
    );
    assert_eq!(
        plain.4,
        PhaseTimes::default(),
        "an untimed world times nothing"
    );
    for p in Phase::ALL {
        assert!(timed.4.of(p) > 0.0, "{p:?} was not timed: {:?}", timed.4);
    }
}

#[test]
fn every_mission_step_applies_on_time_when_missions_step_at_different_times() {
    // Two vehicles whose missions step at different times: the mission system skips the
    // steps before the earliest step still to come, so it must track the earliest of all.
    let t = "seed = 1\nduration = 5\n[pool]\nsize = [6.0, 6.0, 3.0]\n\
        [[vehicles]]\nname = \"a\"\nposition = [2.0, 2.0, 1.0]\n\
        mission = [{ t = 0, mode = \"auto\", depth = 1.0 }, { t = 0.5, depth = 1.1 }, { t = 1.2, depth = 1.2 }]\n\
        [[vehicles]]\nname = \"b\"\nposition = [4.0, 4.0, 1.0]\n\
        mission = [{ t = 0, mode = \"auto\", depth = 2.0 }, { t = 0.73, depth = 2.1 }, { t = 0.74, depth = 2.2 }]\n";
    let desc = load_str(t, Path::new("missions.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Sim::new(&desc, SimOptions::default());
    let depth = |sim: &Sim, i: usize| sim.vehicle(i).setpoints.depth;
    // (vehicle, time of its step, depth before, depth from then on)
    let steps = [
        (0, 0.5, 1.0, 1.1),
        (1, 0.73, 2.0, 2.1),
        (1, 0.74, 2.1, 2.2),
        (0, 1.2, 1.1, 1.2),
    ];
    for (v, at, before, after) in steps {
        // The step whose start time is `at` applies it (dt = 0.01 s).
        let k = (at / desc.dt).round() as u64;
        sim.run(k - sim.step_count());
        assert_eq!(depth(&sim, v), before, "vehicle {v} before {at} s");
        sim.run(1);
        assert_eq!(depth(&sim, v), after, "vehicle {v} at {at} s");
    }
}

#[test]
fn a_conflicting_unordered_system_is_detected() {
    // A second writer of the vehicles' hot state in the Vehicle set, unordered with the
    // vehicle pass: exactly what the detector must refuse.
    fn rogue(_fleet: ResMut<Fleet>) {}
    let mut world = World::new();
    let mut schedule = build_schedule(true, false);
    schedule.add_systems(rogue.in_set(StepSet::Vehicle));
    assert!(schedule.initialize(&mut world).is_err());
}

#[test]
fn one_and_two_threads_give_identical_results() {
    let desc = swarm();
    assert_eq!(desc.vehicles.len(), 600);
    const { assert!(600 >= shoal_sim::parallel::MIN_PARALLEL) };
    let mut digests = Vec::new();
    for threads in [1, 2] {
        let mut sim = Sim::new(
            &desc,
            SimOptions {
                threads,
                record: true,
            },
        );
        assert_eq!(sim.threads(), threads);
        sim.run(1000);
        // The parallel path ran on 2 threads: every step's vehicle pass was split over the
        // pool (600 vehicles, one batch); nothing is split on 1 thread.
        let split = sim.parallel_dispatches();
        let expected = if threads == 1 { 0 } else { 1000 };
        assert_eq!(split.vehicles, expected, "{threads} thread(s): {split:?}");
        assert_eq!(
            split.total(),
            expected,
            "no behaviours, no frames: {split:?}"
        );
        let rows = sim.drain();
        digests.push((sim.digest(), rows.rows));
    }
    assert_eq!(
        digests[0].0, digests[1].0,
        "state digests differ between 1 and 2 threads"
    );
    assert_eq!(
        digests[0].1, digests[1].1,
        "recorded rows differ between 1 and 2 threads"
    );
}

#[test]
fn same_seed_same_result_different_seed_different_noise() {
    let desc = default_world().unwrap();
    let run = |seed: u64| {
        let mut d = desc.clone();
        d.seed = seed;
        let mut sim = Sim::new(&d, SimOptions::default());
        sim.run(300);
        sim.digest()
    };
    assert_eq!(run(7), run(7));
    assert_ne!(run(7), run(8));
}
