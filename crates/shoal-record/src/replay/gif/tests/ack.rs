//! Acknowledgement frames in the GIF: their links dashed, in their outcome's colour, and the
//! legend's one entry for them.

use super::super::geometry::ACK_DASH_PX;
use super::super::layout::{ACK_SAMPLE, LEGEND_ROW, LegendEntry};
use super::*;

/// Along the straight line from `a` to `b` (image pixels) between 20 % and 80 % of its
/// length, one sample per pixel: whether a pixel of colour `c` is within one pixel of it.
fn along(gif: &Decoded, frame: usize, a: (i32, i32), b: (i32, i32), c: RGBColor) -> Vec<bool> {
    let (dx, dy) = (f64::from(b.0 - a.0), f64::from(b.1 - a.1));
    let len = dx.hypot(dy);
    let n = len.round() as i32;
    (n / 5..n * 4 / 5)
        .map(|s| {
            let f = f64::from(s) / len;
            let x = (f64::from(a.0) + f * dx).round() as i32;
            let y = (f64::from(a.1) + f * dy).round() as i32;
            (-1..=1).any(|j| (-1..=1).any(|i| gif.rgb(frame, (x + i, y + j)) == [c.0, c.1, c.2]))
        })
        .collect()
}

/// Runs of equal values: (value, length) in order.
fn runs(v: &[bool]) -> Vec<(bool, usize)> {
    let mut out: Vec<(bool, usize)> = Vec::new();
    for &x in v {
        match out.last_mut() {
            Some((y, n)) if *y == x => *n += 1,
            _ => out.push((x, 1)),
        }
    }
    out
}

/// One delivered frame from vehicle 0 to vehicle 1 just before the end, an acknowledgement
/// or not: the same line, solid for a frame, dashed for an acknowledgement (drawn runs of
/// about a dash, gaps between them every dash and gap), in the colour of delivered frames
/// either way.
#[test]
fn an_acknowledgement_is_drawn_dashed_in_its_outcome_colour() {
    let d = dir("ack");
    let opts = GifOptions {
        view: View::Top,
        trail_s: 0.0,
        max_frames: 2,
        ..opts()
    };
    let delivered = outcome_color(Outcome::Delivered);
    let mut seen = Vec::new();
    for ack in [false, true] {
        let mut data = synthetic();
        data.links = vec![LinkEvent {
            ack,
            ..ev(19.9, 0, 1, Outcome::Delivered)
        }];
        data.meta.links_kept = 1;
        let path = d.join(format!("ack-{ack}.gif"));
        render(&data, &path, &opts).unwrap();
        let gif = decode(&path);
        let scene = Scene::new(&data, &path).unwrap();
        let lay = Layout::new(&scene, &opts);
        let top = lay.panels[0];
        let [a, b] = [paths()[0].1, paths()[1].1].map(|p| top.px(p));
        let last = gif.frames.len() - 1;
        seen.push(along(&gif, last, a, b, delivered));
        // The legend's entry for acknowledgements: its label, and a dashed sample of dark
        // runs with gaps of the background between them.
        let (x, y) = lay
            .legend
            .iter()
            .find_map(|(e, x, y)| match e {
                LegendEntry::Ack(label) => Some((label.clone(), *x, *y)),
                _ => None,
            })
            .map(|(label, x, y)| {
                assert_eq!(label, crate::link_key::ACK_LABEL);
                (x, y)
            })
            .expect("no legend entry for acknowledgements");
        let yc = y + LEGEND_ROW / 2;
        let sample: Vec<bool> = (x..x + ACK_SAMPLE)
            .map(|x| gif.rgb(last, (x, yc)) == [TEXT.0, TEXT.1, TEXT.2])
            .collect();
        let r = runs(&sample);
        assert!(
            r.iter().filter(|(on, _)| *on).count() >= 3,
            "legend sample {r:?}"
        );
        assert!(
            r.iter().any(|&(on, n)| !on && n >= 3),
            "legend sample {r:?}"
        );
    }
    // The frame: one run, the whole way.
    assert!(seen[0].iter().all(|&on| on), "solid: {:?}", runs(&seen[0]));
    // The acknowledgement: dashes of about ACK_DASH_PX.0 px (seen a pixel wider on each
    // side) and gaps between them, one every period.
    let r = runs(&seen[1]);
    let (dash, gap) = ACK_DASH_PX;
    let period = dash + gap;
    let (on, off): (Vec<(bool, usize)>, Vec<_>) = r.iter().partition(|(on, _)| *on);
    // The runs but the first and the last (cut by the ends of the sampled stretch).
    let inner = |v: &[(bool, usize)]| v[1..v.len().saturating_sub(1)].to_vec();
    let expected = seen[1].len() as f64 / period;
    assert!(
        (on.len() as f64 - expected).abs() <= 2.0,
        "{} dashes where about {expected:.1} fit: {r:?}",
        on.len()
    );
    assert!(off.len() + 1 >= on.len() && off.len() >= 3, "gaps: {r:?}");
    for &(_, n) in &inner(&on) {
        assert!((n as f64) <= dash + 4.0, "a dash of {n} px: {r:?}");
    }
    for &(_, n) in &inner(&off) {
        assert!((n as f64) <= gap && n >= 1, "a gap of {n} px: {r:?}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
