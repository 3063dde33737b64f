//! Stopping long work early: a [`Cancel`] is shared between whoever asks for the stop (the
//! `shoal` binary's signal thread) and the long loops of loading, building, running and
//! writing a world, which look at it between units of work (one vehicle placed, one step,
//! one plot) and give up with [`Interrupted`].
//!
//! The libraries never learn *why* they were stopped; the first [`Cause`] is kept for the
//! caller (the binary turns a signal into its exit code), and every request is counted, so
//! work that should go on after a first request (writing the outputs of an interrupted run)
//! can still notice a second one.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

/// Why a stop was asked for (for messages and exit codes; the libraries only pass it on).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cause {
    /// Short name, e.g. `SIGTERM`.
    pub name: &'static str,
    /// Number, e.g. the signal number (15 for `SIGTERM`).
    pub code: i32,
}

/// Work stopped because a stop was asked for through a [`Cancel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("interrupted")]
pub struct Interrupted;

/// A shared request to stop. Cheap to check (one atomic load), safe to share between threads.
#[derive(Debug, Default)]
pub struct Cancel {
    requests: AtomicU32,
    cause: OnceLock<Cause>,
}

impl Cancel {
    /// A request that has not been made (yet).
    pub const fn new() -> Self {
        Self {
            requests: AtomicU32::new(0),
            cause: OnceLock::new(),
        }
    }

    /// Asks for a stop. The first cause is kept; later requests are only counted.
    pub fn request(&self, cause: Cause) {
        // The cause is in place before a checker can see the request.
        let _ = self.cause.set(cause);
        self.requests.fetch_add(1, Ordering::AcqRel);
    }

    /// Whether a stop was asked for.
    pub fn is_requested(&self) -> bool {
        self.requests() > 0
    }

    /// How many times a stop was asked for.
    pub fn requests(&self) -> u32 {
        self.requests.load(Ordering::Acquire)
    }

    /// The first cause, once a stop was asked for.
    pub fn cause(&self) -> Option<Cause> {
        if self.is_requested() {
            self.cause.get().copied()
        } else {
            None
        }
    }

    /// `Err(Interrupted)` once a stop was asked for.
    pub fn check(&self) -> Result<(), Interrupted> {
        if self.is_requested() {
            Err(Interrupted)
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_cause_is_kept_and_every_request_counted() {
        let c = Cancel::new();
        assert_eq!(c.check(), Ok(()));
        assert_eq!(c.cause(), None);
        c.request(Cause {
            name: "SIGTERM",
            code: 15,
        });
        c.request(Cause {
            name: "SIGINT",
            code: 2,
        });
        assert_eq!(c.check(), Err(Interrupted));
        assert_eq!(c.cause().map(|c| c.name), Some("SIGTERM"));
        assert_eq!(c.requests(), 2);
    }
}
