//! A synthetic replay for tests, size measurements and the viewer's development: no physics,
//! but geometry and counts that agree with each other. A test kit, not part of the product:
//! shoal-record's unit tests, its browser tests and its `replay_demo` example include this
//! file (`#[path]`).
//!
//! [`demo`]`(n, seconds)`: `n` vehicles of one μAUV²-sized group (or two, from 8 vehicles) on
//! horizontal circles about a vertical cylinder (radius 0.6 m, floor to surface) in the middle
//! of a 10 × 6 × 3 m pool. The circles are rings of up to 24 vehicles at radii 1.0–2.7 m and
//! depths 0.4–2.6 m; each ring turns at its own speed (0.15–0.3 m/s, alternate directions),
//! with a slow depth oscillation, banked and pitched slightly; heading is the direction of
//! travel.
//!
//! Every vehicle sends one 64-byte frame (33 ms at 19.2 kbit/s) every ≈2 s (its own period
//! and phase) to its near neighbours: the next two on its ring either way, the one opposite,
//! and the nearest on the rings beside it (radius and depth). Each attempt's outcome follows
//! the geometry at the sending time: beyond [`MODEM_RANGE_M`] or, with a probability growing
//! with distance, bit errors → out of budget; the line crossing the cylinder → occluded; the
//! receiver sending itself during the frame → half-duplex; another of the receiver's
//! neighbours sending during the frame → collided; otherwise delivered. The timeline counts
//! every attempt (components and degrees from the frames delivered in each second), the
//! `links` array keeps every k-th one beyond [`LINK_BUDGET`], and the panel
//! holds each second's depth (with 1 cm noise), setpoints, mode, cumulative frames sent and
//! received and the senders heard in that second. Deterministic (no RNG state: a hash of the
//! indices).

use std::f64::consts::{PI, TAU};

use shoal_sim::replay::{
    GroupMeta, LINK_BUDGET, LinkEvent, Meta, ObstacleMeta, Outcome, PANEL, ReplayData, Timeline,
    frame_count, frame_dt, panel_dt,
};

/// Cut-off range of the demo's modems \[m\].
pub const MODEM_RANGE_M: f64 = 2.0;
/// Pool length (north), width (east), depth \[m\].
const POOL: [f64; 3] = [10.0, 6.0, 3.0];
/// Centre of the cylinder (and of every ring), NED \[m\].
const CENTRE: [f64; 2] = [5.0, 3.0];
/// Radius of the cylinder \[m\].
const CYLINDER_R: f64 = 0.6;
/// μAUV² hull length, width, height \[m\].
const HULL: [f64; 3] = [0.270, 0.156, 0.182];
/// Vehicles per ring at most.
const RING: usize = 24;
/// Airtime of one frame: 64 bytes × 10 bits at 19.2 kbit/s \[s\].
const AIRTIME: f64 = 64.0 * 10.0 / 19_200.0;
/// Mode code of the demo's vehicles in `modes` ("auto").
const MODE_AUTO: f32 = 5.0;

