//! The spatial index of the medium: a dense uniform grid of points, rebuilt every step by a
//! counting sort and queried by boxes.

use shoal_model::math::Vec3;

/// The cell of `p` in a grid of `dims` cells of `cell` \[m\] from `origin`, clamped to the
/// grid: truncation is the floor for the non-negative values that remain (a negative or NaN
/// one is cell 0, as a float cast saturates). Clamping moves no two points further apart, so
/// points within a cell of each other stay in neighbouring cells.
pub(super) fn cell_of(p: &Vec3, origin: &Vec3, cell: f64, dims: [usize; 3]) -> [usize; 3] {
    let c = |v: f64, o: f64, n: usize| (((v - o) / cell).max(0.0) as usize).min(n - 1);
    [
        c(p.x, origin.x, dims[0]),
        c(p.y, origin.y, dims[1]),
        c(p.z, origin.z, dims[2]),
    ]
}

/// The index of cell `c` in a grid of `dims` cells, row-major.
pub(super) fn flat_index(c: [usize; 3], dims: [usize; 3]) -> usize {
    (c[0] * dims[1] + c[1]) * dims[2] + c[2]
}

/// The cells of the transmit phase's per-step lists of things by position (the transmissions
/// on record: `air.rs`; the vehicles counting idle slots down: `countdown.rs`): a uniform
/// grid over the vehicles, its cells at least a given reach wide, so that everything within
/// that reach of a point lies in the point's cell or a neighbouring one.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cells {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
}

impl Cells {
    /// Cells at least `reach` \[m\] wide over the box `lo … hi` \[m\] (at most 2^16 of them:
    /// wider cells for a spread-out swarm, so that a query only looks further). Points outside
    /// the box fall into its border cells: any box gives the same answers, a box around the
    /// points the fewest candidates.
    pub(super) fn over(lo: Vec3, hi: Vec3, reach: f64) -> Self {
        let span = (hi - lo).sup(&Vec3::zeros());
        let mut cell = reach.max(1e-3);
        let dims = loop {
            let d = span.map(|s| (s / cell).floor() as usize + 1);
            if d.x.saturating_mul(d.y).saturating_mul(d.z) <= 1 << 16 {
                break [d.x, d.y, d.z];
            }
            cell *= 2.0;
        };
        Self {
            origin: lo,
            cell,
            dims,
        }
    }

    /// How many cells.
    pub(super) fn count(&self) -> usize {
        self.dims.iter().product()
    }

    /// The index of the cell of `p`, clamped to the grid (a position outside it falls into a
    /// border cell, and a query still finds everything within a cell of it: [`cell_of`]).
    pub(super) fn index(&self, p: &Vec3) -> usize {
        flat_index(cell_of(p, &self.origin, self.cell, self.dims), self.dims)
    }

    /// Calls `f` with the index of the cell of `p` and of each of its neighbours.
    pub(super) fn each_around(&self, p: &Vec3, mut f: impl FnMut(usize)) {
        let c = cell_of(p, &self.origin, self.cell, self.dims);
        let range = |c: usize, n: usize| c.saturating_sub(1)..(c + 2).min(n);
        for i in range(c[0], self.dims[0]) {
            for j in range(c[1], self.dims[1]) {
                for k in range(c[2], self.dims[2]) {
                    f(flat_index([i, j, k], self.dims));
                }
            }
        }
    }
}

/// No item (end of a cell's list).
const NONE: u32 = u32::MAX;

/// Items by cell of [`Cells`], each cell a linked list, items numbered in the order they were
/// added: what the transmit phase keeps by position while it walks a step (the transmissions
/// on record, `air.rs`; the vehicles counting down, `countdown.rs`) — an item added during
/// the walk joins its cell at once.
pub(super) struct CellLists<T> {
    cells: Cells,
    /// First item of each cell.
    head: Vec<u32>,
    /// Next item in the same cell.
    next: Vec<u32>,
    items: Vec<T>,
}

impl<T> CellLists<T> {
    /// No items, on `cells`.
    pub(super) fn new(cells: Cells) -> Self {
        Self {
            cells,
            head: vec![NONE; cells.count()],
            next: Vec::new(),
            items: Vec::new(),
        }
    }

    /// No items, on `cells`, in the storage of `self`.
    pub(super) fn reset(&mut self, cells: Cells) {
        self.cells = cells;
        self.head.clear();
        self.head.resize(cells.count(), NONE);
        self.next.clear();
        self.items.clear();
    }

