//! The 3D scene of `run.mcap`, all in ENU ([`shoal_model::frames`]): the vehicles' poses
//! (`/tf`, `tf2_msgs/msg/TFMessage`: frame `world` → one frame per vehicle, FLU), and in
//! Foxglove's `foxglove_msgs/msg/SceneUpdate` the still scene
//! (`/scene`, once: each hull as a cylinder in its vehicle's frame with its name above it,
//! the pool's outline, the obstacles) and the optical links (`/links`: a line per reception
//! attempt from sender to receiver, in the colour of its outcome, [`crate::link_key`], that
//! disappears after [`link_lifetime`]).

use super::foxglove::*;
use super::ros2::{Duration, Header, Point, Pose, Time, Transform, TransformStamped};
use crate::link_key::{Outcome, style};
use crate::replay::ObstacleMeta;
use shoal_model::frames as enu;
use shoal_model::math::{Quat, Vec3};
use shoal_sim::comm::Heard;
use shoal_sim::recorder::col;
use shoal_world::desc::WorldDesc;
use std::f64::consts::FRAC_PI_2;

/// The fixed frame every pose is given in.
pub const WORLD: &str = "world";

/// The pool's outline and the obstacles' colours (sRGB).
const POOL_RGB: (u8, u8, u8) = (111, 211, 255);
const OBSTACLE_RGB: (u8, u8, u8) = (154, 139, 112);

/// How long a link's line stays \[s\]: two record intervals, at least half a second, so
/// links flash rather than accumulate.
pub fn link_lifetime(record_hz: f64) -> Duration {
    Duration::from_secs((2.0 / record_hz).max(0.5))
}

/// The ENU position \[m\] of the body origin in a trajectory row.
pub fn row_position(row: &[f64]) -> [f64; 3] {
    enu::position([row[col::X], row[col::Y], row[col::Z]])
}

/// The pose of vehicle `name` from its trajectory row, as a transform from `world`.
pub fn transform(stamp: Time, name: &str, row: &[f64]) -> TransformStamped {
    TransformStamped {
        header: Header {
            stamp,
            frame_id: WORLD.to_string(),
        },
        child_frame_id: name.to_string(),
        transform: Transform {
            translation: row_position(row).into(),
            rotation: enu::attitude(row[col::ROLL], row[col::PITCH], row[col::YAW]).into(),
        },
    }
}

/// The still scene at `stamp`: the hulls of the vehicles `ids` (frame-locked to their frames),
/// the pool's outline and the obstacles.
pub fn still_scene(desc: &WorldDesc, ids: &[usize], stamp: Time) -> SceneUpdate {
    let mut entities: Vec<SceneEntity> = ids.iter().map(|&i| hull(desc, i, stamp)).collect();
    entities.push(pool(desc, stamp));
    entities.extend(
        desc.geometry
            .obstacles
            .iter()
            .map(|o| obstacle(&crate::replay::capture::obstacle_meta(o), stamp)),
    );
    SceneUpdate {
        deletions: Empty,
        entities,
    }
}

/// Vehicle `i`'s hull: a cylinder along its body x axis (the hull's length), as wide and as
/// high as the hull, in the group's colour, with the vehicle's name above it.
fn hull(desc: &WorldDesc, i: usize, stamp: Time) -> SceneEntity {
    let v = &desc.vehicles[i];
    let h = v.model.params.body.hull_size;
    let colour = shoal_output::plot::rgb(v.group);
    let mut e = SceneEntity::new(stamp, &v.name, format!("hull/{}", v.name));
    e.frame_locked = true;
    e.metadata = vec![
        KeyValuePair {
            key: "group".into(),
            value: desc.groups[v.group].clone(),
        },
        KeyValuePair {
            key: "id".into(),
            value: i.to_string(),
        },
    ];
    // The cylinder's axis (local z) turned onto body x: a quarter turn about y.
    let along_x = Quat::from_axis_angle(&Vec3::y_axis(), FRAC_PI_2);
    e.cylinders.push(CylinderPrimitive {
        pose: Pose {
            position: Point::default(),
            orientation: along_x.into(),
        },
        size: [h.z, h.y, h.x].into(),
        bottom_scale: 1.0,
        top_scale: 1.0,
        color: Color::rgb(colour, 1.0),
    });
    e.texts.push(TextPrimitive {
        pose: Pose::at([0.0, 0.0, h.z]),
        billboard: true,
        font_size: 14.0,
        scale_invariant: true,
        color: Color::rgb((255, 255, 255), 1.0),
        text: v.name.clone(),
    });
    e
}

