//! Carrier sensing: the optical power a vehicle's photodiodes receive from the frames on the
//! air ([`sensed_power`]), and since when the channel has been idle for a threshold
//! ([`idle_since`]) — what the medium-access protocols listen to.

use super::medium::{Medium, Transmission, received_power};
use shoal_model::math::Vec3;
use shoal_model::optics::{LinkGeometry, ModemPose};

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense).
pub(super) fn sensed_power(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    me: u32,
    k: usize,
    pose: &ModemPose,
    t: f64,
) -> f64 {
    medium
        .txs
        .iter()
        .filter(|x| x.tx != me && x.start <= t && x.end > t)
        .map(|x| sensed_one(medium, geo, x, me, k, pose))
        .sum()
}

/// The optical power transmission `x` delivers to modem `k` of vehicle `me` at `pose` \[W\]:
/// the link budget, zero beyond the cut-off range or when walls, obstacles or hulls block it.
fn sensed_one(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    x: &Transmission,
    me: u32,
    k: usize,
    pose: &ModemPose,
) -> f64 {
    let rx = &medium.consts[me as usize][k];
    let g = LinkGeometry::between(&x.pose, pose);
    if g.distance > medium.r_cut {
        return 0.0;
    }
    let p = received_power(
        &medium.consts[x.tx as usize][x.modem],
        rx,
        &g,
        medium.attenuation,
    );
    if p > 0.0
        && geo.line_of_sight(&x.pose.position, &pose.position)
        && medium.vehicles_clear(x.tx, me)
    {
        p
    } else {
        0.0
    }
}

/// For carrier sensing by vehicle `v` at `pos`, `att` with threshold `threshold` \[W\] at time
/// `t` \[s\]: `None` if the power its photodiodes receive from other vehicles' frames on the
/// air exceeds the threshold at one of them, else the end of the last frame that alone did
/// (or the vehicle's own last frame, if later; −∞ if none) \[s\].
#[allow(clippy::too_many_arguments)]
pub(super) fn idle_since(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    v: u32,
    pos: &Vec3,
    att: &shoal_model::math::Quat,
    t: f64,
    threshold: f64,
) -> Option<f64> {
    // A frame that starts at this very instant is not heard yet (sensing takes time): two
    // stations whose back-offs end together both send, and collide.
    let heard = |x: &&Transmission| x.start < t;
    let mut since = m
        .txs
        .iter()
        .filter(|x| heard(x) && x.tx == v)
        .map(|x| x.end.min(t))
        .fold(f64::NEG_INFINITY, f64::max);
    // Modem by modem, so that nothing is allocated per decision.
    for (k, params) in m.kinds[v as usize].params.modems.iter().enumerate() {
        let pose = ModemPose::of(params, pos, att);
        let mut now = 0.0;
        for x in m.txs.iter().filter(|x| heard(x) && x.tx != v) {
            let p = sensed_one(m, geo, x, v, k, &pose);
            if x.end > t {
                now += p;
            } else if p > threshold {
                since = since.max(x.end);
            }
        }
        if now > threshold {
            return None;
        }
    }
    Some(since)
}
