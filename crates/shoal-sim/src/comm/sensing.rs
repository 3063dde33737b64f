//! Carrier sensing: the optical power a vehicle's photodiodes receive from the frames on the
//! air ([`sensed_power`]), and since when the channel has been idle for a threshold
//! ([`idle_since`]) — what the medium-access protocols listen to. Both look at the
//! transmissions on record around the vehicle only ([`Air`], kept by the transmit phase), and
//! compute a link budget only for senders within reach.

use super::air::{Air, OnAir, OnRecord, Scratch};
use super::medium::{Medium, Transmission, received_power};
use shoal_model::math::Vec3;
use shoal_model::optics::{LinkGeometry, ModemPose};

/// What carrier sensing reads: the medium, the walls and obstacles, the transmissions on
/// record by position and the list they index.
pub(super) type Sensing<'a> = (
    &'a Medium,
    &'a shoal_world::geometry::Geometry,
    &'a Air,
    OnRecord<'a>,
);

/// Received optical power at a modem from every transmission active at time `t` except
/// those of vehicle `me` [W] (for carrier sense); `air`: the medium's transmissions.
pub(super) fn sensed_power(
    (medium, geo, air, rec): Sensing<'_>,
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
            sum += sensed_one((medium, geo, air), rec.get(x.index), (me, k, pose));
        },
    );
    sum
}

/// The optical power transmission `x` delivers to modem `k` of vehicle `me` at `pose` \[W\]:
/// the link budget, zero beyond the cut-off range or when walls, obstacles or hulls block it
/// (hull occlusion asked last, remembered by `air`).
fn sensed_one(
    (medium, geo, air): (&Medium, &shoal_world::geometry::Geometry, &Air),
    x: &Transmission,
    (me, k, pose): (u32, usize, &ModemPose),
) -> f64 {
    // Beyond the cut-off range nothing arrives: decided by a squared distance, before the
    // link geometry.
    let d = pose.position - x.pose.position;
    if d.norm_squared() > medium.r_cut * medium.r_cut {
        return 0.0;
    }
    let rx = &medium.consts[me as usize][k];
    if clearly_outside(x, pose, &d, rx.cos_fov) {
        return 0.0;
    }
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

/// Whether the modem at `pose`, `d` from the LED of transmission `x` \[m\], lies behind the
/// LED, or (for a field of view of at most 90°, `cos_fov` ≥ 0) faces away from it — by more
/// than a nanometre, so that the link geometry's rounding could not say otherwise: its
/// [`received_power`] is zero, known from two dot products before the geometry's root and
/// divisions (three sensing budgets in four end here on a ring of modems).
fn clearly_outside(x: &Transmission, pose: &ModemPose, d: &Vec3, cos_fov: f64) -> bool {
    x.pose.axis.dot(d) < -MARGIN || (cos_fov >= 0.0 && pose.axis.dot(d) > MARGIN)
}

/// How far a modem must lie behind an LED, or face away from it, for [`clearly_outside`] to
/// pass it over \[m\]: a nanometre.
const MARGIN: f64 = 1e-9;

/// Whether every modem of vehicle `v` of `m` lies behind the LED of transmission `x` by more
/// than [`MARGIN`] — its centre behind by more than its farthest modem's offset and twice that
/// (the rounding of the two ways of computing it is far smaller): [`clearly_outside`] would
/// pass each of them over, so none receives power from it, known from one dot product.
fn all_behind(m: &Medium, x: &Transmission, v: u32) -> bool {
    let centre = &m.poses[v as usize].0;
    x.pose.axis.dot(&(centre - x.pose.position)) < -(m.max_modem_offset + 2.0 * MARGIN)
}

/// Hands the power a transmission delivers to each of a vehicle's modems (its index, \[W\])
/// to the callback it is given.
type EachPower<'a> = dyn FnMut(&mut dyn FnMut(usize, f64)) + 'a;

/// What a vehicle listening at `t` has found out so far ([`idle_since`]).
struct Listening<'a> {
    v: u32,
    pos: &'a Vec3,
    t: f64,
    threshold: f64,
    /// The squared sensing reach \[m²\].
    reach2: f64,
    /// The end of the last frame that alone was heard above the threshold \[s\].
    since: f64,
    /// The first end of a frame heard now \[s\].
    until: f64,
    /// The frames that ended within reach, put aside: they are looked at only if the
    /// channel is idle ([`Listening::since_ended`]).
    ended: &'a mut Vec<OnAir>,
}

