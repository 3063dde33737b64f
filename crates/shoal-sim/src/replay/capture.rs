//! Gathers a [`ReplayData`] while the world runs: an ECS system at the end of every step
//! samples the vehicles' poses every frame, the panel values every [`super::Meta::panel_dt`] s, and drains the
//! reception attempts the medium logged ([`crate::comm::Ledger::drain_heard`]).
//!
//! It is switched on by [`crate::sim::Sim::enable_replay`] (which also makes the medium log
//! receptions) and taken with [`crate::sim::Sim::take_replay`]; without it the system does
//! nothing.

use super::{
    GroupMeta, LINK_BUDGET, LinkEvent, Meta, ObstacleMeta, PANEL, PANEL_BUDGET_BYTES, ReplayData,
    Timeline,
};
use crate::comm::{CommStats, Ledger, Medium, Outcome};
use crate::components::{Clock, VehicleId};
use crate::connectivity::Connectivity;
use crate::fleet::Fleet;
use crate::recorder::mode_code;
use bevy_ecs::prelude::*;
use shoal_model::control::Mode;
use shoal_world::desc::WorldDesc;

/// The time between replay frames for `vehicles` vehicles over `duration_s` seconds \[s\]:
/// [`super::frame_dt`] (the pose budget), rounded up to a whole number of physics steps
/// `dt` \[s\].
pub fn frame_dt(vehicles: usize, duration_s: f64, dt: f64) -> f64 {
    let want = super::frame_dt(vehicles, duration_s);
    if !(dt > 0.0 && dt.is_finite()) {
        return want;
    }
    // A 1e-9 relative tolerance so 0.1 / 0.01 stays 10 steps.
    (want / dt * (1.0 - 1e-9)).ceil().max(1.0) * dt
}

/// The replay being gathered (an ECS resource).
#[derive(Resource, Debug)]
pub struct ReplayRecorder {
    data: ReplayData,
    /// Physics steps between frames.
    frame_every: u64,
    /// Physics steps between panel rows, at least 1.
    panel_every: u64,
    /// Whether a panel row fits in [`PANEL_BUDGET_BYTES`] at all (not for swarms of more than
    /// about 225,000 vehicles: their pages have no panel).
    panel: bool,
    /// Keep every `stride`-th link event (doubles when the budget is reached).
    stride: u64,
    /// Link events seen so far.
    seen: u64,
    scratch: Vec<LinkEvent>,
}

impl ReplayRecorder {
    /// A recorder for `desc` (the header is filled from the world; frame 0 is taken by the
    /// first call of the system, at the end of the first step).
    pub fn new(desc: &WorldDesc, modem_range_m: f64) -> Self {
        let n = desc.vehicles.len();
        let fdt = frame_dt(n, desc.duration, desc.dt);
        let pdt = super::panel_dt(n, desc.duration);
        let pool = desc.geometry.pool;
        let obstacles = desc.geometry.obstacles.iter().map(obstacle_meta).collect();
        let mut groups: Vec<GroupMeta> = desc
            .groups
            .iter()
            .enumerate()
            .map(|(g, name)| {
                let (r, gr, b) = shoal_output::plot::rgb(g);
                GroupMeta {
                    name: name.clone(),
                    color: format!("#{r:02x}{gr:02x}{b:02x}"),
                    count: 0,
                }
            })
            .collect();
        let mut hull = vec![[0.27, 0.156, 0.182]; desc.groups.len()];
        for v in &desc.vehicles {
            groups[v.group].count += 1;
            let h = v.model.params.body.hull_size;
            hull[v.group] = [h.x, h.y, h.z];
        }
        let meta = Meta {
            version: 1,
            world: desc.name.clone(),
            seed: desc.seed,
            duration_s: 0.0,
            frame_dt: fdt,
            frames: 0,
            panel_dt: pdt,
            vehicles: n,
            pool: [pool.x, pool.y, pool.z],
            obstacles,
            groups,
            group_of: desc.vehicles.iter().map(|v| v.group as u32).collect(),
            names: desc.vehicles.iter().map(|v| v.name.clone()).collect(),
            hull,
            modem_range_m,
            panel: PANEL.iter().map(|s| s.to_string()).collect(),
            modes: Mode::ALL.iter().map(|m| m.name().to_string()).collect(),
            links_kept: 0,
            links_total: 0,
            timeline: Timeline::default(),
            outcomes: Vec::new(),
            ack_label: String::new(),
        };
        Self {
            data: ReplayData {
                meta,
                pos: Vec::new(),
                att: Vec::new(),
                panel: Vec::new(),
                links: Vec::new(),
            },
            frame_every: (fdt / desc.dt).round().max(1.0) as u64,
            panel_every: (pdt / desc.dt).round().max(1.0) as u64,
            panel: n.saturating_mul(PANEL.len() * 4) <= PANEL_BUDGET_BYTES,
            stride: 1,
            seen: 0,
            scratch: Vec::new(),
        }
    }

