//! The medium-access law experiment: does a protocol's throughput follow its textbook law?
//!
//! [`world_text`] builds the geometry the laws assume: `senders` vehicles on a cylinder
//! patch 2 m around one receiver (±60° of its axis, in layers above and below it), every LED
//! facing the receiver, whose one photodiode sees a whole hemisphere; nothing occludes a link,
//! every link is far above its noise floor, and capture is off (a frame survives only if no
//! other frame overlaps it at the receiver). Each sender offers Poisson traffic
//! (`kind = "poisson"`) of frames whose airtime is one [`FRAME_TIME`]; the receiver never
//! transmits. [`measure`] runs it and counts what the receiver got: the offered load G and
//! the throughput S, both in frames per frame time (per slot for slotted protocols), which
//! [`Law::throughput`] predicts. [`csma_world_text`] and [`measure_csma`] do the same for
//! CSMA/CA against Bianchi's saturation model ([`bianchi`]). Used by the tests of the
//! protocols and by the figures of `docs/mac.md` (`examples/mac_laws.rs`).

use crate::comm::CommStats;
use crate::sim::{Sim, SimOptions};
use shoal_world::load::load_str;
use std::path::Path;

/// Payload of the experiment's frames \[bytes\]: with the μAUV² modem's 6-byte header and 10
/// line bits per byte, a 320-bit frame.
pub const PAYLOAD: usize = 26;
/// Airtime of the experiment's frames at 19.2 kbit/s \[s\].
pub const FRAME_TIME: f64 = 320.0 / 19_200.0;
/// Slot of the slotted protocols \[s\]: a frame and a 0.8-ms guard.
pub const SLOT: f64 = 0.0175;

/// A protocol of the experiment and the law it should follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Law {
    /// Unslotted ALOHA: S = G·e^(−2G).
    PureAloha,
    /// Slotted ALOHA: S = G·e^(−G).
    SlottedAloha,
}

impl Law {
    /// The textbook throughput at offered load `g` (frames per frame time or slot).
    pub fn throughput(self, g: f64) -> f64 {
        match self {
            Law::PureAloha => g * (-2.0 * g).exp(),
            Law::SlottedAloha => g * (-g).exp(),
        }
    }

    /// Its `access` in a world file, with the fields it needs.
    fn access(self) -> String {
        match self {
            Law::PureAloha => "access = \"aloha\"".into(),
            Law::SlottedAloha => format!("access = {{ kind = \"slotted_aloha\", slot = {SLOT} }}"),
        }
    }

    /// The time unit of its load and throughput \[s\].
    pub fn unit(self) -> f64 {
        match self {
            Law::PureAloha => FRAME_TIME,
            Law::SlottedAloha => SLOT,
        }
    }
}

/// The experiment's world: `senders` vehicles offering together `g` frames per time unit of
/// `law`, for `duration` \[s\], seed `seed`. The receiver is vehicle 0.
pub fn world_text(law: Law, senders: usize, g: f64, duration: f64, seed: u64) -> String {
    let rate = g / law.unit() / senders as f64;
    let centre = [6.0, 6.0, 1.5];
    let mut t = format!(
        "name = \"{law:?} at G = {g}\"\nseed = {seed}\nduration = {duration}\ndt = 0.01\n\
         [pool]\nsize = [12.0, 12.0, 3.0]\n[output]\nplots = false\n\
         [[vehicles]]\nname = \"receiver\"\nposition = [{}, {}, {}]\n\
         [[vehicles.model.modems]]\nrx_fov_deg = 90.0\ncapture_ratio = 1e6\n",
        centre[0], centre[1], centre[2]
    );
    let layers = senders.div_ceil(13).max(1);
    for i in 0..senders {
        let (layer, k) = (i / 13, i % 13);
        let per_layer = 13.min(senders - layer * 13);
        let phi = if per_layer > 1 {
            (-60.0 + 120.0 * k as f64 / (per_layer - 1) as f64).to_radians()
        } else {
            0.0
        };
        let z = centre[2] + 0.25 * (layer as f64 - (layers - 1) as f64 / 2.0);
        let (x, y) = (centre[0] + 2.0 * phi.cos(), centre[1] + 2.0 * phi.sin());
        let heading = (phi + std::f64::consts::PI).to_degrees();
        t.push_str(&format!(
            "[[vehicles]]\nname = \"s{i}\"\nposition = [{x:.4}, {y:.4}, {z:.3}]\nheading_deg = {heading:.3}\n\
             behaviour = {{ kind = \"poisson\", rate = {rate}, payload_bytes = {PAYLOAD} }}\n\
             [[vehicles.model.modems]]\nled_power = 0.5\nmax_payload = {PAYLOAD}\n{}\n",
            law.access()
        ));
    }
    t
}

