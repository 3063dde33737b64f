//! The allowed range of every number a world file holds, as one table: the checks read it
//! ([`super::validator::Validator::field`]) and the "Allowed ranges" table of
//! `docs/world-files.md` is printed from it ([`markdown`]; a test keeps the two in step).
//!
//! The limits are physical, not merely "positive": a mass, an inertia, a volume or a time
//! constant has a smallest value that still describes a vehicle (so 1e-310 is refused, where it
//! would give a NaN trajectory), and a coefficient that may be zero (no effect) is either zero
//! or at least a smallest meaningful value. Subnormal numbers are never accepted.
//!
//! A field path pattern is the field path with every index written `[]` (any element) and
//! `*` for any key, e.g. `vehicles[].model.control.*.omega`. Some limits depend on another
//! field (a tank's initial volume ≤ its capacity): their end is [`End::Field`], whose value
//! the check supplies.

pub use crate::range::{End, FieldRange, fmt_num};
use crate::range::{r, z};
use End::{Closed as C, Field as F, Open as O, OpenField as OF};

/// Largest coordinate a position may have \[m\].
pub const BIG: f64 = 1e6;

/// Every checked number of a world file.
#[rustfmt::skip]
pub const RANGES: &[FieldRange] = &[
    // Top level.
    r("duration", C(1e-3), C(1e7), "s", "simulated time"),
    r("dt", C(1e-6), C(0.1), "s", "physics step: below 1 µs nothing is resolved better, above 0.1 s RK4 misses the thrusters' dynamics"),
    r("pool.size", C(0.1), C(1e4), "m", "length, width, depth"),
    r("water.density", C(500.0), C(2000.0), "kg/m³", "any water, fresh to brine"),
    r("water.attenuation", C(0.0), C(100.0), "1/m", "beam attenuation c, pure sea 0.056 to harbour mud"),
    r("water.current", C(-5.0), C(5.0), "m/s", "each component, north/east/down"),
    r("water.ambient_irradiance", C(0.0), C(2000.0), "W/m²", "light in the modems' band below the surface (sunlight ≈ 1000)"),
    r("water.diffuse_attenuation", C(0.0), C(100.0), "1/m", "how fast ambient light fades with depth"),
    r("agents.timeout", C(1e-3), C(3600.0), "s", "wait for an agent's command per tick"),
    r("agents.attach_timeout", C(0.0), C(86400.0), "s", "wait for agents to attach before the run"),
    r("agents.pace", C(0.0), C(1e6), "simulated s per wall s", "0: as fast as possible"),
    r("ros2.domain_id", C(0.0), C(232.0), "-", "DDS domain (ROS_DOMAIN_ID)"),
    r("ros2.rtf", C(0.0), C(1e6), "simulated s per wall s", "free-running real-time factor; 0: as fast as possible"),
    r("output.record_hz", C(1e-3), C(1000.0), "Hz", "trajectory rows per simulated second"),
    // Obstacles.
    r("obstacles[].position", C(-BIG), C(BIG), "m", "centre"),
    r("obstacles[].rotation_deg", C(-360.0), C(360.0), "deg", "roll, pitch, yaw"),
    r("obstacles[].size", C(1e-3), C(1e4), "m", "box extents"),
    r("obstacles[].radius", C(1e-3), C(1e4), "m", "sphere, cylinder, capsule"),
    r("obstacles[].height", C(1e-3), C(1e4), "m", "cylinder, capsule"),
    // Vehicle groups and placement.
    r("vehicles[].count", C(1.0), C(1e7), "vehicles", "the loader also refuses a count whose memory this machine does not have"),
    r("vehicles[].heading_deg", C(-360.0), C(360.0), "deg", "initial heading"),
    r("vehicles[].position", C(-BIG), C(BIG), "m", "body origin"),
    r("vehicles[].grid.origin", C(-BIG), C(BIG), "m", "first vehicle"),
    r("vehicles[].grid.spacing", C(-BIG), C(BIG), "m", "between columns (x) and rows (y)"),
    r("vehicles[].grid.columns", C(1.0), C(1e7), "", "vehicles per row"),
    r("vehicles[].random.min", C(-BIG), C(BIG), "m", "corner of the placement box"),
    r("vehicles[].random.max", C(-BIG), C(BIG), "m", "corner of the placement box (each ≥ min)"),
    // Mission.
    r("vehicles[].mission[].t", C(0.0), F("duration"), "s", "step time"),
    r("vehicles[].mission[].depth", C(0.0), F("pool depth"), "m", "depth setpoint"),
    r("vehicles[].mission[].yaw_deg", C(-720.0), C(720.0), "deg", "heading setpoint"),
    r("vehicles[].mission[].surge", C(-1e3), C(1e3), "N", "surge force setpoint"),
    r("vehicles[].mission[].sway", C(-1e3), C(1e3), "N", "sway force setpoint"),
    r("vehicles[].mission[].thrusters.*", F("−max_command"), F("max_command"), "%", "raw thruster command"),
    r("vehicles[].mission[].tilts_deg.*", F("min_deg"), F("max_deg"), "deg", "raw tilt angle"),
    // Behaviours.
    r("vehicles[].behaviour.period", C(1e-3), C(1e6), "s", "beacon or flocking period"),
    r("vehicles[].behaviour.payload_bytes", C(1.0), F("the modems' max_payload"), "bytes", "beacon and Poisson payload"),
    r("vehicles[].behaviour.jitter", C(0.0), C(1e6), "s", "random delay of each transmission"),
    r("vehicles[].behaviour.rate", C(1e-6), C(1e4), "1/s", "Poisson traffic: mean frames per second"),
    r("vehicles[].behaviour.hello", C(1e-3), C(1e6), "s", "reliable gossip: between hellos"),
    r("vehicles[].behaviour.start", C(0.0), F("duration"), "s", "first gossip"),
    r("vehicles[].behaviour.repeats", C(1.0), C(1e4), "", "gossip repeats"),
    r("vehicles[].behaviour.interval", C(1e-3), C(1e6), "s", "between gossip repeats"),
    r("vehicles[].behaviour.surge", C(-1.0), C(1.0), "N", "flocking cruise force"),
    r("vehicles[].behaviour.too_close", z_lo(), C(1.0), "W", "received power above which a neighbour is too close"),
    r("vehicles[].behaviour.too_far", z_lo(), OF("too_close"), "W", "received power below which a neighbour is too far"),
    r("vehicles[].behaviour.cohesion", C(0.0), C(100.0), "", "weight of cohesion against alignment"),
    // Vehicle model: body.
    r("vehicles[].model.body.mass", C(1e-3), C(1e5), "kg", "dry mass, 1 g to 100 t"),
    r("vehicles[].model.body.inertia", C(1e-9), C(1e5), "kg·m²", "principal moments: the diagonal, or a full matrix's diagonal"),
    r("vehicles[].model.body.inertia[]", C(-1e5), C(1e5), "kg·m²", "a row of a full inertia matrix"),
    r("vehicles[].model.body.added_mass[]", C(-1e5), C(1e5), "kg, kg·m, kg·m²", "a row of a full added-mass matrix"),
    r("vehicles[].model.body.cog", C(-100.0), C(100.0), "m", "centre of gravity"),
    r("vehicles[].model.body.cob", C(-100.0), C(100.0), "m", "centre of buoyancy"),
    r("vehicles[].model.body.volume", C(1e-6), C(1e3), "m³", "displaced volume, 1 cm³ to 1000 m³"),
    r("vehicles[].model.body.added_mass", C(0.0), C(1e5), "kg, kg·m²", "diagonal: surge, sway, heave, roll, pitch, yaw"),
    r("vehicles[].model.body.damping_linear", C(0.0), C(1e5), "N·s/m, N·m·s", "surge, sway, heave, roll, pitch, yaw"),
    r("vehicles[].model.body.damping_quadratic", C(0.0), C(1e5), "N·s²/m², N·m·s²", "surge, sway, heave, roll, pitch, yaw"),
    r("vehicles[].model.body.hull_size", C(1e-3), C(100.0), "m", "collision box"),
    // Vehicle model: actuators.
    r("vehicles[].model.tilts[].axis", C(-1e3), C(1e3), "", "non-zero; normalised on load"),
    r("vehicles[].model.tilts[].min_deg", C(-360.0), C(360.0), "deg", "mechanical limit"),
    r("vehicles[].model.tilts[].max_deg", F("min_deg"), C(360.0), "deg", "mechanical limit"),
    r("vehicles[].model.tilts[].rate_deg_s", C(1e-3), C(1e4), "deg/s", "servo speed"),
    r("vehicles[].model.thrusters[].position", C(-100.0), C(100.0), "m", "in the body frame"),
    r("vehicles[].model.thrusters[].direction", C(-1e3), C(1e3), "", "non-zero; normalised on load"),
    r("vehicles[].model.thrusters[].max_command", C(1e-3), C(1e4), "%", "command limit"),
    z("vehicles[].model.thrusters[].lag", 1e-4, 100.0, "s", "spin-up time constant; 0 = instant"),
    z("vehicles[].model.thrusters[].curve.ct_pos", 1e-12, 1e3, "N/%²", "forward thrust per command²"),
    z("vehicles[].model.thrusters[].curve.ct_neg", 1e-12, 1e3, "N/%²", "reverse thrust per command²"),
    r("vehicles[].model.thrusters[].curve.points[]", C(-1e6), C(1e6), "%, N", "a [command, thrust] pair of a thrust table (commands increasing, thrust not decreasing)"),
    r("vehicles[].model.ballast.capacity", C(1e-9), C(10.0), "m³", "tank volume"),
    z("vehicles[].model.ballast.flow", 1e-12, 1.0, "m³/s", "pump flow; 0 = no pump"),
    r("vehicles[].model.ballast.position", C(-100.0), C(100.0), "m", "tank centre"),
    r("vehicles[].model.ballast.initial_volume", C(0.0), F("capacity"), "m³", "water in the tank at the start"),
    // Vehicle model: sensors.
    r("vehicles[].model.pressure.c1", C(1e-9), C(1e4), "m/V", "pressure sensor scale"),
    r("vehicles[].model.pressure.c2", C(-1e4), C(1e4), "m", "pressure sensor offset"),
    r("vehicles[].model.pressure.depth_step", C(1e-9), C(10.0), "m", "quantisation step"),
    r("vehicles[].model.pressure.bits", C(1.0), C(32.0), "bits", "ADC resolution"),
    r("vehicles[].model.pressure.noise_std", C(0.0), C(10.0), "m", "depth noise"),
    r("vehicles[].model.pressure.position", C(-100.0), C(100.0), "m", "pressure port"),
    r("vehicles[].model.imu.attitude_noise_deg", C(0.0), C(90.0), "deg", "attitude noise"),
    r("vehicles[].model.imu.gyro_noise", C(0.0), C(10.0), "rad/s", "rate noise"),
    r("vehicles[].model.imu.gyro_bias", C(-10.0), C(10.0), "rad/s", "rate bias"),
    r("vehicles[].model.imu.accel_noise", C(0.0), C(100.0), "m/s²", "acceleration noise"),
    // Vehicle model: control.
    r("vehicles[].model.control.period", C(1e-4), C(10.0), "s", "controller period (a whole multiple of dt)"),
    r("vehicles[].model.control.*.omega", C(1e-3), C(100.0), "rad/s", "closed-loop natural frequency"),
    r("vehicles[].model.control.*.zeta", C(1e-3), C(100.0), "", "closed-loop damping ratio"),
    r("vehicles[].model.control.*.kp", C(0.0), C(1e6), "", "proportional gain (overrides omega)"),
    r("vehicles[].model.control.*.kd", C(0.0), C(1e6), "", "derivative gain (overrides zeta)"),
    r("vehicles[].model.control.dead_zone", C(0.0), C(10.0), "m", "depth error ignored"),
    r("vehicles[].model.control.filter_window", C(1.0), C(1000.0), "samples", "depth filter"),
    r("vehicles[].model.control.auto_tilt_max_deg", C(0.0), C(90.0), "deg", "auto mode's tilt limit"),
    z("vehicles[].model.control.rate_filter", 1e-4, 100.0, "s", "rate filter time constant; 0 = none"),
    // Vehicle model: optical modems.
    r("vehicles[].model.modems[].position", C(-100.0), C(100.0), "m", "in the body frame"),
    r("vehicles[].model.modems[].direction", C(-1e3), C(1e3), "", "non-zero; normalised on load"),
    r("vehicles[].model.modems[].led_power", C(1e-9), C(1e3), "W", "optical power"),
    r("vehicles[].model.modems[].led_half_angle_deg", C(0.1), O(90.0), "deg", "beam half-power half angle"),
    r("vehicles[].model.modems[].rx_area", C(1e-9), C(1.0), "m²", "photodiode area"),
    r("vehicles[].model.modems[].rx_fov_deg", C(0.1), C(90.0), "deg", "receiver half field of view"),
    r("vehicles[].model.modems[].responsivity", C(1e-3), C(10.0), "A/W", "photodiode responsivity"),
    r("vehicles[].model.modems[].noise_density", C(0.0), C(1e-6), "A/√Hz", "receiver noise"),
    r("vehicles[].model.modems[].bandwidth", C(1.0), C(1e10), "Hz", "receiver bandwidth"),
    r("vehicles[].model.modems[].dark_current", C(0.0), C(1e-3), "A", "photodiode dark current"),
    r("vehicles[].model.modems[].bit_rate", C(1.0), C(1e10), "bit/s", "line rate"),
    r("vehicles[].model.modems[].bits_per_byte", C(8.0), C(16.0), "bits", "on air, with start/stop bits"),
    r("vehicles[].model.modems[].header_bytes", C(0.0), C(64.0), "bytes", "per frame"),
    r("vehicles[].model.modems[].max_payload", C(1.0), C(65536.0), "bytes", "per frame"),
    r("vehicles[].model.modems[].queue_frames", C(1.0), C(1e5), "frames", "transmit queue"),
    r("vehicles[].model.modems[].capture_ratio", C(1.0), C(1e6), "(power ratio)", "a frame survives a collision this much stronger"),
    r("vehicles[].model.modems[].arq_retries", C(0.0), C(100.0), "", "retransmissions of an unacknowledged unicast frame"),
    r("vehicles[].model.modems[].ack_timeout", C(1e-4), C(100.0), "s", "wait for an acknowledgement after the frame ended"),
];

