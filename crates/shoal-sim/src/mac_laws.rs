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
//! [`Law::throughput`] predicts. Used by the tests of the protocols and by the figure of
//! `docs/mac.md` (`examples/mac_laws.rs`).

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
            Law::SlottedAloha => format!("access = \"slotted_aloha\"\nslot = {SLOT}"),
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

/// Runs the experiment's world `text` (see [`world_text`]) for its duration and measures G
/// and S in time units of `law`.
pub fn measure(law: Law, text: &str) -> Result<Point, String> {
    let desc = load_str(text, Path::new("<mac law experiment>")).map_err(|e| e.to_string())?;
    let duration = desc.duration;
    let mut sim = Sim::new(
        &desc,
        SimOptions {
            threads: 1,
            record: false,
        },
    );
    sim.run((duration / desc.dt).round() as u64);
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
