//! Addressed frames from an agent: sends the frames it is told to, at the times it is told,
//! and logs on stdout, one JSON object a line, what its vehicles sent, received and learnt of
//! their acknowledged frames. The vehicles keep their setpoints (they hold where they are).
//!
//! ```sh
//! cargo run --release -- run worlds/agents_unicast.toml                   # terminal 1
//! cargo run --release -p shoal-bridge --example unicast_agent -- \
//!     agents_unicast link --send 0.5:0:1:ack:7 --send 1.0:0:3:ack:8       # terminal 2
//! ```
//!
//! Arguments: `PREFIX AGENT [--delay SECONDS] [--send AT:FROM:TO:ACK:TAG]...`. Each `--send`
//! hands one frame to vehicle FROM's modems ([`ALL_MODEMS`]) on its first tick at or after
//! AT \[s\], `--delay` after the tick (default 0): for vehicle TO (`all`: a broadcast), with
//! acknowledgement if ACK is `ack` (`-`: without), tagged TAG. Its payload is 8 bytes: TAG
//! and FROM, little-endian u32 each. Nothing stops a frame the world will refuse (to FROM
//! itself, to no vehicle, `all` with `ack`): the world counts it in `bad_frames`.
//!
//! Lines (times in seconds, power in watts):
//! - `{"event":"sent","t":…,"from":…,"to":…,"ack":…,"tag":…,"delay":…,"added":…}` (`to` −1
//!   for a broadcast; `added`: the command had room);
//! - `{"event":"rx","t_obs":…,"vehicle":…,"t":…,"peer":…,"unicast":…,"seq":…,"modem":…,
//!   "power":…,"payload":[…]}`;
//! - `{"event":"outcome","t_obs":…,"vehicle":…,"t":…,"sent":…,"to":…,"tag":…,"seq":…,
//!   "transmissions":…,"acknowledged":…}`.

use shoal_bridge::agent::{Agent, AgentLink, Ended};
use shoal_bridge::protocol::{ALL_MODEMS, BROADCAST, Command, Observation};
use std::io::Write;
use std::process::ExitCode;
use std::time::Duration;

/// One frame to send.
#[derive(Clone, Copy, Debug)]
struct Plan {
    /// Earliest tick \[s\].
    at: f64,
    from: u32,
    /// Destination, or [`BROADCAST`].
    to: u32,
    ack: bool,
    tag: u32,
    done: bool,
}

impl Plan {
    /// `AT:FROM:TO:ACK:TAG`.
    fn parse(s: &str) -> Option<Plan> {
        let p: Vec<&str> = s.split(':').collect();
        let [at, from, to, ack, tag] = p.as_slice() else {
            return None;
        };
        Some(Plan {
            at: at.parse().ok().filter(|x: &f64| x.is_finite())?,
            from: from.parse().ok()?,
            to: if *to == "all" {
                BROADCAST
            } else {
                to.parse().ok()?
            },
            ack: match *ack {
                "ack" => true,
                "-" => false,
                _ => return None,
            },
            tag: tag.parse().ok()?,
            done: false,
        })
    }
}

struct Sender {
    plans: Vec<Plan>,
    delay: f64,
    out: std::io::BufWriter<std::io::Stdout>,
}

impl Agent for Sender {
    fn tick(&mut self, o: &Observation, cmd: &mut Command) {
        for f in o.received() {
            let payload: Vec<String> = f.payload().iter().map(u8::to_string).collect();
            let _ = writeln!(
                self.out,
                r#"{{"event":"rx","t_obs":{:?},"vehicle":{},"t":{:?},"peer":{},"unicast":{},"seq":{},"modem":{},"power":{:?},"payload":[{}]}}"#,
                o.time,
                o.vehicle,
                f.t,
                f.peer,
                f.is_unicast(),
                f.seq,
                f.modem,
                f.power,
                payload.join(",")
            );
        }
        for e in o.outcomes() {
            let _ = writeln!(
                self.out,
                r#"{{"event":"outcome","t_obs":{:?},"vehicle":{},"t":{:?},"sent":{:?},"to":{},"tag":{},"seq":{},"transmissions":{},"acknowledged":{}}}"#,
                o.time,
                o.vehicle,
                e.t,
                e.sent,
                e.to,
                e.tag,
                e.seq,
                e.transmissions,
                e.is_acknowledged()
            );
        }
        for p in self
            .plans
            .iter_mut()
            .filter(|p| !p.done && p.from == o.vehicle && o.time + 1e-9 >= p.at)
        {
            p.done = true;
            let mut payload = p.tag.to_le_bytes().to_vec();
            payload.extend_from_slice(&p.from.to_le_bytes());
            let added = if p.to == BROADCAST && !p.ack {
                cmd.send(ALL_MODEMS, &payload, self.delay)
            } else {
                cmd.send_to(p.to, ALL_MODEMS, &payload, self.delay, p.ack, p.tag)
            };
            let to = if p.to == BROADCAST {
                -1
            } else {
                i64::from(p.to)
            };
            let _ = writeln!(
                self.out,
                r#"{{"event":"sent","t":{:?},"from":{},"to":{to},"ack":{},"tag":{},"delay":{:?},"added":{added}}}"#,
                o.time, p.from, p.ack, p.tag, self.delay
            );
        }
    }
}

/// The `--send` plans and the `--delay`, or what is wrong with the arguments.
fn parse(args: &[String]) -> Result<(Vec<Plan>, f64), String> {
    let mut plans = Vec::new();
    let mut delay = 0.0;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let value = || format!("{a} needs a value");
        match a.as_str() {
            "--send" => {
                let s = it.next().ok_or_else(value)?;
                plans
                    .push(Plan::parse(s).ok_or_else(|| format!("--send {s}: AT:FROM:TO:ACK:TAG"))?);
            }
            "--delay" => {
                let s = it.next().ok_or_else(value)?;
                delay = s
                    .parse()
                    .ok()
                    .filter(|d: &f64| d.is_finite())
                    .ok_or_else(|| format!("--delay {s}: a number of seconds"))?;
            }
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    Ok((plans, delay))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: unicast_agent PREFIX AGENT [--delay SECONDS] [--send AT:FROM:TO:ACK:TAG]...";
    let (Some(prefix), Some(name)) = (args.first(), args.get(1)) else {
        eprintln!("{usage}");
        return ExitCode::from(2);
    };
    let (plans, delay) = match parse(&args[2..]) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("unicast_agent: {e}\n{usage}");
            return ExitCode::from(2);
        }
    };
    let mut link = match AgentLink::attach(prefix, name, Duration::from_secs(60)) {
        Ok(l) => l,
        Err(shoal_bridge::BridgeError::Interrupted) => return ExitCode::from(130),
        Err(e) => {
            eprintln!("unicast_agent: {e}");
            return ExitCode::from(1);
        }
    };
    eprintln!("unicast_agent: attached to `{prefix}` as `{name}`");
    let mut agent = Sender {
        plans,
        delay,
        out: std::io::BufWriter::new(std::io::stdout()),
    };
    let ended = link.run(&mut agent);
    let _ = agent.out.flush();
    match ended {
        Ok(Ended::WorldEnded) => {
            eprintln!("unicast_agent: the run ended after {} ticks", link.ticks);
            ExitCode::SUCCESS
        }
        Ok(Ended::Silent) => {
            eprintln!("unicast_agent: the world fell silent");
            ExitCode::from(1)
        }
        Err(shoal_bridge::BridgeError::Interrupted) => ExitCode::from(130),
        Err(e) => {
            eprintln!("unicast_agent: {e}");
            ExitCode::from(1)
        }
    }
}
