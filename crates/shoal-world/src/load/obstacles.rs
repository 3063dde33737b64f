//! Obstacles: every dimension is checked before its parry3d shape is built (a negative or
//! NaN radius must be a located problem, never a panic inside parry).

use super::validator::Validator;
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
    v.fields(&p.key("position"), &o.position);
    v.fields(&p.key("rotation_deg"), &o.rotation_deg);
    let need = |v: &mut Validator<'_>, key: &str, val: Option<f64>| -> f64 {
        match val {
            Some(x) => {
                v.field(&p.key(key), x);
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
    // Dimensions first; the parry shape is built only from checked values.
    enum Dims {
        Box([f64; 3]),
        Sphere(f64),
        Cylinder(f64, f64),
        Capsule(f64, f64),
    }
    let dims = match o.shape {
        ShapeKind::Box => Dims::Box(match o.size {
            Some(s) => {
                v.fields(&p.key("size"), &s);
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
        }),
        ShapeKind::Sphere => Dims::Sphere(need(v, "radius", o.radius)),
        ShapeKind::Cylinder => {
            Dims::Cylinder(need(v, "radius", o.radius), need(v, "height", o.height))
        }
        ShapeKind::Capsule => {
            Dims::Capsule(need(v, "radius", o.radius), need(v, "height", o.height))
        }
    };
    if v.problems.len() > n0 {
        return None;
    }
    let shape = match dims {
        Dims::Box(s) => SharedShape::cuboid(0.5 * s[0], 0.5 * s[1], 0.5 * s[2]),
        Dims::Sphere(r) => SharedShape::ball(r),
        Dims::Cylinder(r, h) => SharedShape::cylinder(0.5 * h, r),
        Dims::Capsule(r, h) => SharedShape::capsule_z(0.5 * h, r),
    };
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
