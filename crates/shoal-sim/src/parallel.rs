//! Data-parallel loops over vehicles on a per-world thread pool.
//!
//! bevy's `par_iter` uses a process-wide pool whose size is fixed at first use; shoal owns one
//! pool per world instead, so a single process can run (and benchmark) worlds on 1 and 2
//! threads. Each vehicle's update depends only on its own data, so results are identical for
//! any thread count.

use bevy_ecs::prelude::Resource;
use bevy_tasks::{TaskPool, TaskPoolBuilder};

/// Below this many items a loop runs on the calling thread only: a vehicle's update takes
/// well under a microsecond, so smaller loops lose more to task hand-off than they gain
/// (measured with `shoal bench`: 100 vehicles ran at 0.77× on 2 threads with a threshold of 32).
pub const MIN_PARALLEL: usize = 256;

/// The thread pool of one world.
#[derive(Resource)]
pub struct Parallel {
    threads: usize,
    pool: Option<TaskPool>,
}

impl Parallel {
    /// A pool giving `threads` (≥ 1) working threads: the calling thread plus `threads − 1`
    /// workers.
    pub fn new(threads: usize) -> Self {
        let threads = threads.max(1);
        let pool = (threads > 1).then(|| {
            TaskPoolBuilder::new()
                .num_threads(threads - 1)
                .thread_name("shoal-worker".into())
                .build()
        });
        Self { threads, pool }
    }

    /// Number of working threads.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Calls `f` on every item, in parallel chunks when worthwhile.
    pub fn for_each<T: Send>(&self, items: &mut [T], f: impl Fn(&mut T) + Sync) {
        match &self.pool {
            Some(pool) if items.len() >= MIN_PARALLEL => {
                let chunk = items.len().div_ceil(self.threads * 4);
                let f = &f;
                pool.scope(|s| {
                    for c in items.chunks_mut(chunk) {
                        s.spawn(async move { c.iter_mut().for_each(f) });
                    }
                });
            }
            _ => items.iter_mut().for_each(f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn visits_every_item_once() {
        for threads in [1, 2, 3] {
            let p = Parallel::new(threads);
            let mut v: Vec<u64> = (0..1000).collect();
            p.for_each(&mut v, |x| *x = *x * 2 + 1);
            assert!(v.iter().enumerate().all(|(i, x)| *x == 2 * i as u64 + 1));
        }
    }
}
