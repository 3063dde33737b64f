//! Whole-swarm reads and commands (`shoal_sim::batch`): setpoints given to all vehicles at once
//! are reached, every bad value is refused before anything changes (naming the vehicle and
//! field), the flat reads equal the per-vehicle snapshots, and frames queued through the batch
//! API are delivered — or lost to half-duplex when two modems start at the same instant.

mod support;
use shoal_model::math::euler_rpy;
use shoal_sim::batch::{
    ActuatorOrder, Arrivals, Column, MODES, Quantity, Rows, SetpointOrder, mode_code,
};
use shoal_sim::orders::{FrameOrder, force_limit};
use shoal_sim::prelude::*;
use support::world::world;

/// Four μAUV² side by side at 0.5 m, no mission: they float with everything off.
const FOUR: &str = "seed = 3\nduration = 100\n[pool]\nsize = [10.0, 10.0, 3.0]\n\
    [[vehicles]]\nname = \"v\"\ncount = 4\n\
    grid = { origin = [2.0, 5.0, 0.5], spacing = [2.0, 0.0], columns = 4 }\n";

fn read(sim: &mut Sim, q: Quantity) -> Vec<f64> {
    let w = q.width(&sim.batch_shape()).unwrap_or(1);
    let mut v = vec![0.0; sim.len() * w];
    sim.read_f64(q, &mut v).unwrap();
    v
}

fn auto(depth: &[f64], yaw: &[f64]) -> (Vec<f64>, Vec<f64>) {
    (depth.to_vec(), yaw.to_vec())
}

#[test]
fn setpoints_for_all_vehicles_at_once_are_reached() {
    let mut sim = world(FOUR);
    let (depth, yaw) = auto(&[0.8, 1.2, 1.6, 2.0], &[0.0, 1.0, -2.0, 3.0]);
    sim.set_setpoints(
        None,
        &SetpointOrder {
            mode: Column::All(mode_code(shoal_model::prelude::Mode::Auto)),
            depth: Some(Column::Each(&depth)),
            yaw: Some(Column::Each(&yaw)),
            surge: None,
            sway: None,
        },
        false,
    )
    .unwrap();
    sim.run(6000); // 60 s: depth and heading time constants are a few seconds
    let reading = read(&mut sim, Quantity::DepthReading);
    let euler = read(&mut sim, Quantity::Euler);
    for i in 0..4 {
        assert!(
            (reading[i] - depth[i]).abs() < 0.03,
            "vehicle {i}: depth {} for {}",
            reading[i],
            depth[i]
        );
        let e = shoal_model::math::wrap_pi(euler[3 * i + 2] - yaw[i]);
        assert!(
            e.abs() < 2f64.to_radians(),
            "vehicle {i}: heading off by {e} rad"
        );
    }
    let mut modes = vec![0i64; 4];
    sim.read_i64(Quantity::Mode, &mut modes).unwrap();
    assert_eq!(modes, [5; 4]);
    assert_eq!(MODES[5], shoal_model::prelude::Mode::Auto);
}

#[test]
fn a_bad_value_changes_nothing_and_names_the_vehicle_and_field() {
    let mut sim = world(FOUR);
    let before = read(&mut sim, Quantity::Setpoint);
    let depth = [1.0, 1.0, f64::NAN, 1.0];
    let e = sim
        .set_setpoints(
            None,
            &SetpointOrder {
                mode: Column::All(5),
                depth: Some(Column::Each(&depth)),
                yaw: None,
                surge: None,
                sway: None,
            },
            false,
        )
        .unwrap_err();
    assert_eq!(
        (e.vehicle, e.name.as_deref(), e.field.as_str()),
        (Some(2), Some("v-2"), "depth")
    );
    assert!(e.to_string().contains("NaN"), "{e}");
    assert_eq!(
        read(&mut sim, Quantity::Setpoint),
        before,
        "a refused command changed setpoints"
    );
    let mut modes = vec![0i64; 4];
    sim.read_i64(Quantity::Mode, &mut modes).unwrap();
    assert_eq!(modes, [0; 4], "still off");

    // Out of range: refused with the range, or clamped to it when asked.
    let f = force_limit(&sim.vehicle(0).model);
    let surge = [0.0, 2.0 * f, 0.0, 0.0];
    let order = SetpointOrder {
        mode: Column::All(5),
        depth: None,
        yaw: None,
        surge: Some(Column::Each(&surge)),
        sway: None,
    };
    let e = sim.set_setpoints(None, &order, false).unwrap_err();
    assert_eq!((e.vehicle, e.field.as_str()), (Some(1), "surge"));
    assert!(e.message.contains("outside the allowed"), "{e}");
    sim.set_setpoints(None, &order, true).unwrap();
    assert_eq!(
        read(&mut sim, Quantity::Setpoint)[4 + 2],
        f,
        "clamped to the force limit"
    );

    // Unknown mode codes, unknown and repeated vehicles, wrong lengths.
    let bad_mode = SetpointOrder {
        mode: Column::All(6),
        depth: None,
        yaw: None,
        surge: None,
        sway: None,
    };
    assert_eq!(
        sim.set_setpoints(None, &bad_mode, false).unwrap_err().field,
        "mode"
    );
    let ok = SetpointOrder {
        mode: Column::All(1),
        ..bad_mode
    };
    assert!(
        sim.set_setpoints(Some(&[4]), &ok, false)
            .unwrap_err()
            .message
            .contains("does not exist")
    );
    assert!(
        sim.set_setpoints(Some(&[1, 1]), &ok, false)
            .unwrap_err()
            .message
            .contains("twice")
    );
    let short = SetpointOrder {
        mode: Column::Each(&[1, 1]),
        ..ok
    };
    assert_eq!(
        sim.set_setpoints(None, &short, false).unwrap_err().field,
        "mode"
    );
}

