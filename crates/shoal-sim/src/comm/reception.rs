//! One reception decided at its receiver: the best-case bound, every copy's power at every
//! modem, occlusion, half-duplex, interference, capture and the bit-error draw
//! ([`receive`]), with the receiver's buffers ([`Scratch`], [`Listener`]).

use super::ending::ByVehicle;
use super::link_layer::Mail;
use super::links::Outcome;
use super::medium::{Logical, Medium};
use super::modem_lanes::ModemLanes;
use super::stats::{DIST_BIN, DIST_BINS, Tally, latency_bin};
use crate::rng::VehicleRng;
use rand::RngExt;
use shoal_model::math::Vec3;
use shoal_model::optics::{
    ModemParams, ModemPose, background_current, ber_ook, frame_error_rate, noise_variance,
};
use shoal_model::vehicle::VehicleModel;

/// Buffers of the delivery phase, one set per chunk of receivers, reused from receiver to
/// receiver.
#[derive(Default)]
pub(super) struct Scratch {
    /// The interferers of the current reception near its receiver (positions in the frame's
    /// [`Logical::overlap`]).
    interferers: Vec<u32>,
    /// Hull occlusion between the current receiver and other vehicles (other vehicle, clear),
    /// computed once per step: it depends on the vehicles' positions only.
    hulls: Vec<(u32, bool)>,
    /// The current receiver's modems (empty until a reception needs them).
    modems: ModemLanes,
    /// The power of each copy of the current frame at each modem, copy after copy \[W\].
    signal: Vec<f64>,
}

/// One receiver of the frames ending in a step, with what it needs for every reception.
pub(super) struct Listener<'s> {
    /// Its id.
    me: u32,
    /// Its model.
    kind: &'s VehicleModel,
    /// Body position \[m\] and attitude.
    pos: Vec3,
    att: shoal_model::math::Quat,
    /// Largest photodiode area of its modems \[m²\].
    area: f64,
    /// Buffers, reset for this receiver.
    scratch: &'s mut Scratch,
}

impl<'s> Listener<'s> {
    /// Receiver `me`, its buffers `scratch` emptied for it.
    pub(super) fn new(m: &'s Medium, me: u32, scratch: &'s mut Scratch) -> Self {
        let kind = &*m.kinds[me as usize];
        let (pos, att) = m.poses[me as usize];
        let area = m.consts[me as usize]
            .iter()
            .map(|c| c.area)
            .fold(0.0, f64::max);
        scratch.hulls.clear();
        scratch.modems.clear();
        Self {
            me,
            kind,
            pos,
            att,
            area,
            scratch,
        }
    }

    /// Hull occlusion between `other` and this receiver (see [`Medium::vehicles_clear`]),
    /// computed once per step.
    fn clear_of_hulls(hulls: &mut Vec<(u32, bool)>, m: &Medium, other: u32, me: u32) -> bool {
        if let Some(&(_, c)) = hulls.iter().find(|h| h.0 == other) {
            return c;
        }
        let c = m.vehicles_clear(other, me);
        hulls.push((other, c));
        c
    }
}

/// Decides one logical frame at one receiver; returns the outcome.
#[allow(clippy::too_many_arguments)]
pub(super) fn receive(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    rx: &mut Listener<'_>,
    own: &ByVehicle,
    l: &Logical<'_>,
    rng: &mut VehicleRng,
    mail: &mut Mail<'_>,
    tally: &mut Tally,
) -> Outcome {
    let f = l.first();
    let latency = f.end - f.sent;
    let distance = (m.poses[f.tx as usize].0 - rx.pos).norm();
    let bin = ((distance / DIST_BIN) as usize).min(DIST_BINS - 1);
    tally.by_distance[bin].0 += 1;
    if !m.may_decode(l, rx.me, rx.area) {
        // Undecodable even in the best case (P(delivery) < 1e-12): lost to range.
        return Outcome::OutOfBudget;
    }
    let consts = &m.consts[rx.me as usize];
    if rx.scratch.modems.is_empty() {
        let modems = &rx.kind.params.modems;
        rx.scratch.modems.fill(modems, consts, &rx.pos, &rx.att);
    }
    // Every copy's power at every modem, the modems' geometry in lanes.
    let n = consts.len();
    if n == 0 {
        // A hull without modems hears nothing (it is a candidate only by its position).
        return Outcome::OutOfBudget;
    }
    rx.scratch.signal.resize(l.copies.len() * n, 0.0);
    for (c, out) in l.copies.iter().zip(rx.scratch.signal.chunks_exact_mut(n)) {
        rx.scratch.modems.powers(m, c, consts, out);
    }
    // Interferers within range of this receiver, once a modem hears the signal.
    rx.scratch.interferers.clear();
    let mut interferers_found = false;
    let mut best = Outcome::OutOfBudget;
    let mut got: Option<(usize, f64, f64)> = None;
    for k in 0..n {
        let at = AtModem {
            m,
            geo,
            me: rx.me,
            k,
            pose: rx.scratch.modems.poses[k],
        };
        let hulls = &mut rx.scratch.hulls;
        let powers = rx.scratch.signal.iter().skip(k).step_by(n).copied();
        let p_sig = match at.signal(l, powers, hulls) {
            Ok(p) => p,
            Err(o) => {
                best = best.better(o);
                continue;
            }
        };
        if own_transmitting(m, own, rx.me, k, f.start, f.end) {
            best = best.better(Outcome::HalfDuplex);
            continue;
        }
        if !interferers_found {
            interferers_found = true;
            near_interferers(m, l, rx.me, &rx.pos, &mut rx.scratch.interferers);
        }
        let rxm = &rx.kind.params.modems[k];
        let p = at.interference(l, &rx.scratch.interferers, &mut rx.scratch.hulls);
        match decode(m, rxm, &at.pose, f.bits, p_sig, p, rng) {
            Ok(snr) => {
                best = Outcome::Delivered;
                if got.is_none_or(|g| p_sig > g.1) {
                    got = Some((k, p_sig, snr));
                }
            }
            Err(o) => best = best.better(o),
        }
    }
    if let Some(got) = got {
        tally.by_distance[bin].1 += 1;
        tally.latency[latency_bin(latency)] += 1;
        if let Some(l) = mail.decoded(rx.me, f, got) {
            tally.acknowledged[latency_bin(l)] += 1;
        }
    }
    best
}

