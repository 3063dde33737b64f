//! Obstacles: every dimension is checked before its parry3d shape is built (a negative or
//! NaN radius must be a located problem, never a panic inside parry).

use super::validator::{BIG, End, Validator};
use crate::error::{FieldPath, ProblemKind};
use crate::geometry::Geometry;
use crate::spec::*;
use parry3d_f64::shape::SharedShape;
use shoal_model::prelude::*;

pub(super) fn obstacle(
    o: &ObstacleSpec,
    p: &FieldPath,
    i: usize,
    v: &mut Validator<'_>,
) -> Option<crate::geometry::Obstacle> {
    let n0 = v.problems.len();
    v.vec(
        &p.key("position"),
        &o.position,
        End::Closed(-BIG),
        End::Closed(BIG),
        "m",
    );
    v.vec(
        &p.key("rotation_deg"),
        &o.rotation_deg,
        End::Closed(-360.0),
        End::Closed(360.0),
        "deg",
    );
    let need = |v: &mut Validator<'_>, key: &str, val: Option<f64>| -> f64 {
        match val {
            Some(x) => {
                v.num(&p.key(key), x, End::Open(0.0), End::Closed(1e4), "m");
                x
            }
            None => {
                v.push(
                    ProblemKind::MissingField,
                    p,
                    format!("a {:?} obstacle needs `{key}` [m]", o.shape).to_lowercase(),
                );
                1.0
            }
        }
    };
    let shape = match o.shape {
        ShapeKind::Box => {
            let s = match o.size {
                Some(s) => {
                    v.vec(&p.key("size"), &s, End::Open(0.0), End::Closed(1e4), "m");
                    s
                }
                None => {
                    v.push(
                        ProblemKind::MissingField,
                        p,
                        "a box obstacle needs `size` = [x, y, z] [m]".into(),
                    );
                    [1.0; 3]
                }
            };
            SharedShape::cuboid(0.5 * s[0], 0.5 * s[1], 0.5 * s[2])
        }
        ShapeKind::Sphere => SharedShape::ball(need(v, "radius", o.radius)),
        ShapeKind::Cylinder => {
            let r = need(v, "radius", o.radius);
            let h = need(v, "height", o.height);
            SharedShape::cylinder(0.5 * h, r)
        }
        ShapeKind::Capsule => {
            let r = need(v, "radius", o.radius);
            let h = need(v, "height", o.height);
            SharedShape::capsule_z(0.5 * h, r)
        }
    };
    if v.problems.len() > n0 {
        return None;
    }
    let [r, pi, y] = o.rotation_deg.map(f64::to_radians);
    let mut att = quat_from_rpy(r, pi, y);
    if o.shape == ShapeKind::Cylinder {
        // parry's cylinder axis is local y; the file's is local z.
        att *= Quat::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2);
    }
    let name = o.name.clone().unwrap_or_else(|| format!("obstacle-{i}"));
    Some(Geometry::obstacle(
        &name,
        shape,
        &Vec3::from(o.position),
        &att,
    ))
}