impl Listening<'_> {
    /// Sorts transmission `a` out: `true` if it is another vehicle's frame on the air now
    /// within reach (its powers decide whether it is heard: [`Listening::heard`]); else a
    /// frame of the vehicle's own is noted (the channel was taken until it ended) and one that
    /// ended within reach is put aside.
    fn on_air(&mut self, a: &OnAir) -> bool {
        // A frame that starts at this very instant is not heard yet (sensing takes time):
        // two stations whose back-offs end together both send, and collide.
        if a.start >= self.t {
            return false;
        }
        if a.tx == self.v {
            // The vehicle's own frames: the channel was taken until they ended.
            self.since = self.since.max(a.end.min(self.t));
            return false;
        }
        if (a.position - self.pos).norm_squared() > self.reach2 {
            return false;
        }
        if a.end > self.t {
            return true;
        }
        // Ended: it matters only if it ended later than those seen so far.
        if a.end > self.since {
            self.ended.push(*a);
        }
        false
    }

    /// Whether frame `a`, on the air, is heard (its powers at the vehicle's modems, handed to
    /// the callback of `each`: any above zero); notes when it ends if it is.
    fn heard(&mut self, a: &OnAir, each: &mut EachPower<'_>) -> bool {
        let mut heard = false;
        each(&mut |_, p| heard |= p > 0.0);
        if heard {
            self.until = self.until.min(a.end);
        }
        heard
    }

    /// The channel is idle: since when, looking at the frames put aside as they ended, the
    /// latest end first — the first that alone was heard above the threshold (`above(frame,
    /// threshold)`: at one of the vehicle's modems) is the last such end, and frames that ended
    /// before what is known need no link budget at all.
    fn since_ended(&mut self, above: impl Fn(&OnAir, f64) -> bool) -> f64 {
        self.ended.sort_unstable_by(|a, b| b.end.total_cmp(&a.end));
        for a in self.ended.iter() {
            if a.end <= self.since {
                break;
            }
            if above(a, self.threshold) {
                self.since = a.end;
                break;
            }
        }
        self.since
    }
}

/// For carrier sensing by vehicle `v` at `pos`, `att` with threshold `threshold` \[W\] at time
/// `t` \[s\]: `Err(until)` if the power its photodiodes receive from other vehicles' frames
/// on the air exceeds the threshold at one of them — `until` the first end of a frame that
/// reaches them now, before which the channel cannot fall idle \[s\] —, else `Ok` with the
/// end of the last frame that alone did (or the vehicle's own last frame, if later; −∞ if
/// none) \[s\].
pub(super) fn idle_since(
    (m, geo, air, rec): Sensing<'_>,
    v: u32,
    t: f64,
    threshold: f64,
) -> Result<f64, f64> {
    air.with_modem_poses(m, v, |poses| {
        listen((m, geo, air, rec), (v, poses), t, threshold)
    })
}