    /// The replay so far, with its timeline from the medium's per-second counts and the
    /// connectivity samples.
    pub fn finish(mut self, t: f64, medium: &Medium, conn: &Connectivity) -> ReplayData {
        let m = &mut self.data.meta;
        m.duration_s = t;
        m.frames = self.data.pos.len() / (3 * m.vehicles.max(1));
        m.links_kept = self.data.links.len();
        let tl = &mut m.timeline;
        let n = m.vehicles.max(1) as f64;
        for c in &medium.per_second {
            let k = |o: Outcome| c[o.index()];
            tl.attempted.push(c.iter().sum());
            tl.delivered.push(k(Outcome::Delivered));
            tl.collided.push(k(Outcome::Collided));
            tl.occluded.push(k(Outcome::Occluded));
            tl.out_of_budget.push(k(Outcome::OutOfBudget));
            tl.half_duplex.push(k(Outcome::HalfDuplex));
        }
        for s in &conn.samples {
            tl.components.push(s.components as u64);
            tl.largest_fraction.push(s.largest as f64 / n);
            tl.mean_degree.push(2.0 * s.edges as f64 / n);
        }
        // One length for every series: seconds without an attempt count none; a final
        // partial second without a graph sample shows the graph as last sampled.
        let len = tl.attempted.len().max(tl.components.len());
        for v in [
            &mut tl.attempted,
            &mut tl.delivered,
            &mut tl.collided,
            &mut tl.occluded,
            &mut tl.out_of_budget,
            &mut tl.half_duplex,
        ] {
            v.resize(len, 0);
        }
        if let Some(&c) = tl.components.last() {
            tl.components.resize(len, c);
            let (f, d) = (
                tl.largest_fraction[tl.largest_fraction.len() - 1],
                tl.mean_degree[tl.mean_degree.len() - 1],
            );
            tl.largest_fraction.resize(len, f);
            tl.mean_degree.resize(len, d);
        } else {
            // No graph sampled (no active medium, so no attempts either).
            tl.components.resize(len, 0);
            tl.largest_fraction.resize(len, 0.0);
            tl.mean_degree.resize(len, 0.0);
        }
        self.data
    }

    fn keep_links(&mut self) {
        // A canonical order, whatever order the vehicles were visited in.
        self.scratch.sort_by(|a, b| {
            a.t.total_cmp(&b.t)
                .then(a.from.cmp(&b.from))
                .then(a.to.cmp(&b.to))
        });
        for e in self.scratch.drain(..) {
            self.data.meta.links_total += 1;
            self.seen += 1;
            if !self.seen.is_multiple_of(self.stride) {
                continue;
            }
            self.data.links.push(e);
            if self.data.links.len() >= LINK_BUDGET {
                // Thin evenly: keep every other event so far, and from now on every
                // 2·stride-th.
                let mut k = 0;
                self.data.links.retain(|_| {
                    k += 1;
                    k % 2 == 0
                });
                self.stride *= 2;
            }
        }
    }
}

