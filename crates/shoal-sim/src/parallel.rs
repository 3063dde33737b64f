//! Data-parallel loops over vehicles on a per-world thread pool.
//!
//! bevy's `par_iter` uses a process-wide pool whose size is fixed at first use; shoal owns one
//! pool per world instead, so a single process can run (and benchmark) worlds on 1 and 2
//! threads. Each vehicle's update depends only on its own data, so results are identical for
//! any thread count.
//!
//! The pool counts the loops it actually split, per kind of loop ([`Dispatches`]): a test
//! comparing 1 and 2 threads reads the count to prove that the parallel path ran at all
//! (small loops stay on the calling thread, [`MIN_PARALLEL`]).

use bevy_ecs::prelude::Resource;
use bevy_tasks::{TaskPool, TaskPoolBuilder};
use serde::Serialize;
use std::cell::{Cell, RefCell};
use std::sync::Mutex;
use std::sync::atomic::{
    AtomicBool, AtomicU64, AtomicUsize, Ordering::Acquire, Ordering::Relaxed, Ordering::Release,
};

/// Below this many vehicles a loop runs on the calling thread only: a vehicle's update takes
/// well under a microsecond, so smaller loops lose more to task hand-off than they gain
/// (measured with `shoal bench`: 100 vehicles ran at 0.77× on 2 threads with a threshold of 32).
pub const MIN_PARALLEL: usize = 256;

/// How long [`Parallel::for_parts_made`]'s threads wait awake for one another \[spins\] (about
/// 0.2 ms, a part taking a few hundred µs; a worker waiting longer for its part yields).
const SPINS: u32 = 20_000;

/// Posts the parts of [`Parallel::for_parts_made`] when dropped, also on a panic, so that no
/// worker waits for them for ever.
struct Post<'a>(&'a AtomicBool);

impl Drop for Post<'_> {
    fn drop(&mut self) {
        self.0.store(true, Release);
    }
}

/// A worker's part in [`Parallel::for_parts_made`], and whether it has been given.
struct Slot<T> {
    part: Mutex<Option<T>>,
    given: AtomicBool,
}

impl<T> Default for Slot<T> {
    fn default() -> Self {
        Self {
            part: Mutex::new(None),
            given: AtomicBool::new(false),
        }
    }
}

impl<T> Slot<T> {
    /// Gives it `part`.
    fn put(&self, part: T) {
        if let Ok(mut s) = self.part.lock() {
            *s = Some(part);
        }
        self.given.store(true, Release);
    }
}

/// Hands the parts [`Parallel::for_parts_made`]'s `make` makes to the workers as they come.
pub struct Handout<'a, T> {
    slots: &'a [Slot<T>],
    /// The next worker to be given a part.
    next: Cell<usize>,
    /// Parts given when every worker had one: the calling thread's.
    extra: RefCell<Vec<T>>,
}

impl<T> Handout<'_, T> {
    /// No workers: every part given is the calling thread's ([`Handout::into_extra`]).
    pub(crate) fn none() -> Self {
        Self {
            slots: &[],
            next: Cell::new(0),
            extra: RefCell::new(Vec::new()),
        }
    }

    /// The parts given when every worker had one.
    pub(crate) fn into_extra(self) -> Vec<T> {
        self.extra.into_inner()
    }

    /// Gives `part` to the next worker without one, which starts on it at once (to the
    /// calling thread when every worker has one).
    pub fn give(&self, part: T) {
        let k = self.next.get();
        match self.slots.get(k) {
            Some(slot) => {
                slot.put(part);
                self.next.set(k + 1);
            }
            None => self.extra.borrow_mut().push(part),
        }
    }
}

/// Working threads of this machine (1 when unknown): the default of a run's `threads`.
pub fn all_cores() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// The loops of a step that run on the pool.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loop {
    /// The behaviours of the vehicles on their control tick (one item per vehicle).
    Behaviour,
    /// The fused vehicle pass: control, actuation, integration, collisions, sensors (one item
    /// per vehicle, visited in groups of [`shoal_model::lanes::LANES`] consecutive vehicles).
    Vehicles,
    /// The medium's reception decisions (one item per vehicle that may hear a frame ending in
    /// the step).
    Delivery,
    /// The per-sender link statistics of every vehicle brought up to date and read for the
    /// communication graph, once per sampled second (one item per vehicle).
    Links,
    /// The transmit phase's walk through a step, in independent parts (one item per vehicle
    /// with a turn in the step).
    Walk,
}