/// What one run of the experiment measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Offered load: transmissions started per time unit.
    pub g: f64,
    /// Throughput: frames the receiver got per time unit.
    pub s: f64,
    /// Transmissions started.
    pub frames: u64,
    /// Frames the receiver got.
    pub delivered: u64,
    /// Frames lost at the receiver to anything but a collision.
    pub other_losses: u64,
}

/// Loads world `text` (named `name` in errors) and runs it on one thread for its duration;
/// the world and the duration \[s\].
fn run(text: &str, name: &str) -> Result<(Sim, f64), String> {
    let desc = load_str(text, Path::new(name)).map_err(|e| e.to_string())?;
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    sim.run((desc.duration / desc.dt).round() as u64);
    Ok((sim, desc.duration))
}

/// Runs the experiment's world `text` (see [`world_text`]) for its duration and measures G
/// and S in time units of `law`.
pub fn measure(law: Law, text: &str) -> Result<Point, String> {
    let (sim, duration) = run(text, "<mac law experiment>")?;
    let rx: CommStats = sim.vehicle(0).comm;
    let frames = sim.medium().started.0;
    let units = duration / law.unit();
    Ok(Point {
        g: frames as f64 / units,
        s: rx.rx.delivered as f64 / units,
        frames,
        delivered: rx.rx.delivered,
        other_losses: rx.rx.lost_range + rx.rx.lost_occlusion + rx.rx.lost_half_duplex,
    })
}
/// Bianchi's saturation model of CSMA/CA with binary exponential back-off (G. Bianchi,
/// "Performance analysis of the IEEE 802.11 distributed coordination function", IEEE JSAC
/// 18(3), 2000): `n` stations that always have a frame, all hearing each other, an ideal
/// channel; contention window `w` slots doubling `m` times; slot `sigma`, a successful
/// exchange occupying the channel `t_s`, a collision `t_c`, a frame's airtime `frame` \[s\].
/// Returns the channel's throughput: the share of time it carries successful frames, and
/// the transmission probability τ per slot.
pub fn bianchi(n: u32, w: f64, m: u32, sigma: f64, t_s: f64, t_c: f64, frame: f64) -> (f64, f64) {
    let tau = |p: f64| {
        let q = 1.0 - 2.0 * p;
        2.0 * q / (q * (w + 1.0) + p * w * (1.0 - (2.0 * p).powi(m as i32)))
    };
    // p = 1 − (1 − τ(p))^(n−1): the left side minus the right rises from negative at p = 0
    // to positive at p = 1; bisection.
    let f = |p: f64| p - (1.0 - (1.0 - tau(p)).powi(n as i32 - 1));
    let (mut lo, mut hi) = (0.0, 1.0 - 1e-12);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = tau(0.5 * (lo + hi));
    let p_tr = 1.0 - (1.0 - t).powi(n as i32);
    let p_s = f64::from(n) * t * (1.0 - t).powi(n as i32 - 1) / p_tr;
    let s =
        p_s * p_tr * frame / ((1.0 - p_tr) * sigma + p_tr * p_s * t_s + p_tr * (1.0 - p_s) * t_c);
    (s, t)
}

