//! The `school` agent in Rust (the same behaviour as `python/examples/school.py`): every
//! vehicle beacons its heading and depth once a second on all modems and steers towards the
//! mean of its own and what it heard in the last 3 s; alone, it stops and turns slowly to
//! find the others. It uses only sensed data and received frames.
//!
//! ```sh
//! cargo run --release -- run worlds/agents_school.toml                            # terminal 1
//! cargo run --release -p shoal-bridge --example school_agent -- agents_school      # terminal 2
//! ```
//! Arguments: `PREFIX [AGENT] [--bad]` (AGENT defaults to `school`; `--bad` also sends
//! invalid commands, to see them rejected and counted).

use shoal_bridge::agent::{Agent, AgentLink, Ended};
use shoal_bridge::protocol::{ALL_MODEMS, Command, Observation, mode};
use std::collections::BTreeMap;
use std::time::Duration;

/// Frame tag of a school beacon.
const TAG: u8 = 0x5c;

#[derive(Default)]
struct School {
    /// Per vehicle: (sender-less) beacons heard as (time, heading, depth).
    heard: BTreeMap<u32, Vec<(f64, f64, f64)>>,
    /// Per vehicle: time of its next beacon.
    next: BTreeMap<u32, f64>,
    bad: bool,
}

impl Agent for School {
    fn tick(&mut self, o: &Observation, cmd: &mut Command) {
        let heard = self.heard.entry(o.vehicle).or_default();
        for f in o.received() {
            let p = f.payload();
            if p.len() == 9 && p[0] == TAG {
                let h = f32::from_le_bytes([p[1], p[2], p[3], p[4]]) as f64;
                let d = f32::from_le_bytes([p[5], p[6], p[7], p[8]]) as f64;
                heard.push((f.t, h, d));
            }
        }
        heard.retain(|(t, _, _)| o.time - t < 3.0);
        // Beacon once a second, staggered by vehicle id.
        let next = self
            .next
            .entry(o.vehicle)
            .or_insert(0.1 * f64::from(o.vehicle % 10));
        if o.time + 1e-9 >= *next {
            let mut p = vec![TAG];
            p.extend_from_slice(&(o.yaw as f32).to_le_bytes());
            p.extend_from_slice(&(o.depth as f32).to_le_bytes());
            cmd.send(ALL_MODEMS, &p, 0.0);
            *next += 1.0;
        }
        if heard.is_empty() {
            cmd.set_mode(mode::AUTO, o.depth, o.yaw + 0.4, 0.0, 0.0);
        } else {
            let (mut x, mut y, mut d) = (o.yaw.cos(), o.yaw.sin(), o.depth);
            for (_, h, dd) in heard.iter() {
                x += h.cos();
                y += h.sin();
                d += dd;
            }
            let depth = d / (heard.len() + 1) as f64;
            cmd.set_mode(mode::AUTO, depth, y.atan2(x), 0.03, 0.0);
        }
        if self.bad && o.vehicle == 0 {
            // A buggy agent: NaN depth on every other tick, a huge surge on the others.
            if o.step.is_multiple_of(10) {
                cmd.depth = f64::NAN;
            } else {
                cmd.surge = 1e9;
            }
        }
    }
}

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bad = args.iter().any(|a| a == "--bad");
    let pos: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let Some(prefix) = pos.first() else {
        eprintln!("usage: school_agent PREFIX [AGENT] [--bad]");
        return std::process::ExitCode::from(2);
    };
    let name = pos.get(1).map_or("school", |s| s.as_str());
    let mut link = match AgentLink::attach(prefix, name, Duration::from_secs(60)) {
        Ok(l) => l,
        Err(shoal_bridge::BridgeError::Interrupted) => return std::process::ExitCode::from(130),
        Err(e) => {
            eprintln!("school_agent: {e}");
            return std::process::ExitCode::from(1);
        }
    };
    eprintln!("school_agent: attached to `{prefix}` as `{name}`");
    let mut school = School {
        bad,
        ..Default::default()
    };
    match link.run(&mut school) {
        Ok(Ended::WorldEnded) => {
            eprintln!("school_agent: the run ended after {} ticks", link.ticks);
            std::process::ExitCode::SUCCESS
        }
        Ok(Ended::Silent) => {
            eprintln!(
                "school_agent: the world fell silent after {} ticks",
                link.ticks
            );
            std::process::ExitCode::from(1)
        }
        Err(shoal_bridge::BridgeError::Interrupted) => {
            // Dropping the link (on return) says goodbye: the world records `left`.
            eprintln!("school_agent: interrupted after {} ticks", link.ticks);
            std::process::ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("school_agent: {e}");
            std::process::ExitCode::from(1)
        }
    }
}
