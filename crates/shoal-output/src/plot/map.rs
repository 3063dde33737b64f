//! Maps: the region a plot of the pool seen from above shows, east to the right and north
//! up, zoomed to where the vehicles are, with one scale on both axes (shoal-sim draws the
//! world's walls and obstacles in it).

/// The region a map (east to the right, north up) shows: the bounding box of `points`
/// ((east, north) \[m\]) grown by a margin (10 % of its extent, at least 0.5 m), within the
/// pool (plus 5 % of its size, so the walls show when the vehicles are near them). Returns
/// the east range, the north range and an image size \[px\] (`height` high, about as wide as
/// the aspect ratio needs, within 560 … 1800 px). Without finite points the whole pool is
/// shown. A map drawn with these also sets [`Plot::equal_aspect`](super::description::Plot::equal_aspect),
/// which widens one range to make the two scales exactly equal whatever the image size.
pub fn map_view(
    pool: (f64, f64),
    points: impl IntoIterator<Item = (f64, f64)>,
    height: u32,
) -> ((f64, f64), (f64, f64), (u32, u32)) {
    let (north, east) = pool;
    let edge = 0.05 * north.max(east);
    let (mut e0, mut e1, mut n0, mut n1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (e, n) in points {
        if e.is_finite() && n.is_finite() {
            (e0, e1, n0, n1) = (e0.min(e), e1.max(e), n0.min(n), n1.max(n));
        }
    }
    let (er, nr) = if e0 <= e1 && n0 <= n1 {
        let grow = |lo: f64, hi: f64, span: f64| {
            let m = (0.1 * (hi - lo)).max(0.5);
            ((lo - m).max(-edge), (hi + m).min(span + edge))
        };
        (grow(e0, e1, east), grow(n0, n1, north))
    } else {
        ((-edge, east + edge), (-edge, north + edge))
    };
    let w =
        ((f64::from(height) - 60.0) * (er.1 - er.0) / (nr.1 - nr.0) + 80.0).clamp(560.0, 1800.0);
    (er, nr, (w as u32, height))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_view_zooms_to_the_points_within_the_pool() {
        // A 100 × 60 m pool (north × east); vehicles within 2 m around (north 50, east 30).
        let pts = [(29.0, 49.0), (31.0, 51.0), (f64::NAN, 0.0)];
        let (e, n, (w, h)) = map_view((100.0, 60.0), pts, 700);
        assert_eq!((e, n), ((28.5, 31.5), (48.5, 51.5)));
        assert_eq!(h, 700);
        assert!((560..=1800).contains(&w));
        // Near a wall the view stops 5 % of the pool's larger side beyond it.
        let (e, n, _) = map_view((100.0, 60.0), [(0.0, 99.0), (60.0, 90.0)], 700);
        assert_eq!(e, (-5.0, 65.0));
        assert!(
            (n.0 - 89.1).abs() < 1e-12 && (n.1 - 99.9).abs() < 1e-12,
            "{n:?}"
        );
        // Nothing to show: the whole pool.
        let (e, n, _) = map_view((100.0, 60.0), std::iter::empty(), 700);
        assert_eq!((e, n), ((-5.0, 65.0), (-5.0, 105.0)));
    }
}
