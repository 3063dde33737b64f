//! The communication graph over time: which vehicles heard each other (a frame delivered
//! either way within a window), sampled every second, with its components, largest component
//! and edges — the connectivity table, plots, summary and replay timeline read it.

use crate::comm::{CommStats, Ledger, Medium};
use crate::components::{Clock, VehicleId};
use crate::parallel::{Loop, Parallel};
use bevy_ecs::prelude::*;

/// One sample of the communication graph.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ConnSample {
    /// Time \[s\].
    pub t: f64,
    /// Vehicles in the largest connected component.
    pub largest: usize,
    /// Connected components (isolated vehicles count as components).
    pub components: usize,
    /// Undirected edges (a frame delivered either way within the window).
    pub edges: usize,
}

/// The communication graph over time: an edge joins two vehicles if a frame was delivered
/// between them (either way) within the last `window` seconds; sampled every `every` seconds.
#[derive(Resource, Clone, Debug)]
pub struct Connectivity {
    /// Sample interval \[s\].
    pub every: f64,
    /// Window \[s\].
    pub window: f64,
    /// Samples.
    pub samples: Vec<ConnSample>,
    /// Edges of the last sample.
    pub last_edges: Vec<(u32, u32)>,
    /// When the last sample has no edge but an earlier one had: the last sample that had
    /// edges (its index in `samples`) and its edges, moved here when the graph emptied (so a
    /// run whose traffic ended early can still show who heard whom; [`Connectivity::last_busy`]).
    pub busy: Option<(usize, Vec<(u32, u32)>)>,
    dt: f64,
}

impl Connectivity {
    /// Samples every second over a 2 s window.
    pub fn new(dt: f64) -> Self {
        Self {
            every: 1.0,
            window: 2.0,
            samples: Vec::new(),
            last_edges: Vec::new(),
            busy: None,
            dt,
        }
    }

    /// The last sample with at least one edge, and its edges: the last sample, or the last
    /// one before the graph emptied; `None` when no frame was ever delivered.
    pub fn last_busy(&self) -> Option<(&ConnSample, &[(u32, u32)])> {
        match (&self.busy, self.samples.last()) {
            (_, Some(last)) if !self.last_edges.is_empty() => Some((last, &self.last_edges)),
            (Some((k, edges)), _) => Some((self.samples.get(*k)?, edges)),
            _ => None,
        }
    }
}

/// Samples the communication graph, folding the reception ledger into the vehicles'
/// statistics first (and between samples when the ledger is full).
pub fn connectivity_system(
    clock: Res<Clock>,
    medium: Res<Medium>,
    par: Res<Parallel>,
    mut conn: ResMut<Connectivity>,
    mut ledger: ResMut<Ledger>,
    mut q: Query<(&VehicleId, &mut CommStats)>,
) {
    if !medium.active() {
        return;
    }
    let n = medium.kinds.len();
    let every = (conn.every / conn.dt).round().max(1.0) as u64;
    let next = clock.step + 1;
    if !next.is_multiple_of(every) {
        if ledger.full(n) {
            ledger.fold_into(n, q.iter_mut().map(|(id, s)| (id.0, s)));
        }
        return;
    }
    let t = next as f64 * clock.dt;
    let window = conn.window;
    let mut items: Vec<_> = q.iter_mut().collect();
    // Each vehicle's statistics and links are its own, so the fold runs per vehicle on the
    // pool; the edges are sorted afterwards, so their order does not depend on the chunks.
    let events = ledger.grouped(n);
    let parts = par.for_each_with(
        Loop::Links,
        &mut items,
        || (Vec::new(), Vec::new()),
        |(edges, scratch), (id, s)| {
            events.apply(id.0, s, scratch);
            for (from, l) in s.links().iter() {
                if t - l.last_delivery <= window {
                    edges.push(((*from).min(id.0), (*from).max(id.0)));
                }
            }
        },
    );
    ledger.done(events);
    let mut edges: Vec<(u32, u32)> = parts.into_iter().flat_map(|(e, _)| e).collect();
    edges.sort_unstable();
    edges.dedup();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for &(a, b) in &edges {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
    let mut size = vec![0usize; n];
    for i in 0..n as u32 {
        let r = find(&mut parent, i);
        size[r as usize] += 1;
    }
    let largest = size.iter().copied().max().unwrap_or(0);
    let components = size.iter().filter(|s| **s > 0).count();
    conn.samples.push(ConnSample {
        t,
        largest,
        components,
        edges: edges.len(),
    });
    if edges.is_empty() {
        if !conn.last_edges.is_empty() {
            // The graph just emptied: keep the last edges it had (moved, not copied).
            let k = conn.samples.len() - 2;
            conn.busy = Some((k, std::mem::take(&mut conn.last_edges)));
        }
    } else {
        conn.busy = None;
    }
    conn.last_edges = edges;
}
