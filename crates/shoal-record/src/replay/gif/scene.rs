//! The replay as the GIF draws it: checked, decoded to metres and radians, with the group styles and the extent the views zoom to.

use super::error::RenderError;
use super::palette::{WATER, mix, parse_hex};
use crate::replay::{LinkEvent, ReplayData};
use plotters::prelude::*;
use std::borrow::Cow;
use std::path::Path;

/// Hull length, width, height when the replay has none for a group \[m\].
const DEFAULT_HULL: [f64; 3] = [0.3, 0.15, 0.1];

/// The replay with its arrays checked against its header.
pub(super) struct Scene<'a> {
    pub(super) data: &'a ReplayData,
    pub(super) frames: usize,
    pub(super) vehicles: usize,
    pub(super) pool: [f64; 3],
    /// Time between replay frames \[s\].
    pub(super) dt: f64,
    /// Group of each vehicle.
    pub(super) group_of: Vec<usize>,
    /// Per group: name (with count), colour, trail colour, hull \[m\].
    pub(super) groups: Vec<GroupStyle>,
    /// Link events with a finite time, by time.
    pub(super) links: Cow<'a, [LinkEvent]>,
}

pub(super) struct GroupStyle {
    pub(super) label: String,
    pub(super) color: RGBColor,
    pub(super) trail: RGBColor,
    pub(super) hull: [f64; 3],
}

impl<'a> Scene<'a> {
    pub(super) fn new(data: &'a ReplayData, path: &Path) -> Result<Self, RenderError> {
        let m = &data.meta;
        let bad = |message: String| RenderError::Data {
            path: path.to_path_buf(),
            message,
        };
        if m.frames == 0 || m.vehicles == 0 {
            return Err(RenderError::Empty {
                path: path.to_path_buf(),
                frames: m.frames,
                vehicles: m.vehicles,
            });
        }
        let want = m
            .frames
            .checked_mul(m.vehicles)
            .and_then(|n| n.checked_mul(3))
            .ok_or_else(|| bad(format!("{} frames × {} vehicles", m.frames, m.vehicles)))?;
        for (name, len) in [("pos", data.pos.len()), ("att", data.att.len())] {
            if len != want {
                return Err(bad(format!(
                    "`{name}` holds {len} values, {} frames × {} vehicles × 3 = {want} expected",
                    m.frames, m.vehicles
                )));
            }
        }
        if !m.pool.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(bad(format!(
                "pool size {:?} m: each must be finite and > 0",
                m.pool
            )));
        }
        if !(m.frame_dt.is_finite() && m.frame_dt > 0.0) {
            return Err(bad(format!(
                "frame_dt = {} s: must be finite and > 0",
                m.frame_dt
            )));
        }
        if m.group_of.len() != m.vehicles {
            return Err(bad(format!(
                "`group_of` has {} entries for {} vehicles",
                m.group_of.len(),
                m.vehicles
            )));
        }
        let n_groups = m.groups.len().max(1);
        let group_of: Vec<usize> = m.group_of.iter().map(|&g| g as usize).collect();
        if let Some((v, g)) = group_of.iter().enumerate().find(|(_, g)| **g >= n_groups) {
            return Err(bad(format!(
                "vehicle {v} is in group {g}, but there are {n_groups} groups"
            )));
        }
        let mut count = vec![0usize; n_groups];
        for &g in &group_of {
            count[g] += 1;
        }
        let groups = (0..n_groups)
            .map(|g| {
                let meta = m.groups.get(g);
                let color = meta
                    .and_then(|x| parse_hex(&x.color))
                    .unwrap_or_else(|| shoal_output::plot::color(g));
                let hull = m
                    .hull
                    .get(g)
                    .copied()
                    .filter(|h| h.iter().all(|v| v.is_finite() && *v > 0.0))
                    .unwrap_or(DEFAULT_HULL);
                let name = meta.map_or("vehicles", |x| x.name.as_str());
                GroupStyle {
                    label: format!("{name} ({})", count[g]),
                    color,
                    trail: mix(color, WATER, 0.55),
                    hull,
                }
            })
            .collect();
        let finite = data.links.iter().all(|e| e.t.is_finite());
        let sorted = data.links.windows(2).all(|w| w[0].t <= w[1].t);
        let links = if finite && sorted {
            Cow::Borrowed(data.links.as_slice())
        } else {
            let mut v: Vec<LinkEvent> = data
                .links
                .iter()
                .copied()
                .filter(|e| e.t.is_finite())
                .collect();
            v.sort_by(|a, b| a.t.total_cmp(&b.t));
            Cow::Owned(v)
        };
        Ok(Self {
            data,
            frames: m.frames,
            vehicles: m.vehicles,
            pool: m.pool,
            dt: m.frame_dt,
            group_of,
            groups,
            links,
        })
    }

    /// Time of the last replay frame \[s\] (the first is at 0).
    pub(super) fn last_t(&self) -> f64 {
        (self.frames - 1) as f64 * self.dt
    }

    /// The replay frame nearest to the time `t` \[s\].
    pub(super) fn frame_at(&self, t: f64) -> usize {
        ((t / self.dt).round().max(0.0) as usize).min(self.frames - 1)
    }

    /// Position of vehicle `v` in replay frame `f` (x north, y east, z down) \[m\].
    #[inline]
    pub(super) fn pos(&self, f: usize, v: usize) -> [f64; 3] {
        let i = (f * self.vehicles + v) * 3;
        let q = &self.data.pos[i..i + 3];
        [0, 1, 2].map(|k| f64::from(q[k]) / 65535.0 * self.pool[k])
    }

    /// Roll, pitch, yaw of vehicle `v` in replay frame `f` \[rad\].
    #[inline]
    pub(super) fn att(&self, f: usize, v: usize) -> [f64; 3] {
        let i = (f * self.vehicles + v) * 3;
        let q = &self.data.att[i..i + 3];
        [0, 1, 2].map(|k| f64::from(q[k]) * std::f64::consts::PI / 32767.0)
    }

    /// Smallest and largest position of all vehicles over the whole run, per axis \[m\].
    pub(super) fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [u16::MAX; 3];
        let mut hi = [0u16; 3];
        for p in self.data.pos.chunks_exact(3) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let m = |q: [u16; 3]| [0, 1, 2].map(|k| f64::from(q[k]) / 65535.0 * self.pool[k]);
        (m(lo), m(hi))
    }

    /// The link events with `t0 < t ≤ t1`.
    pub(super) fn links_in(&self, t0: f64, t1: f64) -> &[LinkEvent] {
        let a = self.links.partition_point(|e| f64::from(e.t) <= t0);
        let b = self.links.partition_point(|e| f64::from(e.t) <= t1);
        &self.links[a..b.max(a)]
    }
}
