//! The wire structs of [`protocol`] to and from the world's own ([`shoal_sim::agents`]): a
//! command as the world's command ([`decode`]), an observation on the wire ([`encode`]). One
//! owner for each direction: the host, the fuzz test and benchmarks call these.
//!
//! Protocol-level problems (another version, an unknown kind or mode, a frame count or
//! length beyond the buffers) are counted here; everything the world can judge — a modem the
//! vehicle lacks, a payload longer than its modem carries, a destination that is not another
//! vehicle, an acknowledgement asked of a broadcast — is left to
//! [`Sim::command_vehicle`](shoal_sim::sim::Sim::command_vehicle), which counts it too.

use crate::protocol::{
    self, ALL_MODEMS, BROADCAST, Command, FRAME_BYTES, Frame, MAX_RX_FRAMES, Observation, Outcome,
    flags, frame_flags,
};
use shoal_model::ballast::Pump;
use shoal_model::control::Mode;
use shoal_model::math::euler_rpy;
use shoal_sim::agents::{self, Order, Rejections};
use shoal_sim::comm::{FrameEvent, FrameOutcome, Received};
use shoal_sim::orders::FrameOrder;

/// A wire command as a world command; protocol-level problems are counted and reject it (or,
/// for a frame, drop that frame).
pub fn decode(c: &Command, rej: &mut Rejections) -> Option<agents::Command> {
    if c.version != protocol::PROTOCOL_VERSION {
        rej.malformed += 1;
        return None;
    }
    let order = match c.kind {
        protocol::kind::KEEP => Order::Keep,
        protocol::kind::MODE => {
            let mode = match c.mode {
                protocol::mode::OFF => Mode::Off,
                protocol::mode::DIVING => Mode::Diving,
                protocol::mode::BUOYANCY => Mode::Buoyancy,
                protocol::mode::TURNING => Mode::Turning,
                protocol::mode::DRIFT => Mode::Drift,
                protocol::mode::AUTO => Mode::Auto,
                _ => {
                    rej.invalid += 1;
                    return None;
                }
            };
            Order::Mode {
                mode,
                depth: c.depth,
                yaw: c.yaw,
                surge: c.surge,
                sway: c.sway,
            }
        }
        protocol::kind::RAW => Order::Raw {
            thrusters: c.thrusters.to_vec(),
            tilts: c.tilts.to_vec(),
            pump: match Pump::from_wire(c.pump.into()) {
                Some(p) => p,
                None => {
                    rej.invalid += 1;
                    return None;
                }
            },
        },
        _ => {
            rej.invalid += 1;
            return None;
        }
    };
    let n = c.n_frames as usize;
    if n > protocol::MAX_TX_FRAMES {
        rej.bad_frames += (n - protocol::MAX_TX_FRAMES) as u64;
    }
    let mut frames = Vec::new();
    for f in c.frames.iter().take(n.min(protocol::MAX_TX_FRAMES)) {
        match frame_order(f) {
            Some(order) => frames.push(order),
            None => rej.bad_frames += 1,
        }
    }
    Some(agents::Command {
        id: c.vehicle,
        order,
        frames,
    })
}

/// A frame to send as the world's order, `None` when its length exceeds the buffer. The
/// destination ([`BROADCAST`]: none), the acknowledgement bit and the tag pass as they are,
/// for the world to check; flag bits other than [`frame_flags::ACK`] are ignored.
fn frame_order(f: &Frame) -> Option<FrameOrder> {
    if f.len as usize > FRAME_BYTES {
        return None;
    }
    Some(FrameOrder {
        to: (f.peer != BROADCAST).then_some(f.peer),
        ack: f.flags & frame_flags::ACK != 0,
        tag: f.tag,
        ..FrameOrder::broadcast(
            (f.modem != ALL_MODEMS).then_some(f.modem as usize),
            f.payload().to_vec(),
            f.t,
        )
    })
}

/// A world observation on the wire, with `extra` bits of [`flags`].
pub fn encode(o: &agents::Observation, extra: u32) -> Observation {
    let mut w = Observation::EMPTY;
    w.vehicle = o.id;
    w.step = o.step;
    w.time = o.t;
    let s = &o.sensors;
    w.depth = s.depth;
    let (roll, pitch, yaw) = euler_rpy(&s.attitude);
    w.roll = roll;
    w.pitch = pitch;
    w.yaw = yaw;
    w.rates = [s.gyro.x, s.gyro.y, s.gyro.z];
    w.accel = [s.accel.x, s.accel.y, s.accel.z];
    w.flags = extra;
    if let Some(p) = o.position {
        w.position = [p.x, p.y, p.z];
        w.flags |= flags::POSITION;
    }
    if s.tank_full {
        w.flags |= flags::TANK_FULL;
    }
    if o.fallback {
        w.flags |= flags::FALLBACK;
    }
    w.n_tilts = s.tilts.len().min(protocol::MAX_TILTS) as u32;
    for (d, v) in w.tilts.iter_mut().zip(&s.tilts) {
        *d = *v;
    }
    let mut n = 0;
    for r in &o.frames {
        if n == MAX_RX_FRAMES || r.payload.len() > FRAME_BYTES {
            w.frames_dropped += 1;
            continue;
        }
        w.frames[n] = received(r);
        n += 1;
    }
    w.n_frames = n as u32;
    for e in &o.outcomes {
        match w.outcomes.get_mut(w.n_outcomes as usize) {
            Some(slot) => {
                *slot = outcome(e);
                w.n_outcomes += 1;
            }
            None => w.outcomes_dropped += 1,
        }
    }
    w
}