/// A synthetic replay of `n_vehicles` over `seconds` s, at the frame rate [`frame_dt`] picks;
/// see the module documentation.
pub fn demo(n_vehicles: usize, seconds: f64) -> ReplayData {
    let seconds = if seconds.is_finite() && seconds > 0.0 {
        seconds
    } else {
        1.0
    };
    let n = n_vehicles;
    let rings = Rings::new(n);
    let dt = frame_dt(n, seconds);
    let frames = frame_count(seconds, dt);
    let pdt = panel_dt(n, seconds);

    // Poses.
    let mut pos = Vec::with_capacity(frames * n * 3);
    let mut att = Vec::with_capacity(frames * n * 3);
    for k in 0..frames {
        let t = k as f64 * dt;
        for i in 0..n {
            let p = rings.pose(i, t);
            for (a, pool) in p.pos.iter().zip(POOL) {
                pos.push(quantise_pos(*a, pool));
            }
            for a in p.rpy {
                att.push(quantise_angle(a));
            }
        }
    }

    // Link attempts, in time order: every vehicle's sends, sorted.
    let mut sends: Vec<(f64, u32)> = Vec::new();
    for i in 0..n {
        let (phase, period) = rings.schedule(i);
        let mut t = phase;
        while t + AIRTIME <= seconds {
            sends.push((t, i as u32));
            t += period;
        }
    }
    sends.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let neighbours: Vec<Vec<u32>> = (0..n).map(|i| rings.neighbours(i)).collect();
    // Who hears whom: the senders of each receiver (the relation is not symmetric).
    let mut senders: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, list) in neighbours.iter().enumerate() {
        for &j in list {
            senders[j as usize].push(i as u32);
        }
    }
    let total: usize = sends
        .iter()
        .map(|&(_, i)| neighbours[i as usize].len())
        .sum();
    let keep_every = total.div_ceil(LINK_BUDGET).max(1);

    let secs = (seconds.ceil() as usize).max(1);
    let mut timeline = Timeline::default();
    for s in [
        &mut timeline.attempted,
        &mut timeline.delivered,
        &mut timeline.collided,
        &mut timeline.occluded,
        &mut timeline.out_of_budget,
        &mut timeline.half_duplex,
        &mut timeline.components,
    ] {
        s.resize(secs, 0);
    }
    let mut links = Vec::with_capacity(total.min(LINK_BUDGET));
    let mut heard: Vec<Vec<(u32, u32)>> = vec![Vec::new(); secs]; // (receiver, sender)
    let mut sent_in: Vec<Vec<u32>> = vec![Vec::new(); secs];
    let mut received_in: Vec<Vec<u32>> = vec![Vec::new(); secs];
    let mut attempt = 0usize;
    for &(t, s) in &sends {
        let sec = (t as usize).min(secs - 1);
        let sp = rings.pose(s as usize, t).pos;
        if sent_in[sec].is_empty() {
            sent_in[sec] = vec![0; n];
            received_in[sec] = vec![0; n];
        }
        sent_in[sec][s as usize] += 1;
        for &r in &neighbours[s as usize] {
            let rp = rings.pose(r as usize, t).pos;
            let d = dist(sp, rp);
            let outcome = if crosses_cylinder(sp, rp) {
                Outcome::Occluded
            } else if d > MODEM_RANGE_M
                || hash01(s as u64, r as u64, (t * 1e3) as u64) < 0.35 * (d / MODEM_RANGE_M).powi(4)
            {
                Outcome::OutOfBudget
            } else if rings.sends_during(r as usize, t) {
                Outcome::HalfDuplex
            } else if senders[r as usize]
                .iter()
                .any(|&o| o != s && rings.sends_during(o as usize, t))
            {
                Outcome::Collided
            } else {
                Outcome::Delivered
            };
            let series = match outcome {
                Outcome::Delivered => &mut timeline.delivered,
                Outcome::Collided => &mut timeline.collided,
                Outcome::Occluded => &mut timeline.occluded,
                Outcome::OutOfBudget => &mut timeline.out_of_budget,
                Outcome::HalfDuplex => &mut timeline.half_duplex,
            };
            series[sec] += 1;
            timeline.attempted[sec] += 1;
            if outcome == Outcome::Delivered {
                heard[sec].push((r, s));
                received_in[sec][r as usize] += 1;
            }
            if attempt.is_multiple_of(keep_every) {
                links.push(LinkEvent {
                    t: (t + AIRTIME) as f32,
                    from: s,
                    to: r,
                    outcome,
                    ack: false,
                });
            }
            attempt += 1;
        }
    }

    // Connectivity of each second's deliveries, and the panel.
    timeline.largest_fraction = vec![0.0; secs];
    timeline.mean_degree = vec![0.0; secs];
    let mut panel = Vec::with_capacity(secs * n * PANEL.len());
    let (mut sent, mut received) = (vec![0u32; n], vec![0u32; n]);
    for sec in 0..secs {
        let mut edges: Vec<(u32, u32)> = heard[sec]
            .iter()
            .map(|&(a, b)| (a.min(b), a.max(b)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let (components, largest) = components(n, &edges);
        timeline.components[sec] = components as u64;
        if n > 0 {
            timeline.largest_fraction[sec] = largest as f64 / n as f64;
            timeline.mean_degree[sec] = 2.0 * edges.len() as f64 / n as f64;
        }
        let mut from: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(r, s) in &heard[sec] {
            from[r as usize].push(s);
        }
        let t = sec as f64;
        for i in 0..n {
            if !sent_in[sec].is_empty() {
                sent[i] += sent_in[sec][i];
                received[i] += received_in[sec][i];
            }
            from[i].sort_unstable();
            from[i].dedup();
            let p = rings.pose(i, t);
            let ahead = rings.pose(i, t + 1.0);
            let noise = (hash01(i as u64, sec as u64, 7) - 0.5) * 0.02;
            if (sec as f64) % pdt != 0.0 {
                // Not a panel row (large swarms: a row every panel_dt s).
                continue;
            }
            panel.extend_from_slice(&[
                (p.pos[2] + noise) as f32,
                rings.depth(i) as f32,
                ahead.rpy[2] as f32,
                MODE_AUTO,
                sent[i] as f32,
                received[i] as f32,
                from[i].len() as f32,
            ]);
        }
    }

    let groups = if n >= 8 {
        vec![("scouts", n / 2), ("relays", n - n / 2)]
    } else {
        vec![("swarm", n)]
    };
    let group_of = (0..n).map(|i| u32::from(n >= 8 && i >= n / 2)).collect();
    let links_total = total as u64;
    ReplayData {
        meta: Meta {
            version: 1,
            world: format!("demo: {n} vehicles on circles"),
            seed: 0,
            duration_s: seconds,
            frame_dt: dt,
            frames,
            panel_dt: pdt,
            vehicles: n,
            pool: POOL,
            obstacles: vec![ObstacleMeta {
                name: "pillar".into(),
                kind: "cylinder".into(),
                size: None,
                radius: Some(CYLINDER_R),
                height: Some(POOL[2]),
                position: [CENTRE[0], CENTRE[1], POOL[2] / 2.0],
                // Local y (the cylinder's axis) onto world z: 90° about x.
                rotation: [
                    std::f64::consts::FRAC_1_SQRT_2,
                    0.0,
                    0.0,
                    std::f64::consts::FRAC_1_SQRT_2,
                ],
            }],
            groups: groups
                .iter()
                .enumerate()
                .map(|(g, &(name, count))| GroupMeta {
                    name: name.into(),
                    color: palette(g),
                    count,
                })
                .collect(),
            group_of,
            names: (0..n)
                .map(|i| format!("auv{i:0w$}", w = digits(n)))
                .collect(),
            hull: vec![HULL; groups.len()],
            modem_range_m: MODEM_RANGE_M,
            panel: PANEL.iter().map(|s| (*s).into()).collect(),
            modes: [
                "off", "diving", "buoyancy", "turning", "drift", "auto", "raw",
            ]
            .iter()
            .map(|s| (*s).into())
            .collect(),
            links_kept: links.len(),
            links_total,
            timeline,
            // The page's writer fills in the one colour key (`html::write`).
            outcomes: Vec::new(),
            ack_label: String::new(),
        },
        pos,
        att,
        panel,
        links,
    }
}

/// The plots' colour `g` as `#rrggbb`.
fn palette(g: usize) -> String {
    let (r, gr, b) = shoal_output::plot::rgb(g);
    format!("#{r:02x}{gr:02x}{b:02x}")
}

/// Decimal digits of the largest index below `n` (at least 1).
fn digits(n: usize) -> usize {
    n.saturating_sub(1).max(1).to_string().len()
}

/// `x` in `[0, pool]` as u16 (`q / 65535 · pool`).
fn quantise_pos(x: f64, pool: f64) -> u16 {
    // Rounding to the nearest step is the quantisation.
    ((x / pool).clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// An angle as i16 (`q · π / 32767`), wrapped to (−π, π].
fn quantise_angle(a: f64) -> i16 {
    let a = (a + PI).rem_euclid(TAU) - PI;
    (a / PI * 32767.0).round().clamp(-32767.0, 32767.0) as i16
}

/// A vehicle's pose: NED position \[m\] and roll, pitch, yaw \[rad\].
struct Pose {
    pos: [f64; 3],
    rpy: [f64; 3],
}

/// The rings of the demo: vehicle `i` is number `i % per` on ring `i / per`.
struct Rings {
    n: usize,
    /// Vehicles per ring.
    per: usize,
    /// Rings in the radius direction (the rest are depth layers).
    radii: usize,
    /// Number of rings.
    count: usize,
}

impl Rings {
    fn new(n: usize) -> Self {
        let count = n.div_ceil(RING).max(1);
        let per = n.div_ceil(count).max(1);
        // About as many radii as depth layers, at most 12 radii.
        let radii = ((count as f64).sqrt().ceil() as usize).clamp(1, 12);
        Rings {
            n,
            per,
            radii,
            count,
        }
    }

    /// Ring and place on it of vehicle `i`.
    fn place(&self, i: usize) -> (usize, usize) {
        (i / self.per, i % self.per)
    }

    /// Vehicles on ring `ring`.
    fn size(&self, ring: usize) -> usize {
        self.per.min(self.n.saturating_sub(ring * self.per))
    }

    fn radius(&self, ring: usize) -> f64 {
        let k = ring % self.radii;
        1.0 + 1.7 * k as f64 / (self.radii.max(2) - 1) as f64
    }

    fn layer_depth(&self, ring: usize) -> f64 {
        let layers = self.count.div_ceil(self.radii);
        let k = ring / self.radii;
        if layers <= 1 {
            1.5
        } else {
            0.4 + 2.2 * k as f64 / (layers - 1) as f64
        }
    }

    /// Depth setpoint of vehicle `i` \[m\].
    fn depth(&self, i: usize) -> f64 {
        self.layer_depth(self.place(i).0)
    }

    /// Angular speed of ring `ring` \[rad/s\] (positive: clockwise seen from above, i.e.
    /// north → east).
    fn omega(&self, ring: usize) -> f64 {
        let speed = 0.15 + 0.15 * hash01(ring as u64, 1, 2);
        let sign = if ring.is_multiple_of(2) { 1.0 } else { -1.0 };
        sign * speed / self.radius(ring)
    }

    fn pose(&self, i: usize, t: f64) -> Pose {
        let (ring, k) = self.place(i);
        let r = self.radius(ring);
        let w = self.omega(ring);
        let th = TAU * k as f64 / self.size(ring) as f64 + 0.37 * ring as f64 + w * t;
        let bob = 0.1 * (0.3 * t + 0.7 * i as f64).sin();
        let bob_rate = 0.03 * (0.3 * t + 0.7 * i as f64).cos();
        let speed = w.abs() * r;
        // Velocity (north, east) = w r (−sin θ, cos θ).
        let yaw = (w * th.cos()).atan2(-w * th.sin());
        Pose {
            pos: [
                CENTRE[0] + r * th.cos(),
                CENTRE[1] + r * th.sin(),
                self.depth(i) + bob,
            ],
            // Bank into the turn (towards the centre), nose down when sinking.
            rpy: [
                w.signum() * 0.15 * speed / 0.3,
                -(bob_rate / speed.max(0.05)).atan(),
                yaw,
            ],
        }
    }

    /// Send phase \[s\] and period \[s\] of vehicle `i`.
    fn schedule(&self, i: usize) -> (f64, f64) {
        (
            2.0 * hash01(i as u64, 3, 4),
            1.8 + 0.4 * hash01(i as u64, 5, 6),
        )
    }

    /// Whether vehicle `i` is sending at some moment of the frame that starts at `t`.
    fn sends_during(&self, i: usize, t: f64) -> bool {
        let (phase, period) = self.schedule(i);
        let k = ((t - phase) / period).round().max(0.0);
        let start = phase + k * period;
        (start - t).abs() < AIRTIME
    }

    /// The near neighbours vehicle `i` sends to.
    fn neighbours(&self, i: usize) -> Vec<u32> {
        let (ring, k) = self.place(i);
        let m = self.size(ring);
        let mut out = Vec::with_capacity(8);
        let mut add = |j: usize| {
            if j != i && j < self.n && !out.contains(&(j as u32)) {
                out.push(j as u32);
            }
        };
        for step in [1, 2, m / 2, m.saturating_sub(1), m.saturating_sub(2)] {
            if step > 0 && step < m {
                add(ring * self.per + (k + step) % m);
            }
        }
        // The nearest vehicle at the start on each ring beside this one.
        let beside = [
            (ring % self.radii > 0).then(|| ring - 1),
            (ring % self.radii + 1 < self.radii).then_some(ring + 1),
            ring.checked_sub(self.radii),
            Some(ring + self.radii),
        ];
        for other in beside.into_iter().flatten().filter(|&o| o < self.count) {
            let size = self.size(other);
            if size == 0 {
                continue;
            }
            let here = self.pose(i, 0.0).pos;
            let nearest = (0..size).map(|q| other * self.per + q).min_by(|&a, &b| {
                dist(here, self.pose(a, 0.0).pos).total_cmp(&dist(here, self.pose(b, 0.0).pos))
            });
            if let Some(j) = nearest {
                add(j);
            }
        }
        out
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Whether the segment `a`–`b` passes through the vertical cylinder (its horizontal
/// projection comes closer than the radius to the axis; it spans the whole depth).
fn crosses_cylinder(a: [f64; 3], b: [f64; 3]) -> bool {
    let (ax, ay) = (a[0] - CENTRE[0], a[1] - CENTRE[1]);
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let s = if len2 > 0.0 {
        (-(ax * dx + ay * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (cx, cy) = (ax + s * dx, ay + s * dy);
    cx * cx + cy * cy < CYLINDER_R * CYLINDER_R
}

/// Connected components of `n` vertices with `edges`: their number and the largest's size.
fn components(n: usize, edges: &[(u32, u32)]) -> (usize, usize) {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for &(a, b) in edges {
        let (ra, rb) = (root(&mut parent, a as usize), root(&mut parent, b as usize));
        if ra != rb {
            parent[ra] = rb;
        }
    }
    let mut size = vec![0usize; n];
    for x in 0..n {
        let r = root(&mut parent, x);
        size[r] += 1;
    }
    let count = size.iter().filter(|&&s| s > 0).count();
    (count, size.into_iter().max().unwrap_or(0))
}

/// A number in [0, 1) from three integers (splitmix64 of their mix).
fn hash01(a: u64, b: u64, c: u64) -> f64 {
    let mut z = a
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(b.wrapping_mul(0xBF58_476D_1CE4_E5B9))
        .wrapping_add(c.wrapping_mul(0x94D0_49BB_1331_11EB))
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_demo_is_consistent() {
        for (n, s) in [(0, 1.0), (1, 2.0), (12, 10.0), (100, 5.5)] {
            let d = demo(n, s);
            d.check().unwrap_or_else(|e| panic!("{n} × {s}: {e}"));
            let t = &d.meta.timeline;
            assert_eq!(t.attempted.len(), s.ceil() as usize);
            for k in 0..t.attempted.len() {
                let lost = t.collided[k] + t.occluded[k] + t.out_of_budget[k] + t.half_duplex[k];
                assert_eq!(t.attempted[k], t.delivered[k] + lost);
            }
            assert_eq!(d.meta.links_total, t.attempted.iter().sum::<u64>());
            assert_eq!(d.links.len() as u64, d.meta.links_total); // none thinned
            assert!(d.links.windows(2).all(|w| w[0].t <= w[1].t));
            assert_eq!(d.panel_rows(), if n > 0 { t.attempted.len() } else { 0 });
        }
    }

    #[test]
    fn every_outcome_occurs_in_a_small_swarm() {
        let d = demo(40, 30.0);
        for o in Outcome::ALL {
            assert!(
                d.links.iter().any(|e| e.outcome == o),
                "{o:?} never happens"
            );
        }
        let count = |o| d.links.iter().filter(|e| e.outcome == o).count();
        let counts = Outcome::ALL.map(count);
        assert!(
            counts.iter().all(|&c| c <= counts[0]),
            "delivered most often: {counts:?}"
        );
        assert!(
            counts[0] * 5 > d.links.len() * 2,
            "delivered > 40 %: {counts:?}"
        );
    }

    #[test]
    fn vehicles_stay_in_the_pool_and_head_along_their_circle() {
        let rings = Rings::new(1000);
        for i in (0..1000).step_by(37) {
            for t in [0.0, 3.3, 50.0] {
                let p = rings.pose(i, t);
                for (a, pool) in p.pos.iter().zip(POOL) {
                    assert!(*a > 0.1 && *a < pool - 0.1, "{i} at {t}: {:?}", p.pos);
                }
                let q = rings.pose(i, t + 0.01);
                let course = (q.pos[1] - p.pos[1]).atan2(q.pos[0] - p.pos[0]);
                let err = (course - p.rpy[2] + PI).rem_euclid(TAU) - PI;
                assert!(
                    err.abs() < 0.05,
                    "{i} at {t}: course {course}, yaw {}",
                    p.rpy[2]
                );
            }
        }
    }

    #[test]
    fn large_swarms_keep_the_link_budget() {
        let d = demo(2000, 120.0);
        assert!(d.links.len() <= LINK_BUDGET);
        assert!(d.meta.links_total > LINK_BUDGET as u64);
        assert!(
            d.links.len() * 2 > LINK_BUDGET,
            "thinned evenly, not starved"
        );
    }

    #[test]
    fn quantisation_round_trips_within_a_step() {
        for x in [0.0, 0.001, 4.2, 9.9999, 10.0] {
            let q = quantise_pos(x, 10.0);
            assert!((q as f64 / 65535.0 * 10.0 - x).abs() <= 10.0 / 65535.0);
        }
        for a in [-PI, -1.0, 0.0, 0.5, PI - 1e-6, 3.0 * PI / 2.0] {
            let q = quantise_angle(a);
            let back = q as f64 * PI / 32767.0;
            let err = (back - a + PI).rem_euclid(TAU) - PI;
            assert!(err.abs() <= PI / 32767.0, "{a} → {q}");
        }
    }
}
