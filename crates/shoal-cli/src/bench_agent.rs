//! What the agent rows of `shoal bench --agents` share, whatever the transport: the agent
//! process (killed if the bench leaves early), the timing loop over a world's end of a
//! transport ([`Exchange`]), a row, and where the checkout and its Python interpreter are.

use shoal_bridge::host::{Flow, Host};
use shoal_sim::prelude::*;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Child;
use std::time::{Duration, Instant};

/// The checkout this binary was built in, or the current directory's, if any: the directory
/// holding `python/shoal/agent`.
pub(crate) fn checkout() -> Option<PathBuf> {
    let starts = [std::env::current_exe().ok(), std::env::current_dir().ok()];
    starts.into_iter().flatten().find_map(|s| {
        s.ancestors()
            .find(|d| d.join("python/shoal/agent/__init__.py").is_file())
            .map(Path::to_path_buf)
    })
}

/// An agent process that is killed if the bench leaves early.
pub(crate) struct AgentProcess(pub(crate) Child);

impl AgentProcess {
    /// Its standard error so far (after it ended).
    pub(crate) fn stderr(&mut self) -> String {
        let mut s = String::new();
        if let Some(e) = self.0.stderr.as_mut() {
            let _ = e.read_to_string(&mut s);
        }
        s.trim().to_string()
    }

    /// Waits up to `limit` for it to end; kills it after that.
    pub(crate) fn wait(&mut self, limit: Duration) -> Option<std::process::ExitStatus> {
        let start = Instant::now();
        while start.elapsed() < limit {
            if let Ok(Some(s)) = self.0.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
        None
    }
}

impl Drop for AgentProcess {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// A world's end of an agent transport, as the agent table times it.
pub(crate) trait Exchange {
    /// The exchange before a physics step.
    fn exchange(&mut self, sim: &mut Sim) -> anyhow::Result<Flow>;
    /// Round-trip statistics so far, cleared.
    fn round_trips(&mut self) -> shoal_sim::agents::RoundTrip;
}

impl Exchange for Host {
    fn exchange(&mut self, sim: &mut Sim) -> anyhow::Result<Flow> {
        Ok(self.before_step(sim)?)
    }
    fn round_trips(&mut self) -> shoal_sim::agents::RoundTrip {
        self.take_round_trips()[0]
    }
}

/// Steps `sim` through the exchange of `host`: 100 steps (20 control ticks, 1 s simulated)
/// of warm-up, round trips cleared, then at least `seconds` \[s\] of wall time and 1 s simulated.
/// Returns the wall and simulated time of the measured part \[s\].
pub(crate) fn time_exchange(
    seconds: f64,
    sim: &mut Sim,
    host: &mut impl Exchange,
) -> anyhow::Result<(f64, f64)> {
    fn step(sim: &mut Sim, host: &mut impl Exchange) -> anyhow::Result<()> {
        match host.exchange(sim)? {
            Flow::Continue => {
                sim.step();
                Ok(())
            }
            Flow::Stop(why) => anyhow::bail!("{why}"),
            Flow::Interrupted => anyhow::bail!("interrupted"),
        }
    }
    for _ in 0..100 {
        step(sim, host)?;
    }
    host.round_trips();
    let start = Instant::now();
    let t0 = sim.time();
    loop {
        for _ in 0..5 {
            step(sim, host)?;
        }
        if start.elapsed().as_secs_f64() >= seconds && sim.time() - t0 >= 1.0 {
            break;
        }
    }
    Ok((start.elapsed().as_secs_f64(), sim.time() - t0))
}

/// One row of the agent table.
pub(crate) struct AgentCell {
    pub(crate) ticks: usize,
    pub(crate) round_trip: shoal_sim::agents::RoundTrip,
    pub(crate) real_time: f64,
}

/// The Python interpreter for agent processes: `explicit`, else the checkout's `.venv` (made
/// by scripts/python-env.sh) if it exists, else `python3`.
pub(crate) fn python(explicit: Option<&Path>, repo: &Path) -> PathBuf {
    if let Some(p) = explicit {
        return p.to_path_buf();
    }
    let venv = repo.join(".venv/bin/python");
    if venv.is_file() {
        venv
    } else {
        PathBuf::from("python3")
    }
}
