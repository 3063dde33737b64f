//! The communication report of a run with traffic, against what the medium's physics allows:
//! the gossip world's flood (time to inform everyone, hops, time per hop) from airtime, tick
//! period and random delay.

mod support;

#[test]
fn gossip_floods_the_swarm_hop_by_hop_at_the_pace_of_ticks_and_airtime() {
    let (desc, sim) = support::world::run_world_file("gossip");
    assert!(desc.vehicles.len() >= 50);
    let snaps = sim.views();
    let c = shoal_record::comm_report::summarize(&desc, &sim, &snaps).unwrap();
    let g = c.gossip.unwrap();
    assert_eq!(g.informed, g.vehicles, "everyone learns the value");
    let t = g.time_to_all_s.unwrap();
    // 8-byte payload + 6-byte header at 19.2 kbit/s.
    let airtime = 14.0 * 10.0 / 19_200.0;
    // Gossip reacts every physics step (0.01 s); random delay up to 0.02 s; repeats 0.1 s apart.
    let (period, jitter, interval) = (0.01, 0.02, 0.1);
    let hops = f64::from(g.max_hops);
    // A hop costs at least one airtime; at most a wait for the next step, the random delay and
    // the airtime, plus one repeat interval when a first try is lost somewhere.
    assert!(t >= hops * airtime, "{t} s for {hops} hops");
    assert!(
        t <= hops * (period + jitter + airtime) + interval,
        "{t} s for {hops} hops"
    );
    // The far corner is ≈ 15 m away and a hop reaches at most ≈ 3.2 m (a diagonal at the edge
    // of the range): at least 5 hops; on a 1.6 m grid, at most 15.
    assert!((5..=15).contains(&g.max_hops), "{} hops", g.max_hops);
    // Informed vehicles learned it in hop order: a vehicle's hop count is its number of
    // relays, so time per hop is bounded the same way.
    assert!(
        g.mean_time_per_hop_s >= airtime
            && g.mean_time_per_hop_s <= period + jitter + airtime + interval
    );
}
