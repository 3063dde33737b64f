//! Fuzzing the agent command path: wire commands with arbitrary field values — wrong
//! versions, unknown kinds, modes and pump values, NaN/inf/huge setpoints and raw commands,
//! frame counts and lengths beyond the limits, frames for unknown modems, destinations that
//! are the sender or no vehicle, acknowledgements asked of broadcasts, any flag bits — decoded
//! ([`shoal_bridge::host::decode`]) and applied to a world's agent-driven vehicle
//! ([`Sim::command_vehicle`]), then the world stepped. Never a panic; a command with a
//! non-finite number it uses is rejected and counted; every state stays finite.
//!
//! `cargo test` runs 256 cases; a long run:
//! `PROPTEST_CASES=1000000 cargo test --release -p shoal-bridge --test fuzz_commands`.

use proptest::prelude::*;
use shoal_bridge::host::decode;
use shoal_bridge::protocol::{self, Command, FRAME_BYTES, Frame, MAX_TILTS, MAX_TX_FRAMES};
use shoal_sim::agents::Rejections;
use shoal_sim::prelude::*;
use shoal_world::load::load_str;
use std::path::Path;

const WORLD: &str = "duration = 10.0\n[pool]\nsize = [6.0, 6.0, 3.0]\n\
    [[vehicles]]\nname = \"pilot\"\nposition = [2.0, 2.0, 1.0]\nagent = \"pilot\"\n\
    [vehicles.model]\nmodems = [{ name = \"front\", position = [0.1, 0.0, 0.0], direction = [1.0, 0.0, 0.0] }]\n\
    [[vehicles]]\nname = \"other\"\nposition = [4.0, 4.0, 1.0]\n";

fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => -200.0..200.0f64,
        1 => prop::sample::select(vec![
            f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -0.0, 5e-324, 1e308, -1e308, 1e9,
        ]),
        1 => any::<f64>(),
    ]
}

fn frame() -> impl Strategy<Value = Frame> {
    (
        number(),
        prop_oneof![3 => 0u16..=(FRAME_BYTES as u16 + 2), 1 => any::<u16>()],
        prop_oneof![3 => 0u8..3, 1 => Just(protocol::ALL_MODEMS), 1 => any::<u8>()],
        any::<u8>(),
        (
            prop_oneof![3 => 0u8..4, 1 => any::<u8>()],
            prop_oneof![2 => Just(protocol::BROADCAST), 2 => 0u32..3, 1 => any::<u32>()],
            any::<u32>(),
        ),
    )
        .prop_map(|(t, len, modem, fill, (flags, peer, tag))| {
            let mut f = Frame::EMPTY;
            f.t = t;
            f.len = len;
            f.modem = modem;
            f.data = [fill; FRAME_BYTES];
            f.flags = flags;
            f.peer = peer;
            f.tag = tag;
            f
        })
}

fn command() -> impl Strategy<Value = Command> {
    (
        (
            prop_oneof![9 => Just(protocol::PROTOCOL_VERSION), 1 => any::<u32>()],
            prop_oneof![8 => Just(0u32), 1 => Just(1u32), 1 => any::<u32>()],
            prop_oneof![8 => 0u32..4, 1 => any::<u32>()],
            prop_oneof![8 => 0u32..7, 1 => any::<u32>()],
            prop_oneof![8 => -1i32..=1, 1 => any::<i32>()],
        ),
        (number(), number(), number(), number()),
        prop::array::uniform8(number()),
        prop::array::uniform4(number()),
        (
            prop_oneof![4 => 0u32..=(MAX_TX_FRAMES as u32 + 1), 1 => any::<u32>()],
            prop::array::uniform4(frame()),
        ),
    )
        .prop_map(
            |(
                (version, vehicle, kind, mode, pump),
                (depth, yaw, surge, sway),
                thrusters,
                tilts,
                (n_frames, frames),
            )| {
                let mut c = Command::leave();
                c.version = version;
                c.vehicle = vehicle;
                c.kind = kind;
                c.mode = mode;
                c.depth = depth;
                c.yaw = yaw;
                c.surge = surge;
                c.sway = sway;
                c.thrusters = thrusters;
                c.tilts = tilts;
                c.pump = pump;
                c.n_frames = n_frames;
                c.frames = frames;
                c
            },
        )
}

/// Whether a command that decodes uses a non-finite number (which must reject it).
fn uses_non_finite(c: &Command, sim: &Sim) -> bool {
    let v = sim.vehicle(0);
    let n_thr = v.model.params.thrusters.len();
    let n_tilt = v.model.params.tilts.len().min(MAX_TILTS);
    match c.kind {
        protocol::kind::MODE => ![c.depth, c.yaw, c.surge, c.sway]
            .iter()
            .all(|x| x.is_finite()),
        protocol::kind::RAW => {
            !c.thrusters[..n_thr].iter().all(|x| x.is_finite())
                || !c.tilts[..n_tilt].iter().all(|x| x.is_finite())
        }
        _ => false,
    }
}

proptest! {
    #[test]
    fn arbitrary_commands_never_panic_and_non_finite_is_rejected(cmds in prop::collection::vec(command(), 1..6)) {
        let desc = load_str(WORLD, Path::new("fuzz.toml")).unwrap();
        let mut sim = Sim::new(&desc, SimOptions { threads: 1, ..SimOptions::default() });
        sim.run(3);
        for c in &cmds {
            let mut rej = Rejections::default();
            let applied = match decode(c, &mut rej) {
                Some(cmd) => sim.command_vehicle(0, &cmd, &mut rej),
                None => false,
            };
            if applied {
                prop_assert!(
                    !(c.vehicle == 0 && c.version == protocol::PROTOCOL_VERSION && uses_non_finite(c, &sim)),
                    "a command with a non-finite number was applied: {c:?}"
                );
            } else {
                prop_assert!(rej.total() > 0, "a refused command was not counted: {c:?}");
            }
            sim.run(5);
        }
        prop_assert!(sim.fault().is_none(), "{}", sim.fault().unwrap());
        for v in sim.vehicles() {
            prop_assert!(v.state.rigid.is_finite(), "{} is not finite", v.name);
        }
    }
}
