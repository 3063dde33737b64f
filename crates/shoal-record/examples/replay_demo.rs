//! Writes a synthetic demo replay (the test kit `tests/support/demo.rs`) and prints its size by part:
//! how big `replay.html` gets for a swarm and a duration.
//!
//! `cargo run -p shoal-record --example replay_demo -- [vehicles] [seconds] [out.html]`
//! (defaults: 12 vehicles, 60 s, `replay-demo.html`).

use std::path::PathBuf;

use shoal_record::replay::html;

#[path = "../tests/support/demo.rs"]
#[allow(
    dead_code,
    reason = "the example uses the demo itself, not its constants"
)]
mod demo;
use demo::demo;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|s| s.parse().ok()).unwrap_or(12);
    let seconds: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(60.0);
    let out = PathBuf::from(args.get(2).map_or("replay-demo.html", String::as_str));
    let data = demo(n, seconds);
    let b64 = |bytes: usize| bytes.div_ceil(3) * 4;
    let m = &data.meta;
    let start = std::time::Instant::now();
    let written = html::write(&out, &data);
    let write_s = start.elapsed().as_secs_f64();
    let path = match written {
        Ok(p) => p,
        Err(e) => {
            eprintln!("replay_demo: {e}");
            std::process::exit(1);
        }
    };
    let total = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let mb = |b: usize| b as f64 / 1e6;
    println!(
        "{}: {n} vehicles × {seconds} s, frame_dt {} s ({} frames), {} of {} link events kept, \
         written in {write_s:.2} s",
        path.display(),
        m.frame_dt,
        m.frames,
        m.links_kept,
        m.links_total
    );
    let poses = b64(data.pos.len() * 2) + b64(data.att.len() * 2);
    let panel = b64(data.panel.len() * 4);
    let links = b64(data.links.len() * 16);
    let header = serde_json::to_string(m).map_or(0, |s| s.len());
    let rest = (total as usize).saturating_sub(poses + panel + links + header);
    println!(
        "total {:.2} MB: poses {:.2} MB, panel {:.2} MB, links {:.2} MB, header {:.2} MB, \
         page + three.js {:.2} MB",
        total as f64 / 1e6,
        mb(poses),
        mb(panel),
        mb(links),
        mb(header),
        mb(rest),
    );
}
