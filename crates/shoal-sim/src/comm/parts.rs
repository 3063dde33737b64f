//! The transmit phase's walk in independent parts ([`split`]): a vehicle's turn reads what
//! the frames started in the step do within the sensing reach of it, and only vehicles with a
//! turn start frames — so the vehicles with a turn fall into groups, each closed under
//! "within reach of one another, directly or through others of the group", whose walks do not
//! touch one another. Walked apart (on several threads) and merged by time
//! ([`super::started::Started::merge`]), they give exactly what one walk of the whole step
//! gives. The groups are packed into as many parts as there are threads, the largest first
//! into the lightest part.

use super::grid::{CellLists, Cells};
use super::medium::Medium;
use shoal_model::math::Vec3;

/// How far apart two vehicles of `m` may be \[m\] for a frame of one to be sensed by the
/// other, or to wake its count of idle slots: the cut-off range between their farthest
/// modems (with a margin for rounding).
fn interaction_range(m: &Medium) -> f64 {
    (m.r_cut + 2.0 * m.max_modem_offset) * (1.0 + 1e-9) + 1e-9
}

/// The root of `i` in the forest `parent`, halving the path on the way.
fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[parent[i as usize] as usize];
        parent[i as usize] = p;
        i = p;
    }
    i
}

/// The `vehicles` with a turn in the step (their ids in `m`) in at most `parts` parts to be
/// walked apart: the positions in `vehicles` of each part's vehicles, ascending; never an empty
/// part. One part holds them all when `parts` is 1.
pub(super) fn split(m: &Medium, vehicles: &[u32], parts: usize) -> Vec<Vec<usize>> {
    let n = vehicles.len();
    if parts <= 1 || n < 2 {
        return vec![(0..n).collect()];
    }
    let reach = interaction_range(m);
    let (lo, hi) = m.grid.bounds();
    let mut near: CellLists<(u32, Vec3)> = CellLists::new(Cells::over(lo, hi, reach));
    let mut parent: Vec<u32> = (0..n as u32).collect();
    // The positions first, in a loop of their own: their reads overlap.
    let at: Vec<Vec3> = vehicles.iter().map(|&v| m.poses[v as usize].0).collect();
    for (i, &p) in at.iter().enumerate() {
        near.each_near(&p, |&(j, q)| {
            if (p - q).norm_squared() <= reach * reach {
                let (a, b) = (root(&mut parent, i as u32), root(&mut parent, j));
                parent[a.max(b) as usize] = a.min(b);
            }
        });
        near.push(&p, (i as u32, p));
    }
    // Each group's size at its root, then the groups largest first (ties: the one whose
    // root comes first), each into the lightest part so far; the vehicles go to their group's
    // part in order.
    let mut size = vec![0u32; n];
    for i in 0..n {
        let r = root(&mut parent, i as u32);
        parent[i] = r;
        size[r as usize] += 1;
    }
    let mut roots: Vec<u32> = (0..n as u32).filter(|&i| parent[i as usize] == i).collect();
    roots.sort_by_key(|&r| std::cmp::Reverse(size[r as usize]));
    let mut load = vec![0u32; parts.min(roots.len())];
    let mut part_of = size;
    for &r in &roots {
        let lightest = (0..load.len()).min_by_key(|&k| load[k]).unwrap_or(0);
        load[lightest] += part_of[r as usize];
        part_of[r as usize] = lightest as u32;
    }
    let mut packed: Vec<Vec<usize>> = load
        .iter()
        .map(|&l| Vec::with_capacity(l as usize))
        .collect();
    for i in 0..n {
        packed[part_of[parent[i] as usize] as usize].push(i);
    }
    packed
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::math::Quat;
    use shoal_model::presets;
    use shoal_model::vehicle::VehicleModel;
    use std::sync::Arc;

    /// A medium of μAUV² at `xs` along x \[m\], 1 m deep.
    fn medium_at(xs: &[f64]) -> Medium {
        let kind = Arc::new(VehicleModel::new(presets::uauv2(), 1000.0));
        let n = xs.len().max(1);
        let mut m = Medium::in_the_dark(vec![kind; n]);
        for (p, x) in m.poses.iter_mut().zip(xs) {
            *p = (Vec3::new(*x, 0.0, 1.0), Quat::identity());
        }
        m.update_grid();
        m
    }

    /// Every vehicle is in one part, in order; two vehicles within reach of one another —
    /// directly or through a chain of others — share a part.
    fn check(m: &Medium, vehicles: &[u32], parts: &[Vec<usize>]) {
        let mut all: Vec<usize> = parts.iter().flatten().copied().collect();
        all.sort_unstable();
        assert_eq!(all, (0..vehicles.len()).collect::<Vec<_>>());
        let reach = m.r_cut + 2.0 * m.max_modem_offset;
        for p in parts {
            assert!(!p.is_empty() && p.is_sorted());
        }
        let part_of = |i: usize| parts.iter().position(|p| p.contains(&i));
        for i in 0..vehicles.len() {
            for j in 0..vehicles.len() {
                let d = (m.poses[vehicles[i] as usize].0 - m.poses[vehicles[j] as usize].0).norm();
                if d <= reach {
                    assert_eq!(part_of(i), part_of(j), "{i} and {j} are {d} m apart");
                }
            }
        }
    }

    #[test]
    fn vehicles_within_reach_through_a_chain_share_a_part() {
        // A chain along x with links just within reach, and a pair far beyond it: two groups.
        let reach = {
            let m = medium_at(&[0.0]);
            m.r_cut + 2.0 * m.max_modem_offset
        };
        assert!(reach > 1.0, "{reach}");
        let xs = [0.0, 0.99, 1.98, 2.97, 40.0, 40.5];
        let m = medium_at(&xs.map(|x| x * reach));
        let vehicles: Vec<u32> = (0..xs.len() as u32).collect();
        let parts = split(&m, &vehicles, 2);
        check(&m, &vehicles, &parts);
        assert_eq!(parts, [vec![0, 1, 2, 3], vec![4, 5]]);
        // One part: all, whatever the positions.
        assert_eq!(split(&m, &vehicles, 1), [vec![0, 1, 2, 3, 4, 5]]);
        // A gap just beyond reach splits the chain.
        let m = medium_at(&[0.0, 1.001 * reach, 2.002 * reach]);
        assert_eq!(split(&m, &[0, 1, 2], 3), [vec![0], vec![1], vec![2]]);
    }
}
