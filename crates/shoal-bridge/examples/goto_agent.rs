//! A minimal agent: drives every vehicle it is given to one depth and heading in auto mode.
//! With `--bad` it also sends, on every tick, commands the world must reject (NaN, unknown
//! mode, unknown vehicle, wrong protocol version, oversized frames); with `--slow MS` it
//! sleeps that long per tick (a heavy computation); with `--stall TICK:SECONDS` it stops
//! answering at its TICK-th tick (counted from 0) until the world's clock has advanced SECONDS
//! (a hang it recovers from, as long in simulated time however fast the world runs; it keeps
//! reading the observations, only to see the time); with `--log` it prints what
//! its first vehicle observes once per simulated second on stderr
//! (`goto_agent: t = 12.00 s, depth 1.234 m, yaw 45.0°`, then ` (fallback)` while the world
//! holds the vehicle under its fallback), so that a test can follow the run.
//!
//! ```sh
//! cargo run --release -p shoal-bridge --example goto_agent -- PREFIX AGENT DEPTH_M HEADING_DEG [--bad] [--slow MS] [--stall TICK:SECONDS] [--log]
//! ```

use shoal_bridge::agent::{Agent, AgentLink, Ended};
use shoal_bridge::protocol::{Command, MAX_TX_FRAMES, Observation, flags, mode};
use std::process::ExitCode;
use std::time::Duration;

struct Goto {
    depth: f64,
    yaw: f64,
    slow: Duration,
    /// (tick, simulated seconds) of the one-off stall.
    stall: Option<(u64, f64)>,
    /// While stalled: the simulated time (s) at which it answers again.
    silent_until: Option<f64>,
    /// Current tick (counted over the slices seen, answered or not), and the step it belongs to.
    tick: u64,
    step: Option<u64>,
    /// `--log`: the first vehicle's id and the last simulated second logged.
    log: Option<(Option<u32>, Option<u64>)>,
}

impl Agent for Goto {
    fn tick(&mut self, o: &Observation, cmd: &mut Command) {
        if let Some((first, second)) = &mut self.log
            && *first.get_or_insert(o.vehicle) == o.vehicle
            && *second != Some(o.time as u64)
        {
            *second = Some(o.time as u64);
            eprintln!(
                "goto_agent: t = {:.2} s, depth {:.3} m, yaw {:.1}°{}",
                o.time,
                o.depth,
                o.yaw.to_degrees(),
                if o.flags & flags::FALLBACK != 0 {
                    " (fallback)"
                } else {
                    ""
                }
            );
        }
        cmd.set_mode(mode::AUTO, self.depth, self.yaw, 0.0, 0.0);
        if !self.slow.is_zero() {
            std::thread::sleep(self.slow);
        }
    }
}

impl Goto {
    /// Whether it answers the slice whose first observation is `o` (false while stalled);
    /// counts the ticks.
    fn answers(&mut self, o: &Observation) -> bool {
        if self.step.is_some_and(|s| s != o.step) {
            self.tick += 1;
        }
        self.step = Some(o.step);
        if let Some((at, seconds)) = self.stall
            && at == self.tick
        {
            self.stall = None;
            self.silent_until = Some(o.time + seconds);
        }
        match self.silent_until {
            Some(t) if o.time < t - 1e-9 => false,
            _ => {
                self.silent_until = None;
                true
            }
        }
    }
}

/// Commands a buggy or hostile agent might send alongside `good`.
fn garbage(good: &Command) -> Vec<Command> {
    let mut nan = *good;
    nan.depth = f64::NAN;
    let mut inf = *good;
    inf.yaw = f64::INFINITY;
    let mut bad_mode = *good;
    bad_mode.mode = 42;
    let mut stranger = *good;
    stranger.vehicle = 999_999;
    let mut old = *good;
    old.version = 7;
    let mut bad_kind = *good;
    bad_kind.kind = 9;
    let mut frames = Command::keep(&Observation::EMPTY);
    frames.vehicle = good.vehicle;
    frames.step = good.step;
    frames.n_frames = (MAX_TX_FRAMES + 5) as u32; // claims more frames than fit
    frames.frames[0].len = 200; // longer than the frame buffer
    frames.frames[1].len = 60; // longer than the μAUV² modem's 58-byte payload
    frames.frames[1].modem = 0;
    frames.frames[2].len = 4;
    frames.frames[2].modem = 17; // no such modem
    vec![nan, inf, bad_mode, stranger, old, bad_kind, frames]
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bad = args.iter().any(|a| a == "--bad");
    let log = args.iter().any(|a| a == "--log");
    let slow_ms = args
        .iter()
        .position(|a| a == "--slow")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(0);
    let stall = args
        .iter()
        .position(|a| a == "--stall")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.split_once(':'))
        .and_then(|(t, s)| Some((t.parse::<u64>().ok()?, s.parse::<f64>().ok()?)));
    let pos: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| {
            !a.starts_with("--")
                && (*i == 0 || !matches!(args[i - 1].as_str(), "--slow" | "--stall"))
        })
        .map(|(_, a)| a)
        .collect();
    let (Some(prefix), Some(name), Some(depth), Some(heading)) = (
        pos.first(),
        pos.get(1),
        pos.get(2).and_then(|s| s.parse::<f64>().ok()),
        pos.get(3).and_then(|s| s.parse::<f64>().ok()),
    ) else {
        eprintln!(
            "usage: goto_agent PREFIX AGENT DEPTH_M HEADING_DEG [--bad] [--slow MS] [--stall TICK:SECONDS] [--log]"
        );
        return ExitCode::from(2);
    };
    let mut link = match AgentLink::attach(prefix, name, Duration::from_secs(60)) {
        Ok(l) => l,
        Err(shoal_bridge::BridgeError::Interrupted) => return ExitCode::from(130),
        Err(e) => {
            eprintln!("goto_agent: {e}");
            return ExitCode::from(1);
        }
    };
    eprintln!("goto_agent: attached to `{prefix}` as `{name}`");
    let mut agent = Goto {
        depth,
        yaw: heading.to_radians(),
        slow: Duration::from_millis(slow_ms),
        stall,
        silent_until: None,
        tick: 0,
        step: None,
        log: log.then_some((None, None)),
    };
    // `AgentLink::run`'s loop, with garbage before each good command (`--bad`) and silence
    // while stalled.
    let result = loop {
        let obs = match link.receive(Duration::from_secs(10)) {
            Ok(Some(o)) => o,
            Ok(None) => break Ok(Ended::Silent),
            Err(e) => break Err(e),
        };
        if obs.iter().any(|o| o.flags & flags::END != 0) {
            break Ok(Ended::WorldEnded);
        }
        if !obs.first().is_some_and(|o| agent.answers(o)) {
            continue;
        }
        let mut cmds = Vec::new();
        for o in &obs {
            let mut c = Command::keep(o);
            agent.tick(o, &mut c);
            if bad {
                cmds.extend(garbage(&c));
            }
            cmds.push(c);
        }
        if let Err(e) = link.send(&cmds) {
            break Err(e);
        }
        link.ticks += 1;
    };
    match result {
        Ok(Ended::WorldEnded) => ExitCode::SUCCESS,
        Ok(Ended::Silent) => {
            eprintln!("goto_agent: the world fell silent");
            ExitCode::from(1)
        }
        Err(shoal_bridge::BridgeError::Interrupted) => {
            // Dropping the link (on return) says goodbye: the world records `left`.
            eprintln!("goto_agent: interrupted after {} ticks", link.ticks);
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("goto_agent: {e}");
            ExitCode::from(1)
        }
    }
}
