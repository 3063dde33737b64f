//! Carrier sensing: the optical power a vehicle's photodiodes receive from the frames on the
//! air ([`sensed_power`]), and since when the channel has been idle for a threshold
//! ([`idle_since`]) — what the medium-access protocols listen to. Both look at the
//! transmissions on record around the vehicle only ([`Air`], kept by the transmit phase), and
//! compute a link budget only for senders within reach.

use super::air::{Air, MODEMS_REMEMBERED, OnAir};
use super::medium::{Medium, Transmission, received_power};
use shoal_model::math::Vec3;
use shoal_model::optics::{LinkGeometry, ModemPose};

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense); `air`: the medium's transmissions.
pub(super) fn sensed_power(
    medium: &Medium,
    geo: &shoal_world::geometry::Geometry,
    air: &Air,
    me: u32,
    (k, pose): (usize, &ModemPose),
    t: f64,
) -> f64 {
    let r2 = medium.r_cut * medium.r_cut;
    let mut sum = 0.0;
    air.in_list_order(
        &pose.position,
        |x| {
            x.tx != me
                && x.start <= t
                && x.end > t
                && (x.position - pose.position).norm_squared() <= r2
        },
        |x| {
            sum += sensed_one(
                (medium, geo, air),
                &medium.txs[x.index as usize],
                me,
                k,
                pose,
            )
        },
    );
    sum
}

/// The optical power transmission `x` delivers to modem `k` of vehicle `me` at `pose` \[W\]:
/// the link budget, zero beyond the cut-off range or when walls, obstacles or hulls block it.
fn sensed_one(
    (medium, geo, air): (&Medium, &shoal_world::geometry::Geometry, &Air),
    x: &Transmission,
    me: u32,
    k: usize,
    pose: &ModemPose,
) -> f64 {
    // Beyond the cut-off range nothing arrives: decided by a squared distance, before the
    // link geometry.
    if (x.pose.position - pose.position).norm_squared() > medium.r_cut * medium.r_cut {
        return 0.0;
    }
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
        && air.vehicles_clear(medium, x.tx, me)
    {
        p
    } else {
        0.0
    }
}

/// For carrier sensing by vehicle `v` at `pos`, `att` with threshold `threshold` \[W\] at time
/// `t` \[s\]: `Err(until)` if the power its photodiodes receive from other vehicles' frames
/// on the air exceeds the threshold at one of them — `until` the first end of a frame that
/// reaches them now, before which the channel cannot fall idle \[s\] —, else `Ok` with the
/// end of the last frame that alone did (or the vehicle's own last frame, if later; −∞ if
/// none) \[s\].
#[allow(clippy::too_many_arguments)]
pub(super) fn idle_since(
    m: &Medium,
    geo: &shoal_world::geometry::Geometry,
    air: &Air,
    v: u32,
    pos: &Vec3,
    att: &shoal_model::math::Quat,
    t: f64,
    threshold: f64,
) -> Result<f64, f64> {
    let mut since = f64::NEG_INFINITY;
    let mut until = f64::INFINITY;
    // Transmission by transmission around the vehicle, modem by modem inside: a transmission
    // whose sender is beyond the cut-off range of the vehicle's farthest modem is passed over
    // once; each modem's power adds up in the order of the medium's list. Nothing is
    // allocated per decision for up to eight modems.
    let modems = &m.kinds[v as usize].params.modems;
    let poses_small: [ModemPose; 8];
    let poses_big: Vec<ModemPose>;
    let poses: &[ModemPose] = if modems.len() <= 8 {
        poses_small = std::array::from_fn(|k| {
            modems.get(k).map_or(
                ModemPose {
                    position: *pos,
                    axis: Vec3::x(),
                },
                |p| ModemPose::of(p, pos, att),
            )
        });
        &poses_small[..modems.len()]
    } else {
        poses_big = modems.iter().map(|p| ModemPose::of(p, pos, att)).collect();
        &poses_big
    };
    let reach = m.r_cut + modems.iter().map(|p| p.position.norm()).fold(0.0, f64::max);
    let mut now_small = [0.0f64; 8];
    let mut now_big = Vec::new();
    let now: &mut [f64] = if modems.len() <= 8 {
        &mut now_small[..modems.len()]
    } else {
        now_big.resize(modems.len(), 0.0);
        &mut now_big
    };
    // The powers of a transmission at the vehicle's modems, remembered for the phase (up to
    // eight modems); `f` with each.
    let each_power = |a: &OnAir, f: &mut dyn FnMut(usize, f64)| {
        let x = &m.txs[a.index as usize];
        if poses.len() <= MODEMS_REMEMBERED {
            let p = air.powers(v, a, || {
                let mut p = [0.0; MODEMS_REMEMBERED];
                for (k, pose) in poses.iter().enumerate() {
                    p[k] = sensed_one((m, geo, air), x, v, k, pose);
                }
                p
            });
            for (k, p) in p[..poses.len()].iter().enumerate() {
                f(k, *p);
            }
        } else {
            for (k, pose) in poses.iter().enumerate() {
                f(k, sensed_one((m, geo, air), x, v, k, pose));
            }
        }
    };
    // Which frames are on the air and heard (their powers add up below, in list order), when
    // the first of them ends, and the end of the last frame that alone was heard.
    air.in_list_order(
        pos,
        |a| {
            // A frame that starts at this very instant is not heard yet (sensing takes time):
            // two stations whose back-offs end together both send, and collide.
            if a.start >= t {
                return false;
            }
            if a.tx == v {
                // The vehicle's own frames: the channel was taken until they ended.
                since = since.max(a.end.min(t));
                return false;
            }
            if (a.position - pos).norm_squared() > reach * reach {
                return false;
            }
            if a.end > t {
                let mut heard = false;
                each_power(a, &mut |_, p| heard |= p > 0.0);
                if heard {
                    until = until.min(a.end);
                }
                heard
            } else {
                // Ended: it matters only if it ended later than those seen so far.
                if a.end > since {
                    let mut alone = false;
                    each_power(a, &mut |_, p| alone |= p > threshold);
                    if alone {
                        since = a.end;
                    }
                }
                false
            }
        },
        |a| each_power(a, &mut |k, p| now[k] += p),
    );
    if now.iter().any(|p| *p > threshold) {
        return Err(until);
    }
    Ok(since)
}
