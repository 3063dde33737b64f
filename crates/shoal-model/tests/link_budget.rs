//! The optical link budget against hand calculations, the calibration of the default μAUV²
//! modem (a 32-byte frame on axis in pool water: ≈ always at 2.0 m, half the time at 2.5 m,
//! almost never at 3.0 m), the field of view, and the effect of water type and daylight.

use shoal_model::optics::*;
use shoal_model::presets::uauv2_modem;
use std::f64::consts::PI;

const POOL_C: f64 = 0.07;
const INDOOR: Ambient = Ambient {
    surface_irradiance: 0.5,
    diffuse_attenuation: 0.1,
};
/// A 32-byte frame on the line: 320 bits.
const BITS_32: u64 = 320;

fn fer_at(d: f64, c: f64, ambient: &Ambient, depth: f64) -> f64 {
    let m = uauv2_modem();
    budget(
        &m.led,
        &m.rx,
        &LinkGeometry::on_axis(d),
        c,
        ambient,
        depth,
        0.0,
        BITS_32,
    )
    .fer
}

#[test]
fn budget_matches_a_hand_calculation_on_axis() {
    let m = uauv2_modem();
    // By hand, at 2.0 m in pool water (m = 1 for Φ½ = 60°):
    // H = 2/(2π·4) · 7e-6 · e^(−0.14) = 0.0795775 · 7e-6 · 0.8693582 = 4.842693e-7
    // P_r = 0.0485 · H = 2.348706e-8 W;  I_s = 0.25 · P_r = 5.871765e-9 A
    // I_bg = 0.25 · 0.5·e^(−0.1) · 7e-6 · sin²60° = 5.937996e-7 A
    // σ² = (4e-12)²·1e5 + 2q(I_s + I_bg + 1e-9)·1e5 = 1.6e-18 + 1.924763e-20 = 1.619248e-18 A²
    // SNR = I_s²/σ² = 21.2924;  BER = Q(4.61437) = 1.9715e-6;  FER(320) = 6.3068e-4
    let b = budget(
        &m.led,
        &m.rx,
        &LinkGeometry::on_axis(2.0),
        POOL_C,
        &INDOOR,
        1.0,
        0.0,
        BITS_32,
    );
    let rel = |a: f64, e: f64| ((a - e) / e).abs();
    assert!(rel(b.gain, 4.842_693e-7) < 1e-6, "H = {}", b.gain);
    assert!(rel(b.p_rx, 2.348_706e-8) < 1e-6, "P_r = {}", b.p_rx);
    assert!(rel(b.i_signal, 5.871_765e-9) < 1e-6);
    assert!(
        rel(b.sigma * b.sigma, 1.619_248e-18) < 1e-6,
        "σ² = {}",
        b.sigma * b.sigma
    );
    assert!(rel(b.snr, 21.2924) < 1e-5, "SNR = {}", b.snr);
    assert!(rel(b.ber, 1.9715e-6) < 1e-4, "BER = {}", b.ber);
    assert!(rel(b.fer, 6.3068e-4) < 1e-4, "FER = {}", b.fer);
}

#[test]
fn budget_off_axis_and_field_of_view() {
    let m = uauv2_modem();
    let on = channel_gain(&m.led, &m.rx, &LinkGeometry::on_axis(2.0), POOL_C);
    // 45° off the LED axis, 30° off the photodiode normal: × cos45° · cos30° (m = 1).
    let g = LinkGeometry {
        distance: 2.0,
        cos_tx: (PI / 4.0).cos(),
        cos_rx: (PI / 6.0).cos(),
    };
    let off = channel_gain(&m.led, &m.rx, &g, POOL_C);
    assert!((off / on - (PI / 4.0).cos() * (PI / 6.0).cos()).abs() < 1e-12);
    // A narrower LED (Φ½ = 30°, m = 4.82) falls off as cos^m: at 30° off axis, half of
    // (m+1)/2-scaled on-axis intensity.
    let narrow = Led {
        half_angle: 30f64.to_radians(),
        ..m.led.clone()
    };
    let g30 = LinkGeometry {
        distance: 2.0,
        cos_tx: (PI / 6.0).cos(),
        cos_rx: 1.0,
    };
    let ratio = channel_gain(&narrow, &m.rx, &g30, POOL_C)
        / channel_gain(&narrow, &m.rx, &LinkGeometry::on_axis(2.0), POOL_C);
    assert!(
        (ratio - 0.5).abs() < 1e-12,
        "half power at the half-power angle: {ratio}"
    );
    // Just outside the 60° field of view, or behind the LED: nothing at all.
    let outside = LinkGeometry {
        distance: 1.0,
        cos_tx: 1.0,
        cos_rx: 60.5f64.to_radians().cos(),
    };
    assert_eq!(channel_gain(&m.led, &m.rx, &outside, POOL_C), 0.0);
    let behind = LinkGeometry {
        distance: 1.0,
        cos_tx: -0.1,
        cos_rx: 1.0,
    };
    assert_eq!(channel_gain(&m.led, &m.rx, &behind, POOL_C), 0.0);
    let b = budget(&m.led, &m.rx, &outside, POOL_C, &INDOOR, 1.0, 0.0, BITS_32);
    assert_eq!(b.fer, 1.0);
}