    /// The cells.
    pub(super) fn cells(&self) -> Cells {
        self.cells
    }

    /// Adds `item` at `p` \[m\]; returns its number.
    pub(super) fn push(&mut self, p: &Vec3, item: T) -> u32 {
        let k = self.cells.index(p);
        let i = self.items.len() as u32;
        self.next.push(self.head[k]);
        self.head[k] = i;
        self.items.push(item);
        i
    }

    /// Item number `i`.
    pub(super) fn get(&self, i: u32) -> &T {
        &self.items[i as usize]
    }

    /// Calls `f` with the number of every item in the cell of `p` and its neighbours (all
    /// within a cell's width of it among them) and the item, in no particular order.
    pub(super) fn each_around(&mut self, p: &Vec3, mut f: impl FnMut(u32, &mut T)) {
        let (head, next, items) = (&self.head, &self.next, &mut self.items);
        self.cells.each_around(p, |c| {
            let mut i = head[c];
            while i != NONE {
                f(i, &mut items[i as usize]);
                i = next[i as usize];
            }
        });
    }

    /// [`CellLists::each_around`], reading.
    pub(super) fn each_near(&self, p: &Vec3, mut f: impl FnMut(&T)) {
        self.cells.each_around(p, |c| {
            let mut i = self.head[c];
            while i != NONE {
                f(&self.items[i as usize]);
                i = self.next[i as usize];
            }
        });
    }
}

/// A dense uniform grid of points (compressed rows: ids sorted by cell), rebuilt every step by
/// a counting sort; box queries index it directly.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    ids: Vec<u32>,
}

impl Grid {
    fn coord(&self, p: &Vec3) -> [usize; 3] {
        cell_of(p, &self.origin, self.cell, self.dims)
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        flat_index(c, self.dims)
    }