/// Timing of the CSMA/CA experiment ([`csma_world_text`]).
pub mod csma {
    /// Physics step \[s\]: an acknowledgement starts within one step of its frame's end.
    pub const DT: f64 = 0.0005;
    /// Back-off slot \[s\].
    pub const SLOT: f64 = 0.001;
    /// Idle time before a back-off count resumes \[s\]: longer than an acknowledgement's
    /// delay (one step), so acknowledgements are never contended.
    pub const DIFS: f64 = 0.003;
    /// Smallest and largest contention window \[slots\].
    pub const CW: (u32, u32) = (16, 1024);
    /// Airtime of an acknowledgement (a 6-byte header) \[s\].
    pub const ACK_TIME: f64 = 60.0 / 19_200.0;
    /// Wait for the acknowledgement: its delay, airtime and the step it is decided in \[s\].
    pub const ACK_TIMEOUT: f64 = 0.0045;
}

/// The CSMA/CA experiment (Bianchi's assumptions): `n` stations on a horizontal circle of
/// 1.2 m radius, alternately 0.15 m above and below its plane, each facing the centre with
/// four modems (front, right, back, left) so that every station hears every other one; an
/// access point ("receiver") 0.9 m above the centre whose one modem looks down with a
/// photodiode that sees the whole hemisphere below it (one collision domain). Each station is
/// saturated with 32-byte unicast frames for the access point, acknowledged and retried
/// without limit; capture is off.
pub fn csma_world_text(n: usize, duration: f64, seed: u64) -> String {
    use csma::*;
    let access = format!(
        "{{ kind = \"csma_ca\", threshold = 1e-12, backoff_slot = {SLOT}, difs = {DIFS}, \
         cw_min = {}, cw_max = {} }}",
        CW.0, CW.1
    );
    circle_world_text(n, duration, seed, &access, true)
}

/// The geometry of [`csma_world_text`] with medium access `access` (its value in a world
/// file) and saturated traffic: acknowledged unicasts for the access point (`acked`) or
/// broadcasts.
fn circle_world_text(n: usize, duration: f64, seed: u64, access: &str, acked: bool) -> String {
    use csma::*;
    let (cx, cy, depth) = (6.0, 6.0, 1.8);
    let common = format!(
        "led_power = 0.5\nmax_payload = {PAYLOAD}\ncapture_ratio = 1e6\n\
         access = {access}\narq_retries = 100\nack_timeout = {ACK_TIMEOUT}\n"
    );
    let to = if acked {
        ", to = \"receiver\", ack = true"
    } else {
        ""
    };
    let mut t = format!(
        "name = \"{n} stations around an access point\"\nseed = {seed}\nduration = {duration}\ndt = {DT}\n\
         [pool]\nsize = [12.0, 12.0, 3.0]\n[output]\nplots = false\n\
         [[vehicles]]\nname = \"receiver\"\nposition = [{cx}, {cy}, {}]\n\
         [[vehicles.model.modems]]\nposition = [0.0, 0.0, 0.09]\ndirection = [0.0, 0.0, 1.0]\n\
         rx_fov_deg = 90.0\n{common}",
        depth - 0.9
    );
    for i in 0..n {
        let phi = std::f64::consts::TAU * i as f64 / n as f64 - std::f64::consts::PI;
        let z = depth + if i % 2 == 0 { 0.15 } else { -0.15 };
        let (x, y) = (cx + 1.2 * phi.cos(), cy + 1.2 * phi.sin());
        let heading = (phi + std::f64::consts::PI).to_degrees();
        t.push_str(&format!(
            "[[vehicles]]\nname = \"s{i}\"\nposition = [{x:.4}, {y:.4}, {z:.3}]\nheading_deg = {heading:.3}\n\
             behaviour = {{ kind = \"poisson\", rate = 1000.0, payload_bytes = {PAYLOAD}{to} }}\n"
        ));
        for (name, pos, dir) in crate::bench::RING {
            t.push_str(&format!(
                "[[vehicles.model.modems]]\nname = \"{name}\"\nposition = {pos}\ndirection = {dir}\n{common}"
            ));
        }
    }
    t
}

