//! The run-time guard: a vehicle whose state stops being finite is reported with its name,
//! the time and its last finite state, its state is kept finite (NaN never reaches the
//! collision geometry, which would panic, or the outputs), and the other vehicles are
//! untouched. A world is given a state no model survives: a surge speed of 1e200 m/s, whose
//! quadratic drag overflows.

use shoal_model::math::Vec6;
use shoal_sim::prelude::*;
use shoal_world::load::load_str;
use std::path::Path;

/// 300 vehicles on a 0.5 m grid: above [`shoal_sim::parallel::MIN_PARALLEL`], so on 2 threads
/// the vehicle pass that finds the fault runs on the pool.
const WORLD: &str = "dt = 0.01\n[pool]\nsize = [14.0, 14.0, 3.0]\n\
    [[vehicles]]\nname = \"a\"\ncount = 300\ngrid = { origin = [2.0, 2.0, 1.0], spacing = [0.5, 0.5], columns = 20 }\n";

fn run(threads: usize) -> (Sim, u64) {
    let desc = load_str(WORLD, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads,
            ..SimOptions::default()
        },
    );
    sim.run(25);
    assert!(sim.fault().is_none());
    sim.fleet_mut().get_mut(VehicleId(1)).physics.state.rigid.nu =
        Vec6::new(1e200, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut steps = 0;
    while sim.fault().is_none() && steps < 10 {
        sim.step();
        steps += 1;
    }
    (sim, steps)
}

#[test]
fn a_non_finite_state_is_reported_with_vehicle_time_and_last_finite_state() {
    for threads in [1, 2] {
        let (sim, steps) = run(threads);
        // 26 steps: each vehicle pass split over the pool on 2 threads, none on 1.
        let split = sim.parallel_dispatches();
        assert_eq!(split.vehicles, 26 * (threads as u64 - 1), "{split:?}");
        let f = sim.fault().expect("the overflow must be reported");
        assert_eq!(steps, 1, "reported in the step that produced it");
        assert_eq!(f.vehicle, 1);
        assert_eq!(f.name, "a-1");
        assert!((f.state.time - 0.26).abs() < 1e-12, "{}", f.state.time);
        assert_eq!(f.state.last.nu[0], 1e200);
        assert!(f.state.last.is_finite());
        let text = f.to_string();
        assert!(
            text.contains("vehicle `a-1` (id 1) became non-finite at t = 0.26 s")
                && text.contains("velocity (1.0000e200, 0.0000, 0.0000) m/s"),
            "{text}"
        );
        // Every vehicle's state stays finite, and the others keep their place.
        for v in sim.vehicles() {
            assert!(v.state.rigid.is_finite(), "{}", v.name);
        }
        let v0 = sim.vehicle(0);
        assert!((v0.state.rigid.position.x - 2.0).abs() < 0.01);
    }
}
