//! Axis ranges and clipping: the range that covers every finite value with a margin
//! ([`data_range`]), and the pieces of a line inside the plot area ([`clip_polyline`]).

/// Relative margin added on each side of an autoscaled axis.
const PAD: f64 = 0.05;

/// The axis range for `values`: from the smallest to the largest finite value, widened to at
/// least `min_span` about its centre, plus a margin of 5 % of the span on each side. Covers
/// every finite value; (0, 1) when there is none.
pub fn data_range(values: impl IntoIterator<Item = f64>, min_span: f64) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    let centre = 0.5 * (lo + hi);
    // Never narrower than a few ulps of the values (a constant series).
    let floor = 1e-9 * centre.abs().max(1.0);
    let span = (hi - lo).max(min_span.max(0.0)).max(floor);
    let (lo, hi) = if hi - lo < span {
        (centre - 0.5 * span, centre + 0.5 * span)
    } else {
        (lo, hi)
    };
    (lo - PAD * span, hi + PAD * span)
}

/// The part of the segment a–b inside the box `x` × `y` (Liang–Barsky), if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    x: (f64, f64),
    y: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0 = 0.0_f64;
    let mut t1 = 1.0_f64;
    for (p, q) in [
        (-dx, a.0 - x.0),
        (dx, x.1 - a.0),
        (-dy, a.1 - y.0),
        (dy, y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

/// The pieces of the polyline `points` inside the box `x` × `y` (each `(min, max)`): lines
/// are cut where they leave the box and at non-finite points. A single point is kept if it is
/// inside.
pub fn clip_polyline(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let inside = |p: &(f64, f64)| finite(p) && p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1;
    if points.len() == 1 {
        return if inside(&points[0]) {
            vec![points.to_vec()]
        } else {
            Vec::new()
        };
    }
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let mut flush = |cur: &mut Vec<(f64, f64)>| {
        if !cur.is_empty() {
            out.push(std::mem::take(cur));
        }
    };
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !finite(&a) || !finite(&b) {
            flush(&mut cur);
            continue;
        }
        match clip_segment(a, b, x, y) {
            None => flush(&mut cur),
            Some((p, q)) => {
                if cur.last() != Some(&p) {
                    flush(&mut cur);
                    cur.push(p);
                }
                cur.push(q);
                if q != b {
                    flush(&mut cur);
                }
            }
        }
    }
    flush(&mut cur);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_covers_every_value_with_a_margin() {
        let v = [3.0, -2.0, f64::NAN, 7.5, f64::INFINITY];
        let (lo, hi) = data_range(v, 0.0);
        assert!(lo < -2.0 && hi > 7.5);
        assert!((lo - (-2.0 - 0.05 * 9.5)).abs() < 1e-12);
        // A constant series gets a non-empty range.
        let (lo, hi) = data_range([1.0; 5], 0.0);
        assert!(lo < 1.0 && hi > 1.0);
        // The smallest span widens about the centre.
        let (lo, hi) = data_range([1.0, 1.002], 0.05);
        assert!((hi - lo - 1.1 * 0.05).abs() < 1e-12);
        assert!((0.5 * (lo + hi) - 1.001).abs() < 1e-12);
        assert_eq!(data_range([f64::NAN], 1.0), (0.0, 1.0));
    }

    #[test]
    fn clipping_cuts_lines_at_the_box_and_at_gaps() {
        let pts = [
            (0.0, 0.0),
            (1.0, 2.0),
            (2.0, 0.0),
            (f64::NAN, 1.0),
            (3.0, 0.5),
            (4.0, 0.5),
        ];
        let pieces = clip_polyline(&pts, (0.0, 10.0), (0.0, 1.0));
        // Up and out at (0.5, 1), back in at (1.5, 1); the gap splits off the last segment.
        assert_eq!(pieces.len(), 3, "{pieces:?}");
        assert_eq!(pieces[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(pieces[1], vec![(1.5, 1.0), (2.0, 0.0)]);
        assert_eq!(pieces[2], vec![(3.0, 0.5), (4.0, 0.5)]);
        for p in pieces.iter().flatten() {
            assert!(p.0 >= 0.0 && p.0 <= 10.0 && p.1 >= 0.0 && p.1 <= 1.0);
        }
        assert!(clip_polyline(&[(5.0, 5.0)], (0.0, 1.0), (0.0, 1.0)).is_empty());
    }
}