/// The pool's outline: the twelve edges of its box, the surface at z = 0.
fn pool(desc: &WorldDesc, stamp: Time) -> SceneEntity {
    let p = desc.geometry.pool;
    let corner = |n: f64, e: f64, d: f64| Point::from(enu::position([n, e, d]));
    let mut points = Vec::with_capacity(24);
    for (a, b) in [(0.0, 0.0), (p.x, 0.0), (p.x, p.y), (0.0, p.y)]
        .iter()
        .zip([(p.x, 0.0), (p.x, p.y), (0.0, p.y), (0.0, 0.0)])
    {
        for d in [0.0, p.z] {
            points.push(corner(a.0, a.1, d));
            points.push(corner(b.0, b.1, d));
        }
        points.push(corner(a.0, a.1, 0.0));
        points.push(corner(a.0, a.1, p.z));
    }
    let mut e = SceneEntity::new(stamp, WORLD, "pool".into());
    e.lines.push(LinePrimitive {
        kind: LINE_LIST,
        pose: Pose::at([0.0; 3]),
        thickness: 2.0,
        scale_invariant: true,
        points,
        color: Color::rgb(POOL_RGB, 1.0),
        colors: Vec::new(),
        indices: Vec::new(),
    });
    e
}

/// An obstacle as the replay describes it (NED), in ENU.
fn obstacle(o: &ObstacleMeta, stamp: Time) -> SceneEntity {
    let [x, y, z, w] = o.rotation;
    let local = Quat::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
    let orientation = enu::ned_to_enu() * local;
    let pose = |q: Quat| Pose {
        position: enu::position(o.position).into(),
        orientation: q.into(),
    };
    let color = Color::rgb(OBSTACLE_RGB, 0.9);
    let r = o.radius.unwrap_or(0.0);
    let mut e = SceneEntity::new(stamp, WORLD, format!("obstacle/{}", o.name));
    match o.kind.as_str() {
        "sphere" => e.spheres.push(SpherePrimitive {
            pose: pose(orientation),
            size: [2.0 * r; 3].into(),
            color,
        }),
        "cylinder" | "capsule" => {
            // Foxglove's cylinders stand on local z; parry's cylinder on local y (a quarter
            // turn about x), its capsule on local z (drawn as a cylinder of its whole length).
            let (q, h) = if o.kind == "cylinder" {
                let y_up = Quat::from_axis_angle(&Vec3::x_axis(), -FRAC_PI_2);
                (orientation * y_up, o.height.unwrap_or(0.0))
            } else {
                (orientation, o.height.unwrap_or(0.0) + 2.0 * r)
            };
            e.cylinders.push(CylinderPrimitive {
                pose: pose(q),
                size: [2.0 * r, 2.0 * r, h].into(),
                bottom_scale: 1.0,
                top_scale: 1.0,
                color,
            });
        }
        _ => e.cubes.push(CubePrimitive {
            pose: pose(orientation),
            size: o.size.unwrap_or([0.2; 3]).into(),
            color,
        }),
    }
    e
}

/// The dash and the gap of an acknowledgement's line \[m\].
const ACK_DASH: (f64, f64) = (0.2, 0.12);

/// Most dashes of one line (a line longer than 3.7 m gets longer dashes): at most 24 points,
/// 0.6 kB more than a frame's line.
const MAX_DASHES: usize = 12;