/// [`idle_since`] for vehicle `v` whose modems are at `poses`.
fn listen(
    (m, geo, air, rec): Sensing<'_>,
    (v, poses): (u32, &[ModemPose]),
    t: f64,
    threshold: f64,
) -> Result<f64, f64> {
    // Transmission by transmission around the vehicle, modem by modem inside: a transmission
    // whose sender is beyond the cut-off range of the vehicle's farthest modem is passed over
    // once. Nothing is allocated per decision once the scratch has grown.
    let pos = &m.poses[v as usize].0;
    let mut scratch = air.listening.borrow_mut();
    let Scratch { ended, on, powers } = &mut *scratch;
    ended.clear();
    on.clear();
    let mut l = Listening {
        v,
        pos,
        t,
        threshold,
        // Beyond the cut-off range of every modem of any vehicle, nothing arrives.
        reach2: (m.r_cut + m.max_modem_offset).powi(2),
        since: f64::NEG_INFINITY,
        until: f64::INFINITY,
        ended,
    };
    let one = |x: &Transmission, k, pose| sensed_one((m, geo, air), x, (v, k, pose));
    // The frames on the air within reach, in the order of the medium's list (in which the
    // powers add up); the vehicle's own noted, the frames that ended put aside.
    air.each_near(pos, |a| {
        if l.on_air(a) {
            on.push(*a);
        }
    });
    on.sort_unstable_by_key(|a| a.index);
    let mut now_small = [0.0f64; 8];
    let mut now_big = Vec::new();
    let now: &mut [f64] = if poses.len() <= 8 {
        &mut now_small[..poses.len()]
    } else {
        now_big.resize(poses.len(), 0.0);
        &mut now_big
    };
    // Which are heard, and when the first of them ends; their powers add up until one of the
    // vehicle's photodiodes receives more than the threshold (the sums only grow). From then
    // on the channel is busy, and only a frame ending before the first end found so far
    // matters, for when it may fall idle.
    let mut busy = false;
    for a in on.iter() {
        if busy && a.end >= l.until {
            continue;
        }
        let x = rec.get(a.index);
        // Behind the LED: no power at any modem (zeros add nothing, and it is not heard).
        if all_behind(m, x, v) {
            continue;
        }
        powers.clear();
        let heard = l.heard(a, &mut |f| {
            for (k, pose) in poses.iter().enumerate() {
                let p = one(x, k, pose);
                powers.push(p);
                f(k, p);
            }
        });
        if heard && !busy {
            for (sum, p) in now.iter_mut().zip(powers.iter()) {
                *sum += p;
            }
            busy = now.iter().any(|p| *p > threshold);
        }
    }
    if busy {
        return Err(l.until);
    }
    // The frames that ended waited: they matter only now that the channel is idle.
    Ok(l.since_ended(|a, threshold| {
        let x = rec.get(a.index);
        !all_behind(m, x, v)
            && poses
                .iter()
                .enumerate()
                .any(|(k, pose)| one(x, k, pose) > threshold)
    }))
}