/// The replay's description of obstacle `o` (`run.mcap` draws obstacles from it too).
pub fn obstacle_meta(o: &shoal_world::geometry::Obstacle) -> ObstacleMeta {
    let t = o.pose.translation;
    let r = o.pose.rotation;
    let mut m = ObstacleMeta {
        name: o.name.clone(),
        kind: "box".into(),
        size: None,
        radius: None,
        height: None,
        position: [t.x, t.y, t.z],
        rotation: [r.x, r.y, r.z, r.w],
    };
    if let Some(b) = o.shape.as_cuboid() {
        let h = b.half_extents;
        m.size = Some([2.0 * h.x, 2.0 * h.y, 2.0 * h.z]);
    } else if let Some(b) = o.shape.as_ball() {
        m.kind = "sphere".into();
        m.radius = Some(b.radius);
    } else if let Some(c) = o.shape.as_cylinder() {
        m.kind = "cylinder".into();
        m.radius = Some(c.radius);
        m.height = Some(2.0 * c.half_height);
    } else if let Some(c) = o.shape.as_capsule() {
        m.kind = "capsule".into();
        m.radius = Some(c.radius);
        m.height = Some(c.height());
    } else {
        // Any other shape: its bounding box.
        let (lo, hi) = (o.aabb.mins, o.aabb.maxs);
        m.size = Some([hi.x - lo.x, hi.y - lo.y, hi.z - lo.z]);
        m.position = [
            0.5 * (lo.x + hi.x),
            0.5 * (lo.y + hi.y),
            0.5 * (lo.z + hi.z),
        ];
        m.rotation = [0.0, 0.0, 0.0, 1.0];
    }
    m
}

/// Quantises `x` in `[0, span]` to 0 … 65535.
fn q_pos(x: f64, span: f64) -> u16 {
    ((x / span).clamp(0.0, 1.0) * 65535.0).round() as u16
}

/// Quantises an angle in (−π, π] to −32767 … 32767.
fn q_angle(a: f64) -> i16 {
    (shoal_model::math::wrap_pi(a) / std::f64::consts::PI * 32767.0)
        .round()
        .clamp(-32767.0, 32767.0) as i16
}

/// Samples the replay at the end of a step (after recording and connectivity).
pub fn replay_system(
    clock: Res<Clock>,
    rec: Option<ResMut<ReplayRecorder>>,
    conn: Res<Connectivity>,
    fleet: Res<Fleet>,
    mut ledger: ResMut<Ledger>,
    mut q: Query<(&VehicleId, &mut CommStats)>,
) {
    let Some(mut rec) = rec else {
        return;
    };
    let rec = &mut *rec;
    let next = clock.step + 1;
    let frame = next == 1 || next.is_multiple_of(rec.frame_every);
    // Panel row 0 describes the start, row k the time k · panel_dt.
    let second = rec.panel && (next == 1 || next.is_multiple_of(rec.panel_every));
    if !frame && !second {
        return;
    }
    let n = rec.data.meta.vehicles;
    let pool = rec.data.meta.pool;
    if frame {
        let base = rec.data.pos.len();
        rec.data.pos.resize(base + 3 * n, 0);
        rec.data.att.resize(base + 3 * n, 0);
        for (id, _) in &q {
            let i = base + 3 * id.0 as usize;
            let r = &fleet.get(*id).physics.state.rigid;
            let (roll, pitch, yaw) = r.attitude.euler_angles();
            for (k, span) in pool.iter().enumerate() {
                rec.data.pos[i + k] = q_pos(r.position[k], *span);
            }
            rec.data.att[i..i + 3].copy_from_slice(&[q_angle(roll), q_angle(pitch), q_angle(yaw)]);
        }
        rec.scratch.extend(ledger.drain_heard().map(|h| LinkEvent {
            t: h.t as f32,
            from: h.from,
            to: h.to,
            outcome: h.outcome,
            ack: h.ack,
        }));
        rec.keep_links();
    }
    if second {
        let mut degree = vec![0u32; n];
        for &(a, b) in &conn.last_edges {
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        let w = PANEL.len();
        let base = rec.data.panel.len();
        rec.data.panel.resize(base + w * n, 0.0);
        // The frames received so far: every attempt folded into the statistics.
        ledger.fold_into(n, q.iter_mut().map(|(id, s)| (id.0, s)));
        for (id, stats) in &q {
            let i = base + w * id.0 as usize;
            let v = fleet.get(*id);
            let (s, c) = (&v.sensors, &v.control);
            let row = [
                s.depth,
                c.setpoints.depth,
                c.setpoints.yaw,
                mode_code(c.setpoints.mode),
                stats.sent as f64,
                stats.rx.delivered as f64,
                f64::from(degree[id.0 as usize]),
            ];
            for (k, v) in row.iter().enumerate() {
                rec.data.panel[i + k] = *v as f32;
            }
        }
    }
}