/// What the CSMA/CA experiment measured and Bianchi's model predicts for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Saturation {
    /// Stations.
    pub n: usize,
    /// Share of time the channel carried frames the access point decoded.
    pub s: f64,
    /// Bianchi's prediction.
    pub model: f64,
    /// Frames the access point decoded.
    pub delivered: u64,
    /// Retransmissions of all stations.
    pub retransmissions: u64,
}

/// Runs the CSMA/CA experiment with `n` stations for `duration` \[s\] and compares the
/// throughput with Bianchi's model for its timing: a success occupies the channel for the
/// frame, the acknowledgement's mean delay (half a step), its airtime and a DIFS; a collision
/// for the frame and a DIFS.
pub fn measure_csma(n: usize, duration: f64, seed: u64) -> Result<Saturation, String> {
    use csma::*;
    let (sim, _) = run(&csma_world_text(n, duration, seed), "<csma experiment>")?;
    let ap = sim.vehicle(0).comm;
    let retransmissions = (1..=n).map(|i| sim.vehicle(i).comm.retransmissions).sum();
    let m = (f64::from(CW.1) / f64::from(CW.0)).log2().round() as u32;
    let t_s = FRAME_TIME + 0.5 * DT + ACK_TIME + DIFS;
    let t_c = FRAME_TIME + DIFS;
    let (model, _) = bianchi(n as u32, f64::from(CW.0), m, SLOT, t_s, t_c, FRAME_TIME);
    Ok(Saturation {
        n,
        s: ap.rx.delivered as f64 * FRAME_TIME / duration,
        model,
        delivered: ap.rx.delivered,
        retransmissions,
    })
}

/// Slotted p-persistent CSMA in saturation: `n` stations that always have a frame, all
/// hearing each other, each sending with probability `p` at every slot boundary of an idle
/// channel (slots of `sigma`, the first a slot after the channel fell idle); a frame's
/// airtime `frame` \[s\]. A boundary is idle with probability (1 − p)^n (it lasts `sigma`),
/// else a transmission starts — alone with probability n·p·(1 − p)^(n−1) — and the channel
/// is busy for the frame and the slot to the next boundary. Returns the channel's
/// throughput: the share of time it carries successful frames.
pub fn p_persistent(n: u32, p: f64, sigma: f64, frame: f64) -> f64 {
    let idle = (1.0 - p).powi(n as i32);
    let alone = f64::from(n) * p * (1.0 - p).powi(n as i32 - 1);
    alone * frame / (idle * sigma + (1.0 - idle) * (frame + sigma))
}

/// What the p-persistent experiment measured and the law predicts for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Persistent {
    /// Stations.
    pub n: usize,
    /// Probability of sending at an idle slot boundary.
    pub p: f64,
    /// Share of time the channel carried frames the access point decoded.
    pub s: f64,
    /// The law's prediction ([`p_persistent`]).
    pub model: f64,
    /// Frames the access point decoded.
    pub delivered: u64,
    /// Frames of the stations lost at the access point to collisions.
    pub collisions: u64,
}

/// Runs slotted p-persistent CSMA with `n` saturated stations broadcasting in the geometry
/// of [`csma_world_text`] for `duration` \[s\] and compares the access point's throughput
/// with [`p_persistent`]'s law.
pub fn measure_p_persistent(
    n: usize,
    p: f64,
    duration: f64,
    seed: u64,
) -> Result<Persistent, String> {
    use csma::*;
    let access =
        format!("{{ kind = \"p_persistent\", threshold = 1e-12, backoff_slot = {SLOT}, p = {p} }}");
    let text = circle_world_text(n, duration, seed, &access, false);
    let (sim, _) = run(&text, "<p-persistent experiment>")?;
    let ap = sim.vehicle(0).comm;
    Ok(Persistent {
        n,
        p,
        s: ap.rx.delivered as f64 * FRAME_TIME / duration,
        model: p_persistent(n as u32, p, SLOT, FRAME_TIME),
        delivered: ap.rx.delivered,
        collisions: ap.rx.lost_collision,
    })
}