#[test]
fn a_subset_of_vehicles_is_commanded_by_id() {
    let mut sim = world(FOUR);
    let depth = [1.5, 0.7];
    sim.set_setpoints(
        Some(&[3, 1]),
        &SetpointOrder {
            mode: Column::All(1),
            depth: Some(Column::Each(&depth)),
            yaw: None,
            surge: None,
            sway: None,
        },
        false,
    )
    .unwrap();
    let sp = read(&mut sim, Quantity::Setpoint);
    let depths: Vec<f64> = (0..4).map(|i| sp[4 * i]).collect();
    assert_eq!(depths, [0.0, 0.7, 0.0, 1.5]);
    let mut modes = vec![0i64; 4];
    sim.read_i64(Quantity::Mode, &mut modes).unwrap();
    assert_eq!(modes, [0, 1, 0, 1]);
}

#[test]
fn raw_actuator_commands_are_checked_and_reach_the_thrusters() {
    let mut sim = world(FOUR);
    let shape = sim.batch_shape();
    assert_eq!((shape.thrusters, shape.tilts), (3, 2));
    // Port and starboard at 40 %, drives level: the vehicle drives forward.
    let thr: Vec<f64> = [0.0, 40.0, 40.0].repeat(4);
    let tilt = vec![0.0; 8];
    let order = ActuatorOrder {
        thrusters: Some(Rows {
            data: &thr,
            width: 3,
        }),
        tilts: Some(Rows {
            data: &tilt,
            width: 2,
        }),
        pump: Some(Column::All(0)),
    };
    sim.set_actuators(None, &order, false).unwrap();
    let x0 = read(&mut sim, Quantity::Position)[0];
    sim.run(500);
    assert_eq!(
        read(&mut sim, Quantity::ThrusterCommand)[..3],
        [0.0, 40.0, 40.0]
    );
    let mut modes = vec![0i64; 4];
    sim.read_i64(Quantity::Mode, &mut modes).unwrap();
    assert_eq!(modes, [6; 4], "raw");
    let x1 = read(&mut sim, Quantity::Position)[0];
    assert!(x1 - x0 > 0.2, "5 s at 40 % moved {} m", x1 - x0);

    let mut bad = thr.clone();
    bad[3 * 2 + 1] = 150.0;
    let e = sim
        .set_actuators(
            None,
            &ActuatorOrder {
                thrusters: Some(Rows {
                    data: &bad,
                    width: 3,
                }),
                tilts: None,
                pump: None,
            },
            false,
        )
        .unwrap_err();
    assert_eq!((e.vehicle, e.field.as_str()), (Some(2), "thrusters[1]"));
    assert!(e.message.contains("-100 … 100 %"), "{e}");
    let e = sim
        .set_actuators(
            None,
            &ActuatorOrder {
                thrusters: None,
                tilts: None,
                pump: Some(Column::All(2)),
            },
            false,
        )
        .unwrap_err();
    assert_eq!(e.field, "pump");
}