/// Whether modem `modem` of vehicle `v` was transmitting at some time in (start, end) \[s\].
fn own_transmitting(
    m: &Medium,
    own: &ByVehicle,
    v: u32,
    modem: usize,
    start: f64,
    end: f64,
) -> bool {
    own.of(v)
        .iter()
        .map(|&k| &m.txs[k as usize])
        .any(|x| x.modem == modem && x.start < end && x.end > start)
}

/// Fills `out` with the positions in `l.overlap` of the transmissions of other vehicles
/// within range (r_cut plus a hull) of receiver `me` at `pos` \[m\], in order.
fn near_interferers(m: &Medium, l: &Logical<'_>, me: u32, pos: &Vec3, out: &mut Vec<u32>) {
    let reach = m.r_cut + m.max_hull_radius;
    out.extend(
        l.overlap
            .iter()
            .enumerate()
            .filter(|(_, x)| x.tx != me && (x.pose.position - pos).norm_squared() <= reach * reach)
            .map(|(i, _)| i as u32),
    );
}

/// One receiving modem of one reception.
struct AtModem<'a> {
    /// The medium.
    m: &'a Medium,
    /// Walls and obstacles.
    geo: &'a shoal_world::geometry::Geometry,
    /// The receiver.
    me: u32,
    /// The modem's index.
    k: usize,
    /// Its pose.
    pose: ModemPose,
}

impl AtModem<'_> {
    /// Whether the ray from `a` to this modem is clear of the water surface, walls and
    /// obstacles.
    fn path_clear(&self, a: &ModemPose) -> bool {
        let b = &self.pose;
        a.position.z > 0.0 && b.position.z > 0.0 && self.geo.line_of_sight(&a.position, &b.position)
    }

    /// The received power of the copies of `l` this modem can see \[W\], or why it has none:
    /// [`Outcome::Occluded`] if some copy would reach it but was blocked, else
    /// [`Outcome::OutOfBudget`]. `powers`: each copy's power at this modem, unoccluded
    /// ([`Medium::power_between`]).
    fn signal(
        &self,
        l: &Logical<'_>,
        powers: impl Iterator<Item = f64>,
        hulls: &mut Vec<(u32, bool)>,
    ) -> Result<f64, Outcome> {
        let mut p_sig = 0.0;
        let mut outcome = Outcome::OutOfBudget;
        for (c, p) in l.copies.iter().zip(powers) {
            if p <= 0.0 {
                continue;
            }
            if self.path_clear(&c.pose) && Listener::clear_of_hulls(hulls, self.m, c.tx, self.me) {
                p_sig += p;
            } else {
                outcome = outcome.better(Outcome::Occluded);
            }
        }
        if p_sig <= 0.0 {
            Err(outcome)
        } else {
            Ok(p_sig)
        }
    }

    /// Total and largest power of the interferers of `l` at `picked` positions of its overlap
    /// list that reach this modem \[W\], in order.
    fn interference(
        &self,
        l: &Logical<'_>,
        picked: &[u32],
        hulls: &mut Vec<(u32, bool)>,
    ) -> (f64, f64) {
        let my = &self.m.consts[self.me as usize][self.k];
        let (mut p_int, mut p_max) = (0.0f64, 0.0f64);
        for &i in picked {
            let x = l.overlap[i as usize];
            let p = self.m.power_between(x, &self.pose, my);
            if p <= 0.0
                || !self.path_clear(&x.pose)
                || !Listener::clear_of_hulls(hulls, self.m, x.tx, self.me)
            {
                continue;
            }
            p_int += p;
            p_max = p_max.max(p);
        }
        (p_int, p_max)
    }
}

/// Decodes a frame of `bits` line bits with signal `p_sig` and interference `(total,
/// largest)` \[W\] at modem `rxm` at `pose`: the SNR if delivered, else the outcome
/// ([`Outcome::Collided`] when the largest interferer is not weak enough to capture over,
/// [`Outcome::OutOfBudget`] for bit errors). Draws one number from `rng` unless it collided.
fn decode(
    m: &Medium,
    rxm: &ModemParams,
    pose: &ModemPose,
    bits: u64,
    p_sig: f64,
    (p_int, p_max): (f64, f64),
    rng: &mut VehicleRng,
) -> Result<f64, Outcome> {
    if p_max * rxm.capture_ratio > p_sig {
        return Err(Outcome::Collided);
    }
    // Delivered when a uniform draw is at least the frame error rate. The Chernoff bound
    // FER ≤ n·BER ≤ n·½·e^(−SNR/2) settles most draws without the error function; the
    // decision is exactly the one the full rate gives.
    let i_s = rxm.rx.responsivity * p_sig;
    let i_bg = background_current(&rxm.rx, &m.ambient, pose.position.z);
    let snr = i_s * i_s / noise_variance(&rxm.rx, i_s, i_bg, p_int);
    let u = rng.random::<f64>();
    let bound = bits as f64 * 0.5 * (-0.5 * snr).exp();
    if u < bound && u < frame_error_rate(ber_ook(snr), bits) {
        return Err(Outcome::OutOfBudget);
    }
    Ok(snr)
}
