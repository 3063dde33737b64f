//! Stop requests from outside the process. SIGINT (Ctrl-C), SIGTERM and SIGHUP all ask
//! `shoal run` to stop cleanly: the loops of loading, building, running and plotting look at
//! the shared [`Cancel`] and give up at their next unit of work, the outputs computed so far
//! are finished, and the process exits with the conventional code of the *first* signal,
//! 128 + its number ([`exit_code`]: 130 SIGINT, 143 SIGTERM, 129 SIGHUP). Later signals never
//! kill the process outright; they are counted, and skip the plots not yet drawn.
//!
//! SIGXFSZ is caught and otherwise ignored, so that a file-size limit (`ulimit -f`) makes the
//! write fail with EFBIG — an error that names the file — instead of killing the process
//! with a core dump.
//!
//! A signal that was ignored when `shoal` started stays ignored (SIGTERM excepted), as shells
//! expect: SIGHUP under `nohup`, SIGINT for a background job of a script. Linux reports the
//! inherited dispositions in `/proc/self/status`; elsewhere every signal is caught.
//!
//! The signals are received by a thread of signal-hook's iterator: no code of shoal runs
//! inside a signal handler.
//!
//! For tests of signals that come while the outputs are written, [`output_hold`] lets the
//! environment variable `SHOAL_HOLD_BEFORE_OUTPUT=NAME` hold `shoal run` just before it
//! begins the output file NAME (e.g. `top.png`): it says so on standard error
//! (`shoal: holding before NAME …`) and goes on when the next signal has come (or after
//! [`HOLD_LIMIT`]), so a test can send that signal exactly then.

use shoal_world::cancel::{Cancel, Cause};
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
use signal_hook::iterator::Signals;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The environment variable of [`output_hold`].
pub const HOLD_VAR: &str = "SHOAL_HOLD_BEFORE_OUTPUT";
/// Longest hold of [`output_hold`] (then the outputs go on without a signal).
pub const HOLD_LIMIT: Duration = Duration::from_secs(60);

/// The stop request of a signal (`None` for SIGXFSZ, which only has to be caught).
fn cause(signal: i32) -> Option<Cause> {
    let name = match signal {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => return None,
    };
    Some(Cause { name, code: signal })
}

/// Whether `signal` was ignored when the process started (read from `SigIgn` in
/// `/proc/self/status`, a hexadecimal mask with bit `signal − 1`; false where there is none).
fn ignored_at_start(signal: i32) -> bool {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        return false;
    };
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigIgn:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| signal >= 1 && (mask >> (signal - 1)) & 1 == 1)
}

/// Catches SIGTERM, and SIGINT, SIGHUP and SIGXFSZ unless they were ignored at the start,
/// from now on; returns the stop request they feed.
pub fn install() -> std::io::Result<Arc<Cancel>> {
    let cancel = Arc::new(Cancel::new());
    let caught: Vec<i32> = [SIGINT, SIGTERM, SIGHUP, SIGXFSZ]
        .into_iter()
        .filter(|&s| s == SIGTERM || !ignored_at_start(s))
        .collect();
    let mut signals = Signals::new(caught)?;
    let requests = cancel.clone();
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                if let Some(c) = cause(signal) {
                    // Answered at once, whatever the phase; the stop itself comes at the next
                    // step boundary (or vehicle, while a world is built).
                    if requests.requests() == 0 {
                        eprintln!(
                            "\nshoal: {} — stopping at the next step and writing the outputs \
                             so far (again: skip the plots)",
                            c.name
                        );
                    }
                    requests.request(c);
                }
            }
        })?;
    Ok(cancel)
}

/// What [`output_hold`] gives: a call with each output file's final name.
pub type Hold = dyn Fn(&Path) + Send + Sync;

/// With `SHOAL_HOLD_BEFORE_OUTPUT=NAME` set, a call for each output file (see the module
/// documentation) that holds before the file named NAME until `cancel` has one request
/// more than when the hold began, or [`HOLD_LIMIT`] has passed.
pub fn output_hold(cancel: &Arc<Cancel>) -> Option<Box<Hold>> {
    let name = std::env::var_os(HOLD_VAR)?;
    let cancel = cancel.clone();
    Some(Box::new(move |file: &Path| {
        if file.file_name() != Some(name.as_os_str()) {
            return;
        }
        let before = cancel.requests();
        eprintln!(
            "shoal: holding before {} until a signal comes ({HOLD_VAR})",
            file.display()
        );
        let start = Instant::now();
        while cancel.requests() == before && start.elapsed() < HOLD_LIMIT {
            std::thread::sleep(Duration::from_millis(5));
        }
    }))
}

/// The exit code of a run stopped by `cause`: 128 + the signal number.
pub fn exit_code(cause: Cause) -> ExitCode {
    ExitCode::from(u8::try_from(128 + cause.code).unwrap_or(u8::MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_are_128_plus_the_signal_number() {
        for (signal, code) in [(SIGINT, 130), (SIGTERM, 143), (SIGHUP, 129)] {
            let c = cause(signal).unwrap();
            assert_eq!(exit_code(c), ExitCode::from(code));
        }
        assert_eq!(cause(SIGXFSZ), None);
    }

    #[test]
    fn ignored_signals_are_read_from_the_process_status() {
        // The test harness ignores none of these (Rust only ignores SIGPIPE).
        assert!(!ignored_at_start(SIGTERM));
        assert!(!ignored_at_start(SIGHUP));
        if cfg!(target_os = "linux") {
            assert!(ignored_at_start(signal_hook::consts::SIGPIPE));
        }
    }
}
