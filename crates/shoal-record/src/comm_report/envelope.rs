//! The most the link budget allows at each distance between two vehicles of a run
//! ([`delivery_envelope`]): the curve that `delivery_vs_distance` draws over the observed
//! ratios, which must lie under it (up to sampling noise).
//!
//! Every reception in the run is at most as good as this best case, per pair of modem designs
//! in the world, and the best pair is taken:
//!
//! * all of the sender's LED copies reach the receiving modem, each on axis at both ends
//!   (`cos φ = cos ψ = 1`, the largest channel gain `shoal_model::optics::channel_gain` has);
//! * the modems are as close as their mounts allow: the distance recorded is between the
//!   vehicles' body origins, so the modems may be nearer by the distance of each from its
//!   body origin;
//! * the receiver is at the pool's floor (the least daylight: ambient light falls with depth);
//! * no other transmitter interferes.
//!
//! The frame is the run's mean frame length (bit errors grow with it, slowly).

use shoal_model::optics::{LinkGeometry, ModemParams, channel_gain, reception};
use shoal_sim::view::VehicleView;
use shoal_world::desc::WorldDesc;

/// The envelope of delivery against distance, and what it assumes.
#[derive(Clone, Debug)]
pub struct Envelope {
    /// (distance between the vehicles' body origins \[m\], greatest delivery probability
    /// \[0, 1\]), at increasing distances.
    pub points: Vec<(f64, f64)>,
    /// What it is, for the legend.
    pub label: String,
}

/// How many distances the envelope is computed at, from 0 to the range drawn.
const SAMPLES: usize = 200;

/// The best-case delivery probability at body-origin distances from 0 to `range_m` \[m\] for
/// the modem designs of the vehicles `snaps` in the world `desc`, with frames of `bits` line
/// bits (see the module documentation); `None` when no vehicle has a modem.
pub fn delivery_envelope(
    desc: &WorldDesc,
    snaps: &[VehicleView<'_>],
    range_m: f64,
    bits: u64,
) -> Option<Envelope> {
    // The distinct modem sets (a sender's copies all leave from one set).
    let mut sets: Vec<&[ModemParams]> = Vec::new();
    for s in snaps {
        let m = s.model.params.modems.as_slice();
        if !m.is_empty() && !sets.contains(&m) {
            sets.push(m);
        }
    }
    let receivers: Vec<&ModemParams> = sets.iter().flat_map(|s| s.iter()).collect();
    let floor = desc.geometry.pool.z;
    // How far a modem of `set` sits from its body origin, at most [m].
    let reach = |set: &[ModemParams]| set.iter().map(|m| m.position.norm()).fold(0.0, f64::max);
    let best = |d: f64| {
        let mut p_best: f64 = 0.0;
        for tx in &sets {
            for rx in &receivers {
                let dm = (d - reach(tx) - rx.position.norm()).max(1e-3);
                let p_rx: f64 = tx
                    .iter()
                    .map(|m| {
                        m.led.power
                            * channel_gain(
                                &m.led,
                                &rx.rx,
                                &LinkGeometry::on_axis(dm),
                                desc.attenuation,
                            )
                    })
                    .sum();
                let b = reception(&rx.rx, p_rx, &desc.ambient, floor, 0.0, bits);
                p_best = p_best.max(1.0 - b.fer);
            }
        }
        p_best
    };
    let first = sets.first()?;
    let copies = sets.iter().map(|s| s.len()).max().unwrap_or(1);
    let nearer = 2.0 * sets.iter().map(|s| reach(s)).fold(0.0, f64::max);
    let points = (0..=SAMPLES)
        .map(|k| {
            let d = k as f64 * range_m / SAMPLES as f64;
            (d, best(d))
        })
        .collect();
    let label = format!(
        "link budget, best case (upper bound): all {copies} LED copies on axis, modems up to \
         {nearer:.2} m nearer than the vehicles, receiver at the floor ({floor:.1} m), no \
         interference, {:.0}-byte frames (run mean)",
        bits as f64 / f64::from(first[0].bits_per_byte)
    );
    Some(Envelope { points, label })
}