/// The lower end of a received-power threshold \[W\]: a photodiode sees nothing below 1 fW.
const fn z_lo() -> End {
    End::Closed(1e-15)
}

/// The pattern of a concrete field path: indices become `[]`.
pub fn pattern(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    let mut in_index = false;
    for c in path.chars() {
        match c {
            '[' => {
                in_index = true;
                out.push_str("[]");
            }
            ']' => in_index = false,
            _ if in_index => {}
            _ => out.push(c),
        }
    }
    out
}

/// Whether a table pattern (`*` for any key) matches a path pattern.
fn matches(table: &str, path: &str) -> bool {
    let (a, b): (Vec<&str>, Vec<&str>) = (table.split('.').collect(), path.split('.').collect());
    a.len() == b.len()
        && a.iter().zip(&b).all(|(x, y)| {
            x == y
                || x.strip_suffix("[]")
                    .map_or(*x == "*", |k| k == "*" && y.ends_with("[]"))
        })
}

/// The range of a field, by its concrete path (`vehicles[3].model.body.mass`), if it has one.
pub fn lookup(path: &str) -> Option<&'static FieldRange> {
    let p = pattern(path);
    all().find(|r| matches(r.field, &p))
}

/// Every row: the table's, then the medium-access protocols' ([`crate::access::ranges`]).
pub fn all() -> impl Iterator<Item = &'static FieldRange> {
    RANGES.iter().chain(crate::access::ranges())
}

