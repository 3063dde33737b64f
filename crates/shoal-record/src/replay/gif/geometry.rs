//! Geometry for the drawings: clipping, convex hulls, obstacle outlines from their shapes and poses, tick steps, the body outline of a vehicle, the dashes of a dashed line.

use super::layout::PanelKind;
use crate::replay::ObstacleMeta;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// The part of the convex polygon `poly` inside the box `h` × `v` (Sutherland–Hodgman).
pub(super) fn clip_convex(poly: &[(f64, f64)], h: (f64, f64), v: (f64, f64)) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = poly.to_vec();
    // Each edge of the box: inside test and intersection.
    let planes: [(usize, f64, bool); 4] = [
        (0, h.0, true),
        (0, h.1, false),
        (1, v.0, true),
        (1, v.1, false),
    ];
    for (axis, bound, keep_above) in planes {
        let inside = |p: &(f64, f64)| {
            let c = if axis == 0 { p.0 } else { p.1 };
            if keep_above { c >= bound } else { c <= bound }
        };
        let input = std::mem::take(&mut out);
        let n = input.len();
        for i in 0..n {
            let (a, b) = (input[i], input[(i + 1) % n]);
            let (ia, ib) = (inside(&a), inside(&b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let (ca, cb) = if axis == 0 { (a.0, b.0) } else { (a.1, b.1) };
                let t = (bound - ca) / (cb - ca);
                out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The convex hull of `pts` (Andrew's monotone chain) into `out`, counter-clockwise in image
/// coordinates' sense of orientation; `pts` is sorted in place.
pub(super) fn convex_hull(pts: &mut [(f64, f64)], out: &mut Vec<(i32, i32)>) {
    out.clear();
    if pts.is_empty() {
        return;
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: [(f64, f64); 32] = [(0.0, 0.0); 32];
    let mut k = 0usize;
    let n = pts.len().min(15);
    for &p in &pts[..n] {
        while k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0 {
            k -= 1;
        }
        hull[k] = p;
        k += 1;
    }
    let lower = k + 1;
    for &p in pts[..n].iter().rev().skip(1) {
        while k >= lower && cross(hull[k - 2], hull[k - 1], p) <= 0.0 {
            k -= 1;
        }
        hull[k] = p;
        k += 1;
    }
    out.extend(
        hull[..k.saturating_sub(1).max(1)]
            .iter()
            .map(|p| (p.0.round() as i32, p.1.round() as i32)),
    );
}

/// A unit quaternion from (x, y, z, w); `None` unless finite and non-zero.
pub(super) fn rotation_of(q: [f64; 4]) -> Option<UnitQuaternion<f64>> {
    let q = Quaternion::new(q[3], q[0], q[1], q[2]);
    (q.coords.iter().all(|c| c.is_finite()) && q.norm() > 1e-12)
        .then(|| UnitQuaternion::from_quaternion(q))
}

/// The support point of the obstacle `o` in the world direction `d` (the point of the shape
/// farthest along `d`) \[m\], or `None` for an unknown kind or missing or bad dimensions.
/// Shapes as parry builds them: box of full extents `size`, sphere, cylinder along local y of
/// full `height`, capsule along local z with a straight part of `height`.
pub(super) fn support(
    o: &ObstacleMeta,
    rot: &UnitQuaternion<f64>,
    d: Vector3<f64>,
) -> Option<Vector3<f64>> {
    let l = rot.inverse_transform_vector(&d);
    let pos_f = |v: f64| v.is_finite() && v >= 0.0;
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    let local = match o.kind.as_str() {
        "box" => {
            let s = o.size.filter(|s| s.iter().all(|v| pos_f(*v)))?;
            Vector3::new(
                0.5 * s[0] * sign(l.x),
                0.5 * s[1] * sign(l.y),
                0.5 * s[2] * sign(l.z),
            )
        }
        "sphere" => {
            let r = o.radius.filter(|r| pos_f(*r))?;
            l.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
        }
        "cylinder" => {
            let (r, h) = (
                o.radius.filter(|r| pos_f(*r))?,
                o.height.filter(|h| pos_f(*h))?,
            );
            let radial = Vector3::new(l.x, 0.0, l.z);
            radial.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
                + Vector3::new(0.0, 0.5 * h * sign(l.y), 0.0)
        }
        "capsule" => {
            let (r, h) = (
                o.radius.filter(|r| pos_f(*r))?,
                o.height.filter(|h| pos_f(*h))?,
            );
            l.try_normalize(1e-12).unwrap_or_else(Vector3::zeros) * r
                + Vector3::new(0.0, 0.0, 0.5 * h * sign(l.z))
        }
        _ => return None,
    };
    let p = Vector3::from(o.position);
    p.iter()
        .all(|c| c.is_finite())
        .then(|| rot.transform_vector(&local) + p)
}

/// The outline of the obstacle `o` seen by the panel (its projection: from above on x–y, from
/// the side on x–z) in map coordinates, as a convex polygon of 48 support points.
pub(super) fn obstacle_outline(o: &ObstacleMeta, kind: PanelKind) -> Option<Vec<(f64, f64)>> {
    let rot = rotation_of(o.rotation)?;
    (0..48)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 48.0;
            let (c, s) = (a.cos(), a.sin());
            let d = match kind {
                PanelKind::Top => Vector3::new(c, s, 0.0),
                PanelKind::Side => Vector3::new(c, 0.0, s),
            };
            let p = support(o, &rot, d)?;
            Some(match kind {
                PanelKind::Top => (p.y, p.x),
                PanelKind::Side => (p.x, p.z),
            })
        })
        .collect()
}

/// A nice tick step for `span` metres over `px` pixels: about one tick per 60 px.
pub(super) fn tick_step(span: f64, px: f64) -> f64 {
    let raw = (span * 60.0 / px.max(1.0)).max(1e-6);
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

pub(super) fn tick_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else if step >= 0.1 {
        1
    } else {
        2
    };
    let v = if v.abs() < 0.5 * step * 1e-6 { 0.0 } else { v };
    format!("{v:.decimals$}")
}

/// The body of a vehicle in its own frame (x forward, y right, z down) \[m\]: a pointed
/// prism of the hull's length, width and height.
pub(super) fn body_points(hull: [f64; 3]) -> [Vector3<f64>; 10] {
    let (l, w, h) = (0.5 * hull[0], 0.5 * hull[1], 0.5 * hull[2]);
    let outline = [(l, 0.0), (l / 3.0, w), (-l, w), (-l, -w), (l / 3.0, -w)];
    let mut pts = [Vector3::zeros(); 10];
    for (i, (x, y)) in outline.into_iter().enumerate() {
        pts[i] = Vector3::new(x, y, -h);
        pts[i + 5] = Vector3::new(x, y, h);
    }
    pts
}

/// Dash and gap of the dashed lines of acknowledgement frames \[px\] (a dash is drawn with
/// both its end pixels, so the gaps look a pixel shorter).
pub(super) const ACK_DASH_PX: (f64, f64) = (6.0, 5.0);

/// The dashes of a dashed line from `a` to `b` (image positions \[px\]): pieces of `dash`
/// px with gaps of `gap` px, the first starting at `a`, the last cut short at `b`; each as
/// its two end pixels. None when `a` and `b` coincide.
pub(super) fn dashes(
    a: (f64, f64),
    b: (f64, f64),
    (dash, gap): (f64, f64),
) -> impl Iterator<Item = [(i32, i32); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = dx.hypot(dy);
    let period = dash + gap;
    let n = if len > 0.0 && len.is_finite() && period > 0.0 {
        // Truncation intended: the dashes that start before the end.
        (len / period).ceil() as usize
    } else {
        0
    };
    let at = move |s: f64| {
        let f = s / len;
        ((a.0 + f * dx).round() as i32, (a.1 + f * dy).round() as i32)
    };
    (0..n).map(move |k| {
        let s0 = k as f64 * period;
        [at(s0), at((s0 + dash).min(len))]
    })
}