/// The points of a line from `a` to `b` \[m\] as `LINE_LIST` pairs: one pair for a frame;
/// for an acknowledgement, a pair per dash ([`ACK_DASH`]) — foxglove's lines have no dash
/// pattern, and the GIF and `replay.html` draw acknowledgements dashed.
fn link_points(a: [f64; 3], b: [f64; 3], ack: bool) -> Vec<Point> {
    let (a, b) = (Vec3::from(a), Vec3::from(b));
    let length = (b - a).norm();
    let (dash, gap) = ACK_DASH;
    let dashes = ((length + gap) / (dash + gap)).floor() as usize;
    let point = |v: Vec3| Point::from([v.x, v.y, v.z]);
    if !ack || dashes < 2 {
        return vec![point(a), point(b)];
    }
    let n = dashes.min(MAX_DASHES);
    // n dashes and n − 1 gaps in their proportion fill the line exactly.
    let unit = length / (n as f64 * dash + (n - 1) as f64 * gap);
    let along = |s: f64| a + (b - a) * (s / length);
    (0..n)
        .flat_map(|k| {
            let s = k as f64 * (dash + gap) * unit;
            [point(along(s)), point(along(s + dash * unit))]
        })
        .collect()
}

/// The links of the attempts `frames` at `stamp`: a line each from the sender to the
/// receiver where `position` puts them (ENU \[m\]), numbered on from `first`; the lines of
/// acknowledgements dashed ([`crate::link_key::ACK_PROSE`]).
pub fn links(
    frames: &[Heard],
    names: &[String],
    position: impl Fn(u32) -> Option<[f64; 3]>,
    stamp: Time,
    lifetime: Duration,
    first: u64,
) -> SceneUpdate {
    let mut entities = Vec::with_capacity(frames.len());
    for (k, h) in (first..).zip(frames) {
        let (Some(a), Some(b)) = (position(h.from), position(h.to)) else {
            continue;
        };
        let o = h.outcome;
        let s = style(o);
        let name = |i: u32| names.get(i as usize).cloned().unwrap_or_default();
        let mut e = SceneEntity::new(stamp, WORLD, format!("link/{k}"));
        e.lifetime = lifetime;
        e.metadata = vec![
            KeyValuePair {
                key: "outcome".into(),
                value: s.label.into(),
            },
            KeyValuePair {
                key: "sender".into(),
                value: name(h.from),
            },
            KeyValuePair {
                key: "receiver".into(),
                value: name(h.to),
            },
            KeyValuePair {
                key: "frame".into(),
                value: if h.ack { "acknowledgement" } else { "data" }.into(),
            },
        ];
        e.lines.push(LinePrimitive {
            kind: LINE_LIST,
            pose: Pose::at([0.0; 3]),
            thickness: if o == Outcome::Delivered { 3.0 } else { 1.5 },
            scale_invariant: true,
            points: link_points(a, b, h.ack),
            color: Color::rgb(s.rgb, if o == Outcome::Delivered { 1.0 } else { 0.6 }),
            colors: Vec::new(),
            indices: Vec::new(),
        });
        entities.push(e);
    }
    SceneUpdate {
        deletions: Empty,
        entities,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hull_lies_along_the_body_x_axis() {
        let along_x = Quat::from_axis_angle(&Vec3::y_axis(), FRAC_PI_2);
        let axis = along_x * Vec3::z();
        assert!((axis - Vec3::x()).norm() < 1e-12);
        // size.x is the extent along the primitive's x, which the turn puts on body −z.
        assert!((along_x * Vec3::x() + Vec3::z()).norm() < 1e-12);
    }

    #[test]
    fn links_last_two_samples_or_half_a_second() {
        assert_eq!(
            link_lifetime(10.0),
            Duration {
                sec: 0,
                nanosec: 500_000_000
            }
        );
        assert_eq!(link_lifetime(1.0), Duration { sec: 2, nanosec: 0 });
    }

    #[test]
    fn a_row_places_its_frame_in_enu() {
        let mut row = vec![0.0; shoal_sim::recorder::FIXED.len()];
        (row[col::X], row[col::Y], row[col::Z]) = (1.0, 2.0, 0.5);
        row[col::YAW] = FRAC_PI_2;
        let t = transform(Time::default(), "a", &row);
        assert_eq!(t.transform.translation, [2.0, 1.0, -0.5].into());
        assert!(t.transform.rotation.w > 1.0 - 1e-12, "{t:?}");
        assert_eq!(
            (t.header.frame_id.as_str(), t.child_frame_id.as_str()),
            ("world", "a")
        );
    }
}