/// The "Allowed ranges" table of `docs/world-files.md`, printed from [`RANGES`].
pub fn markdown() -> String {
    let mut s = String::from("| field | allowed | unit | meaning |\n|---|---|---|---|\n");
    for r in all() {
        let name = r.field.rsplit('.').next().unwrap_or(r.field);
        s.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            r.field,
            r.allowed(name, None, None),
            r.unit,
            r.why
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_and_lookup() {
        assert_eq!(
            pattern("vehicles[3].model.modems[0].bit_rate"),
            "vehicles[].model.modems[].bit_rate"
        );
        assert_eq!(
            lookup("vehicles[3].model.body.mass").unwrap().field,
            "vehicles[].model.body.mass"
        );
        assert_eq!(
            lookup("vehicles[0].model.control.yaw.omega").unwrap().field,
            "vehicles[].model.control.*.omega"
        );
        assert_eq!(
            lookup("vehicles[1].mission[2].thrusters.port")
                .unwrap()
                .field,
            "vehicles[].mission[].thrusters.*"
        );
        assert!(lookup("vehicles[0].model.body.nonsense").is_none());
    }

    #[test]
    fn every_pattern_is_unique_and_every_range_is_ordered() {
        let rows: Vec<&FieldRange> = all().collect();
        for (i, a) in rows.iter().enumerate() {
            assert!(
                rows[i + 1..].iter().all(|b| b.field != a.field),
                "{} twice",
                a.field
            );
            if let (End::Closed(l) | End::Open(l), End::Closed(h) | End::Open(h)) = (a.lo, a.hi) {
                assert!(l < h, "{}: {l} ≥ {h}", a.field);
            }
            assert!(a.zero_or >= 0.0);
        }
    }

    #[test]
    fn allowed_text() {
        let m = lookup("vehicles[0].model.body.mass").unwrap();
        assert_eq!(m.allowed("mass", None, None), "0.001 ≤ mass ≤ 1e5");
        let l = lookup("vehicles[0].model.thrusters[1].lag").unwrap();
        assert_eq!(l.allowed("lag", None, None), "lag = 0 or 1e-4 ≤ lag ≤ 100");
        let v = lookup("vehicles[0].model.ballast.initial_volume").unwrap();
        assert_eq!(
            v.allowed("initial_volume", None, Some(2e-5)),
            "0 ≤ initial_volume ≤ 2e-5 (capacity)"
        );
    }
}