/// Whether any modem of vehicle `v` receives power from transmission `a`: a frame that
/// reaches none of them changes nothing [`idle_since`] finds.
pub(super) fn reaches((m, geo, air, rec): Sensing<'_>, v: u32, a: &OnAir) -> bool {
    let x = rec.get(a.index);
    if all_behind(m, x, v) {
        return false;
    }
    air.with_modem_poses(m, v, |poses| {
        poses
            .iter()
            .enumerate()
            .any(|(k, pose)| sensed_one((m, geo, air), x, (v, k, pose)) > 0.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    /// A frame of sender `tx` that ended at `end` \[s\], at `index` in the medium's list.
    fn ended(end: f64, tx: u32, index: u32) -> OnAir {
        OnAir {
            start: end - 0.01,
            end,
            position: Vec3::zeros(),
            tx,
            index,
        }
    }

    /// The power each sender's frame delivers to a listener's one modem \[W\].
    fn power(tx: u32) -> f64 {
        match tx {
            2 => 0.5e-9,
            4 => 2e-9,
            3 => 3e-9,
            _ => 5e-9,
        }
    }

    fn listener<'a>(pos: &'a Vec3, since: f64, ended: &'a mut Vec<OnAir>) -> Listening<'a> {
        Listening {
            v: 9,
            pos,
            t: 1.0,
            threshold: 1e-9,
            reach2: 100.0,
            since,
            until: f64::INFINITY,
            ended,
        }
    }

    /// The channel is idle since the latest end of a frame that alone was heard above the
    /// threshold (by hand: senders 1, 3 and 4 are above it, 2 below; 4's frame ended last of
    /// those, at 0.45). The frames that ended are put aside and looked at latest end first,
    /// which needs the link budget of only the frames that end after that one — and of none
    /// when the vehicle's own frame ended later still.
    #[test]
    fn since_is_the_latest_end_heard_alone_above_the_threshold() {
        let frames = [
            ended(0.3, 1, 0),
            ended(0.5, 2, 1),
            ended(0.4, 3, 2),
            ended(0.45, 4, 3),
        ];
        let pos = Vec3::zeros();
        let asked = RefCell::new(Vec::new());
        let budget = |a: &OnAir, threshold: f64| {
            asked.borrow_mut().push(a.tx);
            power(a.tx) > threshold
        };
        let mut later = Vec::new();
        let mut l = listener(&pos, 0.2, &mut later);
        for a in &frames {
            assert!(!l.on_air(a));
        }
        assert_eq!(l.since_ended(budget), 0.45);
        assert_eq!(*asked.borrow(), [2, 4]);
        // The vehicle's own frame ended last: no budget at all.
        asked.borrow_mut().clear();
        let mut later = Vec::new();
        let mut l = listener(&pos, 0.2, &mut later);
        for a in frames.iter().chain([&ended(0.6, 9, 4)]) {
            assert!(!l.on_air(a));
        }
        assert_eq!(l.since_ended(budget), 0.6);
        assert!(asked.borrow().is_empty());
    }

    /// A frame of vehicle 0's first modem in a medium of two μAUV² (vehicle 0 at 1 m depth,
    /// unturned), vehicle 1 at `listener` \[m\], turned by `yaw` \[rad\] about the vertical.
    fn first_modem_frame(listener: Vec3, yaw: f64) -> (Medium, Transmission) {
        use shoal_model::math::Quat;
        use shoal_model::presets;
        use shoal_model::vehicle::VehicleModel;
        use std::sync::Arc;
        let kind = Arc::new(VehicleModel::new(presets::uauv2(), 1000.0));
        let mut m = Medium::in_the_dark(vec![kind; 2]);
        m.poses[0] = (Vec3::new(0.0, 0.0, 1.0), Quat::identity());
        m.poses[1] = (listener, Quat::from_axis_angle(&Vec3::z_axis(), yaw));
        let (pos, att) = m.poses[0];
        let pose = ModemPose::of(&m.kinds[0].params.modems[0], &pos, &att);
        let x = Transmission {
            id: 0,
            tx: 0,
            modem: 0,
            start: 0.0,
            end: 0.01,
            seq: 0,
            sent: 0.0,
            payload: Arc::from(vec![0u8; 4]),
            bits: 64,
            pose,
            kind: super::super::frames::Kind::Broadcast,
        };
        (m, x)
    }

    /// Whether [`clearly_outside`] passes over every modem of vehicle 1 for frame `x`.
    fn every_modem_outside(m: &Medium, x: &Transmission) -> bool {
        let (pos, att) = m.poses[1];
        m.kinds[1].params.modems.iter().enumerate().all(|(k, p)| {
            let pose = ModemPose::of(p, &pos, &att);
            let d = pose.position - x.pose.position;
            clearly_outside(x, &pose, &d, m.consts[1][k].cos_fov)
        })
    }

    /// A vehicle is behind an LED as a whole only when its centre is further behind than its
    /// farthest modem reaches, with the margin (by hand: the listener's centre on the LED's
    /// axis, behind the LED by the farthest offset plus 3 nm, 1 nm or nothing); whatever way it
    /// is turned, a vehicle the whole-vehicle test passes over has every modem passed over by
    /// the per-modem test too.
    #[test]
    fn a_vehicle_behind_the_led_is_so_modem_by_modem() {
        let probe = first_modem_frame(Vec3::zeros(), 0.0);
        let (led, axis) = (probe.1.pose.position, probe.1.pose.axis);
        let offset = probe.0.max_modem_offset;
        assert!(offset > 0.05, "{offset}");
        let at = |behind: f64| led - axis * (offset + behind);
        for yaw in [0.0, 0.4, 1.0, std::f64::consts::FRAC_PI_2, 2.5, 3.0] {
            let (m, x) = first_modem_frame(at(3e-9), yaw);
            assert!(all_behind(&m, &x, 1), "3 nm behind, yaw {yaw}");
            assert!(every_modem_outside(&m, &x), "yaw {yaw}");
            let (m, x) = first_modem_frame(at(1e-9), yaw);
            assert!(
                !all_behind(&m, &x, 1),
                "1 nm behind is within the margin, yaw {yaw}"
            );
            let (m, x) = first_modem_frame(at(0.0), yaw);
            assert!(!all_behind(&m, &x, 1), "yaw {yaw}");
            // In front of the LED: nothing is passed over at once.
            let (m, x) = first_modem_frame(led + axis, yaw);
            assert!(!all_behind(&m, &x, 1), "in front, yaw {yaw}");
        }
    }
}
