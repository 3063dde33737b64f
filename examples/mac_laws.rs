//! Throughput of the medium-access protocols against their textbook laws: unslotted ALOHA
//! (S = G·e^(−2G)) and slotted ALOHA (S = G·e^(−G)), measured in shoal's optical medium over
//! offered loads 0.05–2 in the geometry the laws assume (`shoal::sim::mac_laws`: 78 senders
//! around one receiver, all in view, capture off); and CSMA/CA with binary exponential
//! back-off against Bianchi's saturation model, 2–20 saturated stations; slotted p-persistent
//! CSMA against its saturation law, 2–20 stations at p = 0.1 and 0.3. Prints the tables of
//! `docs/mac.md` and draws its figures.
//!
//! ```text
//! cargo run --release --example mac_laws -- [OUT_STEM] [SECONDS]   # default: docs/img/mac_laws 240
//! ```

use shoal::output::plot::{Plot, Series};
use shoal::sim::mac_laws::{
    Law, Point, measure, measure_csma, measure_p_persistent, p_persistent, world_text,
};

/// Senders of the experiment.
const SENDERS: usize = 78;
/// Offered loads measured.
const LOADS: [f64; 9] = [0.05, 0.1, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0];

fn main() {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "docs/img/mac_laws".into());
    let seconds: f64 = args
        .next()
        .map_or(240.0, |s| s.parse().expect("SECONDS: a number"));
    let mut series = Vec::new();
    println!("| protocol | law | offered G | throughput S | law S(G) | S − law [pp] | frames |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for (i, (law, name, formula)) in [
        (Law::PureAloha, "ALOHA", "G·e^(−2G)"),
        (Law::SlottedAloha, "slotted ALOHA", "G·e^(−G)"),
    ]
    .into_iter()
    .enumerate()
    {
        let points: Vec<Point> = LOADS
            .iter()
            .enumerate()
            .map(|(k, &g)| {
                measure(law, &world_text(law, SENDERS, g, seconds, 1 + k as u64))
                    .expect("the experiment's world loads")
            })
            .collect();
        for p in &points {
            println!(
                "| {name} | {formula} | {:.3} | {:.4} | {:.4} | {:+.2} | {} |",
                p.g,
                p.s,
                law.throughput(p.g),
                100.0 * (p.s - law.throughput(p.g)),
                p.frames
            );
        }
        series.push(Series {
            label: Some(format!("{name}: law {formula}")),
            points: (0..=220)
                .map(|k| {
                    let g = k as f64 * 0.01;
                    (g, law.throughput(g))
                })
                .collect(),
            color: i,
            ..Default::default()
        });
        series.push(Series {
            label: Some(format!(
                "{name}: shoal, {SENDERS} senders, {seconds} s per load"
            )),
            points: points.iter().map(|p| (p.g, p.s)).collect(),
            color: i,
            dots: true,
            width: 5,
            ..Default::default()
        });
    }
    let files = Plot {
        title: "Medium access: throughput against offered load".into(),
        x_label: "offered load G [frames per frame time or slot]".into(),
        y_label: "throughput S [frames per frame time or slot]".into(),
        series,
        x_range: Some((0.0, 2.2)),
        y_range: Some((0.0, 0.45)),
        ..Default::default()
    }
    .write(std::path::Path::new(&out))
    .expect("write the figure");
    for f in files {
        println!("wrote {}", f.display());
    }
    csma(&format!("{out}_csma"), seconds / 4.0);
    persistent(&format!("{out}_p_persistent"), seconds / 4.0);
}

/// Slotted p-persistent CSMA against its saturation law: saturated stations, `seconds` each.
fn persistent(out: &str, seconds: f64) {
    use shoal::sim::mac_laws::{FRAME_TIME, csma::SLOT};
    println!();
    println!("| p | stations | throughput S | law | S − law [pp] | frames | collided frames |");
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    let mut series = Vec::new();
    for (k, p) in [0.1, 0.3].into_iter().enumerate() {
        let mut measured = Vec::new();
        for n in [2usize, 3, 5, 7, 10, 15, 20] {
            let r = measure_p_persistent(n, p, seconds, n as u64)
                .expect("the experiment's world loads");
            println!(
                "| {p} | {n} | {:.4} | {:.4} | {:+.2} | {} | {} |",
                r.s,
                r.model,
                100.0 * (r.s - r.model),
                r.delivered,
                r.collisions
            );
            measured.push((n as f64, r.s));
        }
        let law = (2..=20)
            .map(|n| (f64::from(n), p_persistent(n, p, SLOT, FRAME_TIME)))
            .collect();
        series.push(Series {
            label: Some(format!("law, p = {p}")),
            points: law,
            color: k,
            ..Default::default()
        });
        series.push(Series {
            label: Some(format!("shoal, p = {p}, {seconds} s per point")),
            points: measured,
            color: k,
            dots: true,
            width: 5,
            ..Default::default()
        });
    }
    let files = Plot {
        title: "Slotted p-persistent CSMA: saturation throughput".into(),
        x_label: "stations".into(),
        y_label: "throughput S [share of time carrying delivered frames]".into(),
        series,
        x_range: Some((0.0, 21.0)),
        y_range: Some((0.0, 0.8)),
        ..Default::default()
    }
    .write(std::path::Path::new(out))
    .expect("write the figure");
    for f in files {
        println!("wrote {}", f.display());
    }
}

/// CSMA/CA against Bianchi: saturated stations, `seconds` each.
fn csma(out: &str, seconds: f64) {
    println!();
    println!("| stations | throughput S | Bianchi | S − Bianchi [pp] | frames | retransmissions |");
    println!("|---:|---:|---:|---:|---:|---:|");
    let mut measured = Vec::new();
    let mut model = Vec::new();
    for n in [2usize, 3, 5, 7, 10, 15, 20] {
        let r = measure_csma(n, seconds, n as u64).expect("the experiment's world loads");
        println!(
            "| {n} | {:.4} | {:.4} | {:+.2} | {} | {} |",
            r.s,
            r.model,
            100.0 * (r.s - r.model),
            r.delivered,
            r.retransmissions
        );
        measured.push((n as f64, r.s));
        model.push((n as f64, r.model));
    }
    let files = Plot {
        title: "CSMA/CA with binary exponential back-off: saturation throughput".into(),
        x_label: "stations".into(),
        y_label: "throughput S [share of time carrying delivered frames]".into(),
        series: vec![
            Series {
                label: Some("Bianchi's model (W = 16, m = 6)".into()),
                points: model,
                color: 2,
                ..Default::default()
            },
            Series {
                label: Some(format!("shoal, {seconds} s per point")),
                points: measured,
                color: 2,
                dots: true,
                width: 5,
                ..Default::default()
            },
        ],
        x_range: Some((0.0, 21.0)),
        y_range: Some((0.0, 0.7)),
        ..Default::default()
    }
    .write(std::path::Path::new(out))
    .expect("write the figure");
    for f in files {
        println!("wrote {}", f.display());
    }
}