    /// Rebuilds the grid over `points` (index = id) with cells of about `cell` \[m\] (larger if
    /// the points spread so far that the grid would exceed a few cells per point).
    pub fn rebuild(&mut self, cell: f64, points: &[Vec3]) {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for p in points {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if points.is_empty() {
            lo = Vec3::zeros();
            hi = Vec3::zeros();
        }
        let mut cell = cell.max(1e-3);
        let budget = 4 * points.len() + 4096;
        let dims = |cell: f64| {
            // b ≥ a: truncation is the floor.
            let n = |a: f64, b: f64| ((b - a) / cell) as usize + 1;
            [n(lo.x, hi.x), n(lo.y, hi.y), n(lo.z, hi.z)]
        };
        while dims(cell).iter().product::<usize>() > budget {
            cell *= 1.5;
        }
        self.origin = lo;
        self.cell = cell;
        self.dims = dims(cell);
        let cells = self.dims.iter().product::<usize>();
        self.start.clear();
        self.start.resize(cells + 1, 0);
        for p in points {
            let k = self.flat(self.coord(p));
            self.start[k + 1] += 1;
        }
        for k in 0..cells {
            self.start[k + 1] += self.start[k];
        }
        self.ids.clear();
        self.ids.resize(points.len(), 0);
        let mut fill = self.start.clone();
        for (i, p) in points.iter().enumerate() {
            let k = self.flat(self.coord(p));
            self.ids[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
    }

    /// The box its points lay in when it was last rebuilt \[m\] (all zero before).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let d = Vec3::new(
            self.dims[0] as f64,
            self.dims[1] as f64,
            self.dims[2] as f64,
        );
        (self.origin, self.origin + d * self.cell)
    }

    /// Calls `f` with every id whose cell overlaps the box `lo … hi` \[m\] (a superset of the
    /// points inside it); stops early when `f` returns `false`. Returns whether it ran to the end.
    pub fn each_in_box(&self, lo: &Vec3, hi: &Vec3, mut f: impl FnMut(u32) -> bool) -> bool {
        if self.dims[0] == 0 {
            return true;
        }
        let (a, b) = (self.coord(lo), self.coord(hi));
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                let row = self.flat([x, y, 0]);
                let (s, e) = (
                    self.start[row + a[2]] as usize,
                    self.start[row + b[2] + 1] as usize,
                );
                for &id in &self.ids[s..e] {
                    if !f(id) {
                        return false;
                    }
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whatever the box the cells are laid over (around the points, inside them, beside
    /// them), two points within the reach of each other lie in neighbouring cells: a query
    /// around one finds the other.
    #[test]
    fn cells_find_every_point_within_reach_whatever_the_box() {
        let pts: Vec<Vec3> = (0..300)
            .map(|i| {
                let f = f64::from(i);
                Vec3::new((f * 0.37) % 9.0, (f * 0.61) % 7.0, (f * 0.13) % 2.0)
            })
            .collect();
        let reach = 1.3;
        let boxes = [
            (Vec3::zeros(), Vec3::new(9.0, 7.0, 2.0)),
            (Vec3::new(3.0, 3.0, 0.5), Vec3::new(4.0, 4.0, 1.0)),
            (Vec3::new(20.0, -5.0, 0.0), Vec3::new(30.0, 0.0, 1.0)),
            (Vec3::zeros(), Vec3::zeros()),
        ];
        for (lo, hi) in boxes {
            let cells = Cells::over(lo, hi, reach);
            for p in &pts {
                let mut around = Vec::new();
                cells.each_around(p, |c| around.push(c));
                for q in &pts {
                    if (p - q).norm() <= reach {
                        assert!(around.contains(&cells.index(q)), "{p} {q} over {lo} … {hi}");
                    }
                }
            }
        }
    }

    /// A box query yields each point of the cells the box overlaps, once: every point inside
    /// the box, the points of those cells outside it (within one cell of the box), and no
    /// other point — checked against brute force for boxes inside, across and beyond the
    /// points, on a grid whose cell was enlarged to fit the budget and one that was not.
    #[test]
    fn dense_grid_box_query_finds_exactly_the_points_inside() {
        use std::collections::BTreeSet;
        let pts: Vec<Vec3> = (0..500)
            .map(|i| {
                let f = i as f64;
                Vec3::new((f * 0.37) % 9.0, (f * 0.61) % 7.0, (f * 0.13) % 2.0)
            })
            .collect();
        let boxes = [
            (Vec3::new(2.0, 1.5, 0.3), Vec3::new(5.5, 4.0, 1.2)),
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.9, 0.9, 0.9)),
            // Beyond the points on every side: clamped to the outer cells.
            (Vec3::new(-3.0, 5.9, -1.0), Vec3::new(1.1, 9.0, 0.5)),
            (Vec3::new(8.2, -2.0, 1.7), Vec3::new(12.0, 0.4, 5.0)),
            // Thinner than a cell.
            (Vec3::new(4.0, 3.0, 1.0), Vec3::new(4.05, 3.05, 1.05)),
        ];
        for cell in [0.8, 0.05] {
            let mut g = Grid::default();
            g.rebuild(cell, &pts);
            assert!(g.cell >= cell);
            for (lo, hi) in &boxes {
                let mut found = Vec::new();
                assert!(g.each_in_box(lo, hi, |id| {
                    found.push(id);
                    true
                }));
                let set: BTreeSet<u32> = found.iter().copied().collect();
                assert_eq!(set.len(), found.len(), "no duplicates");
                // Brute force: the points whose cell lies in the box's range of cells.
                let (a, b) = (g.coord(lo), g.coord(hi));
                let in_cells: BTreeSet<u32> = (0..pts.len() as u32)
                    .filter(|&i| {
                        let c = g.coord(&pts[i as usize]);
                        (0..3).all(|k| a[k] <= c[k] && c[k] <= b[k])
                    })
                    .collect();
                assert_eq!(set, in_cells, "box {lo:?} … {hi:?}, cell {}", g.cell);
                // Independently of the cells: every point inside is found, and nothing more
                // than one cell outside the box on any axis.
                let within = |p: &Vec3, margin: f64| {
                    (0..3).all(|k| p[k] >= lo[k] - margin && p[k] <= hi[k] + margin)
                };
                let inside: BTreeSet<u32> = (0..pts.len() as u32)
                    .filter(|&i| within(&pts[i as usize], 0.0))
                    .collect();
                assert!(
                    inside.is_subset(&set),
                    "missed {:?}",
                    inside.difference(&set)
                );
                let far: Vec<u32> = set
                    .iter()
                    .copied()
                    .filter(|&i| !within(&pts[i as usize], g.cell))
                    .collect();
                assert!(far.is_empty(), "found points far outside the box: {far:?}");
                assert!(
                    set.len() < pts.len(),
                    "box {lo:?} … {hi:?} yields every point"
                );
            }
        }
        // The first box holds points, and points lie outside it.
        let (lo, hi) = boxes[0];
        let n_in = pts
            .iter()
            .filter(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
            .count();
        assert!(n_in > 10 && n_in < 250, "{n_in} points inside");
    }
}