impl Loop {
    const fn index(self) -> usize {
        self as usize
    }
}

/// How many loops of each kind a world split over its pool (each call of
/// [`Parallel::for_each`] that took the parallel path counts once). Always zero on one thread.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Dispatches {
    /// Behaviour loops split.
    pub behaviour: u64,
    /// Vehicle passes split.
    pub vehicles: u64,
    /// Medium delivery loops split.
    pub delivery: u64,
    /// Link-statistics loops of the communication graph split.
    pub links: u64,
    /// Transmit walks split into parts.
    pub walk: u64,
}

impl Dispatches {
    /// All loops split.
    pub fn total(&self) -> u64 {
        self.behaviour + self.vehicles + self.delivery + self.walk
    }
}

/// The thread pool of one world.
#[derive(Resource)]
pub struct Parallel {
    threads: usize,
    pool: Option<TaskPool>,
    /// The smallest loop split over the pool \[vehicles\].
    min_parallel: usize,
    /// Loops split, by [`Loop`].
    dispatches: [AtomicU64; 5],
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
        Self {
            threads,
            pool,
            min_parallel: MIN_PARALLEL,
            dispatches: Default::default(),
        }
    }

    /// Number of working threads.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// The smallest loop split over the pool \[vehicles\]: [`MIN_PARALLEL`] unless changed by
    /// [`Parallel::set_min_parallel`].
    pub fn min_parallel(&self) -> usize {
        self.min_parallel
    }

    /// Splits loops of at least `vehicles` (≥ 1) vehicles over the pool. Results do not
    /// depend on it (nor on the thread count); tests lower it to run the parallel path on
    /// small worlds.
    pub fn set_min_parallel(&mut self, vehicles: usize) {
        self.min_parallel = vehicles.max(1);
    }

    /// The loops split over the pool so far.
    pub fn dispatches(&self) -> Dispatches {
        let [behaviour, vehicles, delivery, links, walk] = [
            Loop::Behaviour,
            Loop::Vehicles,
            Loop::Delivery,
            Loop::Links,
            Loop::Walk,
        ]
        .map(|k| self.dispatches[k.index()].load(Relaxed));
        Dispatches {
            behaviour,
            vehicles,
            delivery,
            links,
            walk,
        }
    }

    /// Into how many parts a loop that can only be split into independent parts is to be split
    /// ([`Parallel::for_parts_made`]), its work counted in vehicle updates (the unit of
    /// [`Parallel::min_parallel`]): one per working thread when the loop weighs at least that
    /// much and the pool has workers, else one.
    pub fn parts(&self, work: usize) -> usize {
        if self.pool.is_some() && work >= self.min_parallel {
            self.threads
        } else {
            1
        }
    }

    /// Calls `f` on each of a loop's independent parts, each on its own thread, the parts made
    /// on the calling thread while the workers wake: every working thread first gets ready
    /// (`ready(k)`, k = 0 for the calling thread, 1, 2, … for the workers), the calling thread
    /// makes the parts (`make`, at most one per working thread) — handing a worker its part as
    /// soon as it is made ([`Handout::give`], to the workers in order), or returning the parts
    /// at the end, its own first — and each thread calls `f` with its part (`None` if there
    /// are fewer parts than threads) and what it got ready. Returns what `f` returns, the
    /// calling thread's first (and any parts beyond one per thread, which it takes too, next),
    /// then the workers' in order. Counted as a split loop of `kind`; on one thread, the parts
    /// returned, then those given, each with `ready(0)`.
    pub fn for_parts_made<T: Send, P: Send, R: Send + 'static>(
        &self,
        kind: Loop,
        make: impl FnOnce(&Handout<'_, T>) -> Vec<T>,
        ready: impl Fn(usize) -> P + Sync,
        f: impl Fn(Option<T>, P) -> R + Sync,
    ) -> Vec<R> {
        let Some(pool) = &self.pool else {
            let handout = Handout::none();
            let mut parts = make(&handout);
            parts.extend(handout.into_extra());
            return parts.into_iter().map(|t| f(Some(t), ready(0))).collect();
        };
        self.dispatches[kind.index()].fetch_add(1, Relaxed);
        let workers = self.threads - 1;
        let slots: Vec<Slot<T>> = (0..workers).map(|_| Slot::default()).collect();
        let (posted, done) = (&AtomicBool::new(false), &AtomicUsize::new(0));
        let (f, ready, slots) = (&f, &ready, &slots);
        let mut here = Vec::new();
        let others = pool.scope(|s| {
            for (k, slot) in slots.iter().enumerate() {
                s.spawn(async move {
                    let p = ready(k + 1);
                    // The parts come about now: wait awake, then yield.
                    let mut spins = 0u32;
                    while !slot.given.load(Acquire) && !posted.load(Acquire) {
                        if spins < SPINS {
                            std::hint::spin_loop();
                            spins += 1;
                        } else {
                            std::thread::yield_now();
                        }
                    }
                    let part = slot.part.lock().ok().and_then(|mut s| s.take());
                    let r = f(part, p);
                    done.fetch_add(1, Release);
                    r
                });
            }
            // Should `make` or `f` panic here, the workers stop waiting for their parts.
            let _post = Post(posted);
            let handout = Handout {
                slots,
                next: Cell::new(0),
                extra: RefCell::new(Vec::new()),
            };
            let mut parts = make(&handout);
            let open = &slots[handout.next.get()..];
            let mine = parts
                .len()
                .saturating_sub(open.len())
                .max(1)
                .min(parts.len());
            let theirs = parts.split_off(mine);
            for (slot, part) in open.iter().zip(theirs) {
                slot.put(part);
            }
            posted.store(true, Release);
            parts.extend(handout.into_extra());
            let mut mine = parts.into_iter();
            here.push(f(mine.next(), ready(0)));
            here.extend(mine.map(|t| f(Some(t), ready(0))));
            let mut spins = 0u32;
            while done.load(Acquire) < workers && spins < SPINS {
                std::hint::spin_loop();
                spins += 1;
            }
        });
        here.into_iter().chain(others).collect()
    }

    /// Calls `f` on every item of the loop `kind`, in parallel chunks when the loop has at
    /// least [`Parallel::min_parallel`] vehicles and the pool has workers.
    pub fn for_each<T: Send>(&self, kind: Loop, items: &mut [T], f: impl Fn(&mut T) + Sync) {
        self.for_each_with(kind, items, || (), |(), item| f(item));
    }

    /// The pool when a loop of `kind` over `vehicles` items is to be split over it (and then
    /// counts the dispatch), `None` when the loop stays on the calling thread.
    fn pool_for(&self, kind: Loop, vehicles: usize) -> Option<&TaskPool> {
        let pool = self
            .pool
            .as_ref()
            .filter(|_| vehicles >= self.min_parallel)?;
        self.dispatches[kind.index()].fetch_add(1, Relaxed);
        Some(pool)
    }

    /// Calls `f` on every group of `group` (≥ 1) consecutive items of the loop `kind` (the
    /// last group may be shorter), in parallel runs of whole groups when the loop has at least
    /// [`Parallel::min_parallel`] items and the pool has workers. The groups are the same on
    /// any number of threads.
    pub fn for_each_group<T: Send>(
        &self,
        kind: Loop,
        items: &mut [T],
        group: usize,
        f: impl Fn(&mut [T]) + Sync,
    ) {
        self.for_each_group_with(kind, items, &mut [] as &mut [()], group, |g, _| f(g));
    }

    /// [`Parallel::for_each_group`] over `items` and, beside them, `side` (the same length, or
    /// empty): `f` gets a group of items and the matching group of `side` (empty when `side`
    /// is), so that a loop can also fill another array in place.
    pub fn for_each_group_with<T: Send, U: Send>(
        &self,
        kind: Loop,
        items: &mut [T],
        side: &mut [U],
        group: usize,
        f: impl Fn(&mut [T], &mut [U]) + Sync,
    ) {
        assert!(
            side.is_empty() || side.len() == items.len(),
            "side array of {} for {} items",
            side.len(),
            items.len()
        );
        let group = group.max(1);
        let f = &f;
        let body = move |items: &mut [T], side: &mut [U]| {
            for (k, g) in items.chunks_mut(group).enumerate() {
                let s = if side.is_empty() {
                    &mut []
                } else {
                    &mut side[k * group..k * group + g.len()]
                };
                f(g, s);
            }
        };
        match self.pool_for(kind, items.len()) {
            Some(pool) => {
                let run = items
                    .len()
                    .div_ceil(self.threads * 4)
                    .next_multiple_of(group);
                pool.scope(|s| {
                    let mut rest = side;
                    for c in items.chunks_mut(run) {
                        let n = c.len().min(rest.len());
                        let (mine, tail) = std::mem::take(&mut rest).split_at_mut(n);
                        rest = tail;
                        s.spawn(async move { body(c, mine) });
                    }
                });
            }
            None => body(items, side),
        }
    }

    /// [`Parallel::for_each`] with a state per chunk of items, for tallies that would
    /// otherwise be shared between threads: `init` makes a chunk's state, `f` visits each item
    /// of the chunk with it, and the states come back in chunk order (one state when the loop
    /// ran on the calling thread). How the items are chunked depends on the thread count, so
    /// the caller's merge must not depend on it (sums of counts, for instance).
    pub fn for_each_with<T: Send, S: Send + 'static>(
        &self,
        kind: Loop,
        items: &mut [T],
        init: impl Fn() -> S + Sync,
        f: impl Fn(&mut S, &mut T) + Sync,
    ) -> Vec<S> {
        match self.pool_for(kind, items.len()) {
            Some(pool) => {
                let chunk = items.len().div_ceil(self.threads * 4);
                let (f, init) = (&f, &init);
                pool.scope(|s| {
                    for c in items.chunks_mut(chunk) {
                        s.spawn(async move {
                            let mut state = init();
                            c.iter_mut().for_each(|item| f(&mut state, item));
                            state
                        });
                    }
                })
            }
            _ => {
                let mut state = init();
                items.iter_mut().for_each(|item| f(&mut state, item));
                vec![state]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_model::lanes::LANES;

    /// Each part goes to one thread with what that thread got ready — the first to the
    /// calling thread (ready 0), the next to the worker (ready 1) — and comes back in that
    /// order; a worker without a part gets `None`; parts beyond one a thread go to the calling
    /// thread. On one thread every part is done in order, nothing is counted as split.
    #[test]
    fn parts_made_go_one_to_a_thread_with_what_it_got_ready() {
        let run = |p: &Parallel, parts: Vec<u32>| {
            p.for_parts_made(Loop::Walk, |_| parts, |k| k, |part, k| (part, k))
        };
        let two = Parallel::new(2);
        assert_eq!(run(&two, vec![10, 20]), [(Some(10), 0), (Some(20), 1)]);
        assert_eq!(run(&two, vec![10]), [(Some(10), 0), (None, 1)]);
        assert_eq!(
            run(&two, vec![10, 20, 30]),
            [(Some(10), 0), (Some(20), 0), (Some(30), 1)]
        );
        assert_eq!(two.dispatches().walk, 3);
        let one = Parallel::new(1);
        assert_eq!(run(&one, vec![10, 20]), [(Some(10), 0), (Some(20), 0)]);
        assert_eq!(one.dispatches().walk, 0);
        // Parts given while the rest are made go to the workers in order, those beyond one a
        // worker to the calling thread after its own; on one thread all to it.
        let given = |p: &Parallel, early: Vec<u32>| {
            let make = |h: &Handout<'_, u32>| {
                early.into_iter().for_each(|t| h.give(t));
                vec![10]
            };
            p.for_parts_made(Loop::Walk, make, |k| k, |part, k| (part, k))
        };
        assert_eq!(given(&two, vec![20]), [(Some(10), 0), (Some(20), 1)]);
        assert_eq!(
            given(&two, vec![20, 30]),
            [(Some(10), 0), (Some(30), 0), (Some(20), 1)]
        );
        assert_eq!(given(&one, vec![20]), [(Some(10), 0), (Some(20), 0)]);
    }

    #[test]
    fn visits_every_item_once() {
        for threads in [1, 2, 3] {
            let p = Parallel::new(threads);
            let mut v: Vec<u64> = (0..1000).collect();
            p.for_each(Loop::Delivery, &mut v, |x| *x = *x * 2 + 1);
            assert!(v.iter().enumerate().all(|(i, x)| *x == 2 * i as u64 + 1));
            let split = u64::from(threads > 1);
            assert_eq!(
                p.dispatches(),
                Dispatches {
                    delivery: split,
                    ..Dispatches::default()
                }
            );
        }
    }

    #[test]
    fn states_per_chunk_see_every_item_once_and_sum_alike_on_any_thread_count() {
        for threads in [1, 2, 3] {
            let p = Parallel::new(threads);
            let mut v: Vec<u64> = (0..1000).collect();
            let states = p.for_each_with(
                Loop::Delivery,
                &mut v,
                || (0u64, 0u64),
                |(n, sum), x| {
                    *n += 1;
                    *sum += *x;
                    *x += 1;
                },
            );
            assert_eq!(states.len() > 1, threads > 1);
            let n: u64 = states.iter().map(|s| s.0).sum();
            let sum: u64 = states.iter().map(|s| s.1).sum();
            assert_eq!((n, sum), (1000, 999 * 1000 / 2));
            assert!(v.iter().enumerate().all(|(i, x)| *x == i as u64 + 1));
        }
    }

    #[test]
    fn groups_are_whole_and_the_same_on_any_thread_count() {
        for threads in [1, 2, 3] {
            let mut p = Parallel::new(threads);
            p.set_min_parallel(1);
            let mut v: Vec<(usize, usize)> = (0..1003).map(|i| (i, 0)).collect();
            p.for_each_group(Loop::Vehicles, &mut v, LANES, |g| {
                assert!(g.len() == LANES || g[0].0 == 1003 / LANES * LANES);
                assert_eq!(g[0].0 % LANES, 0);
                let first = g[0].0;
                g.iter_mut().for_each(|x| x.1 = first + 1);
            });
            assert!(v.iter().all(|&(i, g)| g == i / LANES * LANES + 1));
            assert_eq!(p.dispatches().vehicles, u64::from(threads > 1));
        }
    }

    #[test]
    fn side_groups_match_item_groups_on_any_thread_count() {
        for threads in [1, 2, 3] {
            let mut p = Parallel::new(threads);
            p.set_min_parallel(1);
            let mut items: Vec<usize> = (0..1003).collect();
            let mut side = vec![0usize; 1003];
            p.for_each_group_with(Loop::Vehicles, &mut items, &mut side, LANES, |g, s| {
                assert_eq!(g.len(), s.len());
                g.iter().zip(s.iter_mut()).for_each(|(i, x)| *x = *i + 1);
            });
            assert!(side.iter().enumerate().all(|(i, x)| *x == i + 1));
        }
    }

    #[test]
    fn splits_loops_of_at_least_min_parallel_vehicles() {
        let mut p = Parallel::new(2);
        let mut enough = vec![0u8; MIN_PARALLEL];
        let mut vehicles = vec![0u8; MIN_PARALLEL - 1];
        // One vehicle short stays serial.
        p.for_each_group(Loop::Vehicles, &mut enough, LANES, |g| {
            g.iter_mut().for_each(|x| *x += 1);
        });
        p.for_each(Loop::Behaviour, &mut vehicles, |x| *x += 1);
        assert_eq!(
            p.dispatches(),
            Dispatches {
                vehicles: 1,
                ..Dispatches::default()
            }
        );
        p.set_min_parallel(1);
        p.for_each(Loop::Behaviour, &mut vehicles[..1], |x| *x += 1);
        assert_eq!(p.dispatches().behaviour, 1);
        assert_eq!(p.dispatches().total(), 2);
        assert!(enough.iter().all(|x| *x == 1) && vehicles[0] == 2 && vehicles[1] == 1);
    }
}
