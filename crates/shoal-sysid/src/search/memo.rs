//! Replays already made in one search, by model.
//!
//! A fit replays the log for every parameter vector it tries, and some vectors come back: the
//! point where one Levenberg–Marquardt pass stops is where the next pass (with new weights)
//! starts and takes its Jacobian, and a fit is evaluated in full where its minimisation
//! ended. A replay depends only on the model — not on the residual weights, nor on a
//! stability resample — so the search keeps its latest replays here and takes them again
//! instead of simulating twice. The numbers are the same either way: a search's result does
//! not depend on what the memo held, only its time does.

use crate::evaluate::dataset::{Part, Replayed};
use shoal_model::effects::Effect;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

/// The replays a search keeps, most recently used last, within a memory budget.
pub(super) struct Memo {
    entries: Mutex<Entries>,
    /// Most bytes of replayed series kept.
    budget: usize,
}

#[derive(Default)]
struct Entries {
    list: VecDeque<(Key, Arc<Replayed>)>,
    bytes: usize,
}

/// A model of the search: its effects (family and form) and their parameter values, bit for
/// bit.
#[derive(Clone, PartialEq)]
struct Key {
    effects: Vec<(String, String)>,
    values: Vec<u64>,
}

/// Whether a kept replay of `have` serves a request for `want` (a whole replay holds the
/// estimation samples too).
fn serves(have: Part, want: Part) -> bool {
    have == want || have == Part::All
}

impl Memo {
    /// Default budget \[bytes\]: about a hundred replays of a two-minute, 50 Hz log with four
    /// channels; a long log keeps fewer.
    pub const BUDGET: usize = 64 << 20;

    /// An empty memo keeping at most `budget` bytes of replays (at least the latest one).
    pub fn new(budget: usize) -> Self {
        Self {
            entries: Mutex::new(Entries::default()),
            budget,
        }
    }

    /// The replay of the model with `effects` at `values` for the samples of `part`: a kept
    /// one that holds them, or `replay()`'s (then kept).
    pub fn get_or_replay(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[f64],
        part: Part,
        replay: impl FnOnce() -> Replayed,
    ) -> Arc<Replayed> {
        let mut one = self.get_or_replay_many(effects, &[values], part, |_| vec![replay()]);
        one.pop().expect("a replay per model")
    }