#[test]
fn default_modem_is_calibrated_to_the_papers_range() {
    let at = |d: f64| fer_at(d, POOL_C, &INDOOR, 1.0);
    assert!(at(2.0) < 0.01, "2.0 m: FER {}", at(2.0));
    assert!((at(2.5) - 0.5).abs() < 0.05, "2.5 m: FER {}", at(2.5));
    assert!(at(3.0) > 0.99, "3.0 m: FER {}", at(3.0));
    // Monotone in distance.
    let mut prev = 0.0;
    for k in 0..60 {
        let f = at(1.0 + 0.05 * k as f64);
        assert!(f >= prev);
        prev = f;
    }
}

/// Distance at which the on-axis FER crosses 0.5.
fn d50(c: f64, ambient: &Ambient, depth: f64) -> f64 {
    let (mut lo, mut hi) = (0.05, 20.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if fer_at(mid, c, ambient, depth) < 0.5 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[test]
fn water_type_changes_range_by_the_beer_lambert_amount() {
    // Beam attenuation of the named water types [1/m].
    let types = [
        ("pool", 0.07),
        ("pure_sea", 0.056),
        ("clear_ocean", 0.151),
        ("coastal", 0.398),
        ("turbid_harbour", 2.19),
    ];
    let ranges: Vec<f64> = types.iter().map(|t| d50(t.1, &INDOOR, 1.0)).collect();
    // Clearer water reaches further.
    assert!(
        ranges[1] > ranges[0]
            && ranges[0] > ranges[2]
            && ranges[2] > ranges[3]
            && ranges[3] > ranges[4],
        "{ranges:?}"
    );
    // The link is thermal-noise limited, so the 50 % range is where the received power is the
    // same in every water: e^(−c d)/d² must agree (shot noise moves it by < 0.1 %).
    let p = |c: f64, d: f64| (-c * d).exp() / (d * d);
    let p0 = p(types[0].1, ranges[0]);
    for (t, d) in types.iter().zip(&ranges) {
        assert!((p(t.1, *d) / p0 - 1.0).abs() < 1e-3, "{}: d50 = {d}", t.0);
    }
}

#[test]
fn daylight_near_the_surface_shortens_the_range() {
    let day = Ambient {
        surface_irradiance: 50.0,
        diffuse_attenuation: 0.1,
    };
    let shallow = d50(POOL_C, &day, 0.3);
    let deep = d50(POOL_C, &day, 40.0);
    let indoor = d50(POOL_C, &INDOOR, 0.3);
    assert!(
        shallow < 0.9 * indoor,
        "daylight at 0.3 m: {shallow} vs {indoor}"
    );
    // 40 m down (e^(−4) of the surface light) the loss is a fifth of what it is at 0.3 m.
    assert!(
        deep > shallow && (indoor - deep) < 0.2 * (indoor - shallow),
        "daylight fades with depth: {deep}"
    );
}

#[test]
fn airtime_of_uart_frames() {
    let m = uauv2_modem();
    // 32 bytes on the line (26 payload + 6 header), 10 bits each at 19.2 kbit/s.
    assert!((m.airtime(26) - 32.0 * 10.0 / 19_200.0).abs() < 1e-15);
    assert_eq!(m.frame_bits(26), 320);
}

#[test]
fn received_power_with_precomputed_constants_matches_the_hand_calculation() {
    // The medium's form of the budget: P_r of the hand calculation above (2.0 m on axis, pool
    // water) is 2.348706e-8 W, with the sender's LED and the receiver's photodiode.
    let m = uauv2_modem();
    let rel = |a: f64, e: f64| ((a - e) / e).abs();
    let (tx, rx) = (ModemConsts::of(&m), ModemConsts::of(&m));
    let p = received_power(&tx, &rx, &LinkGeometry::on_axis(2.0), POOL_C);
    assert!(rel(p, 2.348_706e-8) < 1e-6, "P_r = {p}");
    // A receiver with half the photodiode area and a 30° field of view gets half the power on
    // axis and nothing 35° off its normal; the sender's side is unchanged.
    let mut small = m.clone();
    small.rx.area = 3.5e-6;
    small.rx.fov = 30f64.to_radians();
    let half = received_power(
        &tx,
        &ModemConsts::of(&small),
        &LinkGeometry::on_axis(2.0),
        POOL_C,
    );
    assert!(rel(half, 2.348_706e-8 / 2.0) < 1e-6, "P_r = {half}");
    let aside = LinkGeometry {
        distance: 2.0,
        cos_tx: 1.0,
        cos_rx: 35f64.to_radians().cos(),
    };
    assert_eq!(
        received_power(&tx, &ModemConsts::of(&small), &aside, POOL_C),
        0.0
    );
    // A 25° LED at 0.2 W (m = ln 2 / −ln cos 25° = 7.045875): coef = 0.2 (m+1)/(2π)
    // = 0.256108 W; 20° off its axis at 1.5 m: 0.256108/2.25 · (cos 20°)^m · 7e-6 · e^(−0.105)
    //   = 0.113826 · 0.645151 · 7e-6 · 0.900325 = 4.628065e-7 W.
    let mut narrow = m.clone();
    narrow.led = Led {
        power: 0.2,
        half_angle: 25f64.to_radians(),
    };
    let g = LinkGeometry {
        distance: 1.5,
        cos_tx: 20f64.to_radians().cos(),
        cos_rx: 1.0,
    };
    let p = received_power(&ModemConsts::of(&narrow), &rx, &g, POOL_C);
    assert!(rel(p, 4.628_065e-7) < 1e-5, "P_r = {p}");
    // And the channel gain is the same budget at 1 W.
    let h = channel_gain(&narrow.led, &m.rx, &g, POOL_C);
    assert!(rel(0.2 * h, p) < 1e-12, "{h} vs {p}");
}
