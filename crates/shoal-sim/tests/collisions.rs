//! Hulls against the static world: no tunnelling through a thin plate at the μAUV²'s stated
//! maximum speed even with a coarse step, walls that stop a vehicle under full thrust, a heavy
//! vehicle that comes to rest on the floor, and a light one that floats at the surface.

use shoal_model::math::Vec6;
use shoal_sim::prelude::*;
use shoal_world::load::load_str;
use std::path::Path;

fn world(text: &str) -> Sim {
    let desc = load_str(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
    Sim::new(&desc, SimOptions::default())
}

/// Largest world x of the hull's corners (the true front of the rotated box).
fn hull_front(v: &VehicleSnapshot) -> f64 {
    let h = v.model.params.body.hull_size * 0.5;
    let r = &v.state.rigid;
    let mut front = f64::NEG_INFINITY;
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let c = shoal_model::math::Vec3::new(sx * h.x, sy * h.y, sz * h.z);
                front = front.max(r.position.x + (r.attitude * c).x);
            }
        }
    }
    front
}

fn set_velocity(sim: &mut Sim, id: usize, nu: Vec6) {
    sim.fleet_mut()
        .get_mut(VehicleId(id as u32))
        .physics
        .state
        .rigid
        .nu = nu;
}

#[test]
fn no_tunnelling_through_a_thin_plate_at_max_speed() {
    // A 1 mm plate; 1.5 m/s (paper: maximum speed) with dt = 0.1 s moves 15 cm per step,
    // more than the plate and the hull's half length together.
    // Without the swept test the hull's centre would be past the plate after the step and the
    // contact would push it out on the far side. Also at 4 m/s (40 cm per step).
    for speed in [1.5, 4.0] {
        let text = "dt = 0.1\nduration = 5\n[pool]\nsize = [10.0, 4.0, 3.0]\n\
            [[obstacles]]\nshape = \"box\"\nsize = [0.001, 2.0, 2.0]\nposition = [5.0, 2.0, 1.5]\n\
            [[vehicles]]\nposition = [4.75, 2.0, 1.5]\n[vehicles.model.control]\nperiod = 0.1\n";
        let mut sim = world(text);
        set_velocity(&mut sim, 0, Vec6::new(speed, 0.0, 0.0, 0.0, 0.0, 0.0));
        let plate_face = 5.0 - 0.0005;
        let mut min_gap = f64::INFINITY;
        for _ in 0..50 {
            sim.step();
            let v = sim.vehicle(0);
            let front = hull_front(&v);
            assert!(
                front <= plate_face + 1e-6,
                "{speed} m/s: tunnelled: hull front at {front}"
            );
            min_gap = min_gap.min(plate_face - front);
        }
        // The swept test stops the hull at the plate, not a step short of it.
        assert!(min_gap < 1e-3, "{speed} m/s: closest approach {min_gap} m");
        let v = sim.vehicle(0);
        assert!(v.contacts.impacts >= 1);
        assert!(
            v.state.rigid.nu[0] <= 1e-9,
            "velocity into the plate removed: {}",
            v.state.rigid.nu[0]
        );
    }
}

#[test]
fn a_wall_stops_a_vehicle_under_full_thrust() {
    // Turning-mode geometry (β = 0), both side thrusters at +100 %: full surge into the wall.
    let text = "duration = 40\n[pool]\nsize = [3.0, 3.0, 2.0]\n\
        [[vehicles]]\nposition = [2.0, 1.5, 1.0]\n\
        mission = [{ t = 0, mode = \"raw\", thrusters = { port = 100, stbd = 100 } }]\n";
    let mut sim = world(text);
    let mut max_front: f64 = 0.0;
    for _ in 0..4000 {
        sim.step();
        max_front = max_front.max(hull_front(&sim.vehicle(0)));
    }
    let v = sim.vehicle(0);
    assert!(v.contacts.impacts >= 1, "it reached the wall");
    assert!(
        max_front <= 3.0 + 1e-6,
        "penetrated the wall to {max_front}"
    );
    assert!(3.0 - max_front < 0.02, "pressed against it");
}

#[test]
fn a_heavy_vehicle_rests_on_the_floor() {
    let text = "duration = 60\n[pool]\nsize = [3.0, 3.0, 1.0]\n\
        [[vehicles]]\nposition = [1.5, 1.5, 0.3]\n\
        [vehicles.model.ballast]\ninitial_volume = 2.0e-5\n";
    let mut sim = world(text);
    sim.run(6000);
    let v = sim.vehicle(0);
    let bottom = v.state.rigid.position.z + 0.091;
    assert!(
        (bottom - 1.0).abs() < 1e-3,
        "hull bottom at {bottom}, floor at 1.0"
    );
    assert!(
        v.state.rigid.nu.fixed_rows::<3>(0).norm() < 1e-3,
        "at rest: {}",
        v.state.rigid.nu
    );
    assert!(v.contacts.steps_in_contact > 1000);
}

#[test]
fn a_light_vehicle_floats_at_the_surface_in_the_world() {
    let text = "duration = 200\n[pool]\nsize = [3.0, 3.0, 2.0]\n\
        [[vehicles]]\nposition = [1.5, 1.5, 1.0]\n\
        [vehicles.model.ballast]\ninitial_volume = 0.0\n";
    let mut sim = world(text);
    let mut min_z = f64::INFINITY;
    for _ in 0..20000 {
        sim.step();
        min_z = min_z.min(sim.vehicle(0).state.rigid.position.z);
    }
    let v = sim.vehicle(0);
    // Top of the hull just above the surface, never flying out of the water.
    let top = v.state.rigid.position.z - 0.091;
    assert!((-0.01..0.0).contains(&top), "hull top at {top}");
    assert!(min_z > 0.0, "centre stayed under water: {min_z}");
    assert!(
        v.sensors.depth.max(0.0) < 2e-3,
        "depth reading ≈ 0: {}",
        v.sensors.depth
    );
}
