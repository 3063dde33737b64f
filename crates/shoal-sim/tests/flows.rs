//! Per-flow measures of unicast traffic (`Medium::flows`): a flow over a clean link delivers
//! and acknowledges what it offered, a flow to a vehicle out of reach gives every frame up
//! after its retries; each flow's LED time is its frames' and acknowledgements' airtimes,
//! counted by hand; and the flows add up to the world's totals.

mod support;

use shoal_sim::comm::{CommStats, FlowStats};
use shoal_sim::prelude::*;
use support::world::world;

/// Airtime of a frame with `n` payload bytes on the μAUV² modem \[s\]: (n + 6 header bytes)
/// × 10 line bits at 19.2 kbit/s.
fn airtime(n: usize) -> f64 {
    (n + 6) as f64 * 10.0 / 19_200.0
}

const PAYLOAD: usize = 26;

/// `a` sends acknowledged unicasts to `b`, which faces it 1.25 m away; `d` sends them to `c`,
/// 9 m behind it (out of reach). One front modem each, three retries.
const WORLD: &str = r#"
seed = 6
duration = 20.0
[pool]
size = [16.0, 6.0, 3.0]
[[vehicles]]
name = "a"
position = [2.0, 2.0, 1.5]
behaviour = { kind = "poisson", rate = 4.0, payload_bytes = 26, to = "b", ack = true }
[[vehicles.model.modems]]
[[vehicles]]
name = "b"
position = [3.25, 2.0, 1.5]
heading_deg = 180
[[vehicles.model.modems]]
[[vehicles]]
name = "c"
position = [3.0, 4.5, 1.5]
[[vehicles.model.modems]]
[[vehicles]]
name = "d"
position = [12.0, 4.5, 1.5]
behaviour = { kind = "poisson", rate = 2.0, payload_bytes = 26, to = "c", ack = true }
[[vehicles.model.modems]]
"#;

fn flow(sim: &Sim, from: u32, to: u32) -> FlowStats {
    let f = sim.medium().flows().iter().find(|(k, _)| **k == (from, to));
    f.map(|(_, s)| s.clone()).unwrap_or_default()
}

#[test]
fn flows_count_what_they_offered_delivered_gave_up_and_lit() {
    let mut sim = world(WORLD);
    sim.run(2000);
    let stats = |id: usize| -> CommStats { sim.vehicle(id).comm };
    let (a, b, d) = (stats(0), stats(1), stats(3));
    assert_eq!(sim.medium().flows().len(), 2);

    // a → b: a clean link. Every frame handed over was delivered once and acknowledged,
    // but those still waiting at the end; nothing was given up.
    let ab = flow(&sim, 0, 1);
    assert!(ab.offered > 60, "{ab:?}");
    assert_eq!(ab.offered_bytes, ab.offered * PAYLOAD as u64);
    assert_eq!((ab.gave_up, ab.delivered), (0, ab.acknowledged), "{ab:?}");
    let waiting = ab.offered - ab.acknowledged;
    assert!(waiting <= 2, "{ab:?}");
    // Its LEDs: a's transmissions of the frames, b's acknowledgements (header only).
    let lit =
        (a.sent + a.retransmissions) as f64 * airtime(PAYLOAD) + b.acks_sent as f64 * airtime(0);
    assert!((ab.led_on_s - lit).abs() < 1e-9, "{} vs {lit}", ab.led_on_s);
    // Hand-over at a step boundary, the frame, the acknowledgement a step boundary later at
    // most: the median latency (a bin centre, ±6 %) between the two airtimes and a step more.
    let p50 = ab.latency_quantile(0.5).unwrap();
    let (lo, hi) = (
        airtime(PAYLOAD) + airtime(0),
        airtime(PAYLOAD) + airtime(0) + 0.01,
    );
    assert!(
        p50 > lo * 0.94 && p50 < hi * 1.06,
        "{p50} not in [{lo}, {hi}]"
    );

    // d → c: out of reach. Every frame went out 1 + 3 times and was given up.
    let dc = flow(&sim, 3, 2);
    assert!(dc.offered > 30, "{dc:?}");
    assert_eq!((dc.delivered, dc.acknowledged), (0, 0));
    assert!(dc.offered - dc.gave_up <= 2, "{dc:?}");
    assert_eq!(dc.retransmissions, d.retransmissions);
    assert!(dc.retransmissions >= 3 * dc.gave_up, "{dc:?}");
    let lit = (d.sent + d.retransmissions) as f64 * airtime(PAYLOAD);
    assert!((dc.led_on_s - lit).abs() < 1e-9, "{} vs {lit}", dc.led_on_s);
    assert_eq!(dc.latency_quantile(0.5), None);
    assert_eq!(dc.delivery_after_retries(), Some(0.0));

    // The flows add up to the world's totals.
    let all: Vec<CommStats> = (0..4).map(stats).collect();
    let sum = |f: &dyn Fn(&CommStats) -> u64| all.iter().map(f).sum::<u64>();
    assert_eq!(ab.gave_up + dc.gave_up, sum(&|s| s.gave_up));
    assert_eq!(
        ab.retransmissions + dc.retransmissions,
        sum(&|s| s.retransmissions)
    );
    let acked: u64 = sim.medium().ack_latency_histogram().iter().sum();
    assert_eq!(ab.acknowledged + dc.acknowledged, acked);
    let energy: f64 = all.iter().map(|s| s.led_energy_j).sum();
    assert!((ab.led_energy_j + dc.led_energy_j - energy).abs() < 1e-9);
}