/// A received frame on the wire (its payload fits: checked by the caller).
fn received(r: &Received) -> Frame {
    let mut f = Frame {
        t: r.t,
        power: r.power,
        modem: r.modem.min(254) as u8,
        flags: if r.unicast { frame_flags::UNICAST } else { 0 },
        peer: r.from,
        seq: r.seq,
        len: r.payload.len() as u16,
        ..Frame::EMPTY
    };
    f.data[..r.payload.len()].copy_from_slice(&r.payload);
    f
}

/// The end of an acknowledged frame on the wire.
fn outcome(e: &FrameEvent) -> Outcome {
    Outcome {
        t: e.t,
        sent: e.sent,
        to: e.to,
        tag: e.tag,
        seq: e.seq,
        transmissions: e.transmissions,
        acknowledged: u8::from(e.outcome == FrameOutcome::Acknowledged),
        ..Outcome::EMPTY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::MAX_OUTCOMES;
    use shoal_model::control::SensorReadings;
    use std::sync::Arc;

    fn obs(frames: Vec<Received>, outcomes: Vec<FrameEvent>) -> agents::Observation {
        agents::Observation {
            id: 2,
            step: 40,
            t: 0.4,
            sensors: SensorReadings::zeros(0),
            position: None,
            frames,
            outcomes,
            fallback: false,
        }
    }

    fn event(tag: u32, outcome: FrameOutcome) -> FrameEvent {
        FrameEvent {
            t: 0.35,
            to: 5,
            seq: 12,
            tag,
            payload: Arc::from(&[1u8, 2][..]),
            sent: 0.3,
            transmissions: 3,
            outcome,
        }
    }

    /// A received frame names its sender, its sequence number and whether it was addressed
    /// to this vehicle; outcomes keep their order, and those beyond the wire's room are
    /// counted.
    #[test]
    fn senders_and_outcomes_reach_the_wire() {
        let rx = |from: u32, unicast: bool| Received {
            t: 0.31,
            from,
            seq: 9,
            modem: 1,
            power: 2e-7,
            snr: 40.0,
            sent: 0.3,
            payload: Arc::from(&b"hi"[..]),
            unicast,
        };
        let mut outcomes: Vec<FrameEvent> = (0..MAX_OUTCOMES as u32 + 2)
            .map(|k| event(100 + k, FrameOutcome::GaveUp))
            .collect();
        outcomes[0].outcome = FrameOutcome::Acknowledged;
        let w = encode(&obs(vec![rx(3, true), rx(4, false)], outcomes), 0);
        let [u, b] = w.received() else {
            panic!("two frames: {:?}", w.received())
        };
        assert_eq!(
            (u.peer, u.flags, u.seq, u.tag, u.modem),
            (3, frame_flags::UNICAST, 9, 0, 1)
        );
        assert_eq!((u.t, u.power, u.payload()), (0.31, 2e-7, &b"hi"[..]));
        assert!(u.is_unicast() && !b.is_unicast());
        assert_eq!((b.peer, b.flags), (4, 0));
        assert_eq!(w.outcomes().len(), MAX_OUTCOMES);
        assert_eq!(w.outcomes_dropped, 2);
        let first = w.outcomes()[0];
        assert_eq!(
            (
                first.t,
                first.sent,
                first.to,
                first.tag,
                first.seq,
                first.transmissions
            ),
            (0.35, 0.3, 5, 100, 12, 3)
        );
        assert!(first.is_acknowledged());
        let tags: Vec<u32> = w.outcomes().iter().map(|o| o.tag).collect();
        assert_eq!(tags, [100, 101, 102, 103]);
        assert!(w.outcomes()[1..].iter().all(|o| !o.is_acknowledged()));
    }

    /// A frame's destination, acknowledgement bit and tag become the world's order as they
    /// are (the world judges them); a frame longer than the buffer is counted and dropped.
    #[test]
    fn addressed_frames_decode_to_orders() {
        let mut c = Command::keep(&Observation::EMPTY);
        c.send_to(1, 0, b"abc", 0.02, true, 41);
        c.send(ALL_MODEMS, b"all", 0.0);
        c.send_to(BROADCAST, 0, b"x", 0.0, true, 0); // the world refuses this one
        c.frames[3].len = FRAME_BYTES as u16 + 1;
        c.n_frames = 4;
        let mut rej = Rejections::default();
        let cmd = decode(&c, &mut rej).expect("a valid command");
        assert_eq!(rej.bad_frames, 1, "the oversized one");
        let f = &cmd.frames;
        assert_eq!(f.len(), 3);
        assert_eq!(
            (f[0].to, f[0].ack, f[0].tag, f[0].modem),
            (Some(1), true, 41, Some(0))
        );
        assert_eq!((f[0].delay, &f[0].payload[..]), (0.02, &b"abc"[..]));
        assert_eq!((f[1].to, f[1].ack, f[1].modem), (None, false, None));
        assert_eq!((f[2].to, f[2].ack), (None, true));
    }
}