#[test]
fn flat_reads_equal_the_vehicle_snapshots() {
    let mut sim = world(shoal_world::load::DEFAULT_WORLD);
    sim.run(700);
    let pos = read(&mut sim, Quantity::Position);
    let att = read(&mut sim, Quantity::Attitude);
    let vel = read(&mut sim, Quantity::Velocity);
    let depth = read(&mut sim, Quantity::DepthReading);
    let imu = read(&mut sim, Quantity::ImuEuler);
    let sp = read(&mut sim, Quantity::Setpoint);
    let n = sim.len();
    let mut sent = vec![0i64; n];
    let mut got = vec![0i64; n];
    sim.read_i64(Quantity::FramesSent, &mut sent).unwrap();
    sim.read_i64(Quantity::FramesReceived, &mut got).unwrap();
    for i in 0..n {
        let v = sim.vehicle(i);
        let r = &v.state.rigid;
        assert_eq!(pos[3 * i..3 * i + 3], *r.position.as_slice());
        let q = r.attitude.coords;
        assert_eq!(att[4 * i..4 * i + 4], [q.w, q.x, q.y, q.z]);
        assert_eq!(vel[6 * i..6 * i + 6], *r.nu.as_slice());
        assert_eq!(depth[i], v.sensors.depth);
        assert_eq!(imu[3 * i + 2], euler_rpy(&v.sensors.attitude).2);
        assert_eq!(
            sp[4 * i..4 * i + 4],
            [
                v.setpoints.depth,
                v.setpoints.yaw,
                v.setpoints.surge,
                v.setpoints.sway
            ]
        );
        assert_eq!(sent[i] as u64, v.comm.sent);
        assert_eq!(got[i] as u64, v.comm.rx.delivered);
    }
    assert!(
        got.iter().sum::<i64>() > 0,
        "the default world's beacons are heard"
    );
    // A wrong buffer is an error, not a panic.
    assert!(sim.read_f64(Quantity::Position, &mut [0.0; 5]).is_err());
    assert!(sim.read_f64(Quantity::Mode, &mut vec![0.0; n]).is_err());
}

/// Two μAUV² 1 m apart facing each other, one front modem each (the preset's).
const PAIR: &str = "seed = 5\nduration = 100\n[pool]\nsize = [10.0, 6.0, 3.0]\n\
    [[vehicles]]\nname = \"a\"\nposition = [4.0, 3.0, 1.5]\n\
    [[vehicles]]\nname = \"b\"\nposition = [5.25, 3.0, 1.5]\nheading_deg = 180\n";

/// Runs `steps` steps collecting what is delivered.
fn collect(sim: &mut Sim, steps: u64) -> Vec<(u32, shoal_sim::comm::Received)> {
    let mut out = Arrivals::default();
    for _ in 0..steps {
        let t0 = sim.time();
        sim.step();
        sim.collect_received(t0, Some(&mut out), true);
    }
    out.frames
}

fn frame(payload: &[u8], delay: f64) -> FrameOrder {
    FrameOrder::broadcast(None, payload.to_vec(), delay)
}

#[test]
fn queued_frames_are_delivered_unless_both_modems_start_together() {
    // Staggered by 50 ms (more than a frame's airtime): each hears the other, once (in the
    // order of delivery).
    let mut sim = world(PAIR);
    sim.queue_frames(
        &[(0, frame(b"from a", 0.0)), (1, frame(b"from b", 0.05))],
        false,
    )
    .unwrap();
    let got = collect(&mut sim, 50);
    let seen: Vec<(u32, u32, &[u8])> = got.iter().map(|(v, r)| (*v, r.from, &*r.payload)).collect();
    assert_eq!(seen, [(1, 0, &b"from a"[..]), (0, 1, &b"from b"[..])]);
    assert!(got.iter().all(|(_, r)| r.power > 0.0 && r.t > r.sent));

    // The same instant: both modems are transmitting while the other's frame arrives
    // (half-duplex), so neither is heard.
    let mut sim = world(PAIR);
    sim.queue_frames(
        &[(0, frame(b"from a", 0.0)), (1, frame(b"from b", 0.0))],
        false,
    )
    .unwrap();
    assert!(collect(&mut sim, 50).is_empty());
    let mut lost = vec![0i64; 8];
    sim.read_i64(Quantity::FramesLost, &mut lost).unwrap();
    assert_eq!((lost[3], lost[7]), (1, 1), "lost to half-duplex: {lost:?}");
}

#[test]
fn bad_frames_are_refused_with_the_vehicle_and_frame() {
    let mut sim = world(PAIR);
    let long = vec![1u8; 200];
    let e = sim
        .queue_frames(&[(0, frame(b"ok", 0.0)), (1, frame(&long, 0.0))], false)
        .unwrap_err();
    assert_eq!((e.vehicle, e.field.as_str()), (Some(1), "frames[1]"));
    assert!(e.message.contains("200 bytes"), "{e}");
    let e = sim
        .queue_frames(&[(0, frame(b"x", 2.0))], false)
        .unwrap_err();
    assert!(e.message.contains("delay"), "{e}");
    let e = sim
        .queue_frames(
            &[(0, FrameOrder::broadcast(Some(3), b"x".to_vec(), 0.0))],
            false,
        )
        .unwrap_err();
    assert!(e.message.contains("modem 3 does not exist"), "{e}");
    assert!(sim.queue_frames(&[(2, frame(b"x", 0.0))], false).is_err());
    // Nothing was queued by the refused calls.
    assert!(collect(&mut sim, 50).is_empty());
}