    /// [`Memo::get_or_replay`] for the models with `effects` at each of `values`: the kept
    /// replays, and those of the others from one call of `replay` with their values (each
    /// once, in the order of `values`; then kept).
    pub fn get_or_replay_many(
        &self,
        effects: &[Arc<dyn Effect>],
        values: &[&[f64]],
        part: Part,
        replay: impl FnOnce(&[&[f64]]) -> Vec<Replayed>,
    ) -> Vec<Arc<Replayed>> {
        let names: Vec<(String, String)> = effects
            .iter()
            .map(|e| (e.name().to_string(), e.form().to_string()))
            .collect();
        let keys: Vec<Key> = values
            .iter()
            .map(|v| Key {
                effects: names.clone(),
                values: v.iter().map(|x| x.to_bits()).collect(),
            })
            .collect();
        let mut found: Vec<Option<Arc<Replayed>>> = {
            let mut e = self.lock();
            keys.iter()
                .map(|key| {
                    let i = e
                        .list
                        .iter()
                        .rposition(|(k, r)| k == key && serves(r.part(), part))?;
                    let hit = e.list.remove(i).expect("index from rposition");
                    let r = hit.1.clone();
                    e.list.push_back(hit);
                    Some(r)
                })
                .collect()
        };
        // The models not kept, each once (a request may name one model twice).
        let mut missing: Vec<usize> = Vec::new();
        for (i, f) in found.iter().enumerate() {
            if f.is_none() && !missing.iter().any(|&m| keys[m] == keys[i]) {
                missing.push(i);
            }
        }
        if !missing.is_empty() {
            // Replayed outside the lock: the other threads go on meanwhile.
            let made = replay(&missing.iter().map(|&i| values[i]).collect::<Vec<_>>());
            assert_eq!(made.len(), missing.len(), "a replay per model");
            let mut e = self.lock();
            for (&m, r) in missing.iter().zip(made) {
                let r = Arc::new(r);
                for (f, key) in found.iter_mut().zip(&keys) {
                    if f.is_none() && *key == keys[m] {
                        *f = Some(r.clone());
                    }
                }
                e.bytes += r.bytes();
                e.list.push_back((keys[m].clone(), r));
            }
            while e.bytes > self.budget && e.list.len() > 1 {
                if let Some((_, old)) = e.list.pop_front() {
                    e.bytes -= old.bytes();
                }
            }
        }
        found
            .into_iter()
            .map(|f| f.expect("kept or replayed"))
            .collect()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Entries> {
        // A panic elsewhere cannot leave the list half-changed (every change is one push or
        // pop), so a poisoned lock is still usable.
        self.entries.lock().unwrap_or_else(|p| p.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn replayed(n: usize) -> Replayed {
        Replayed::from_series(vec![vec![(vec![0.0; n], vec![1.0; n])]], Part::All)
    }

    #[test]
    fn a_model_is_replayed_once_while_it_is_kept() {
        let lag = shoal_model::effects::by_name("thruster_lag").unwrap();
        let fx = [lag];
        let memo = Memo::new(1 << 20);
        let mut calls = 0;
        for _ in 0..3 {
            memo.get_or_replay(&fx, &[0.4], Part::All, || {
                calls += 1;
                replayed(10)
            });
        }
        assert_eq!(calls, 1);
        // Another value (even −0.0 against 0.0) is another model.
        for v in [0.0, -0.0, 0.41] {
            memo.get_or_replay(&fx, &[v], Part::All, || {
                calls += 1;
                replayed(10)
            });
        }
        assert_eq!(calls, 4);
        // A whole replay serves a request for the estimation samples; not the other way.
        memo.get_or_replay(&fx, &[0.4], Part::Estimation, || unreachable!("kept"));
        let partial =
            |n| Replayed::from_series(vec![vec![(vec![0.0; n], vec![1.0; n])]], Part::Estimation);
        memo.get_or_replay(&fx, &[0.5], Part::Estimation, || {
            calls += 1;
            partial(5)
        });
        let whole = memo.get_or_replay(&fx, &[0.5], Part::All, || {
            calls += 1;
            replayed(10)
        });
        assert_eq!((calls, whole.part()), (6, Part::All));
    }

    #[test]
    fn a_batch_replays_the_models_not_kept_together_each_once() {
        let fx = [shoal_model::effects::by_name("thruster_lag").unwrap()];
        let memo = Memo::new(1 << 20);
        memo.get_or_replay(&fx, &[0.4], Part::All, || replayed(10));
        let mut asked: Vec<Vec<f64>> = Vec::new();
        let got =
            memo.get_or_replay_many(&fx, &[&[0.1], &[0.4], &[0.2], &[0.1]], Part::All, |vs| {
                asked = vs.iter().map(|v| v.to_vec()).collect();
                vs.iter()
                    .map(|v| replayed((v[0] * 1000.0) as usize))
                    .collect()
            });
        assert_eq!(asked, [[0.1], [0.2]]);
        let bytes: Vec<usize> = got.iter().map(|r| r.bytes()).collect();
        assert_eq!(bytes, [1600, 160, 3200, 1600]);
        assert!(Arc::ptr_eq(&got[0], &got[3]));
        // All kept now.
        let again =
            memo.get_or_replay_many(&fx, &[&[0.2], &[0.1]], Part::All, |_| unreachable!("kept"));
        assert!(Arc::ptr_eq(&again[0], &got[2]) && Arc::ptr_eq(&again[1], &got[0]));
    }

    #[test]
    fn the_budget_drops_the_least_recently_used() {
        let fx = [shoal_model::effects::by_name("thruster_lag").unwrap()];
        // Each replay takes 2 × 8 × 1000 bytes: the budget holds two.
        let memo = Memo::new(40_000);
        let calls = std::cell::Cell::new(0);
        let get = |v: f64| {
            memo.get_or_replay(&fx, &[v], Part::All, || {
                calls.set(calls.get() + 1);
                replayed(1000)
            });
        };
        get(1.0);
        get(2.0);
        get(1.0); // 1.0 used last: 2.0 goes when 3.0 comes
        get(3.0);
        get(1.0);
        get(2.0);
        assert_eq!(calls.get(), 4);
    }
}
