//! Static geometry of a world with parry3d: the pool (walls and floor as half-spaces; the
//! surface is open), obstacles, hull contacts with a swept test so that no hull tunnels
//! through thin obstacles, overlap tests for placement, and line-of-sight rays.
//!
//! parry ≥ 0.2x uses glam types; this module converts at its boundary so the rest of shoal
//! speaks nalgebra only.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query::{self, Ray, RayCast, ShapeCastOptions};
use parry3d_f64::shape::{Cuboid, HalfSpace, Shape, SharedShape};
use shoal_model::math::{Quat, Vec3};

/// nalgebra → parry vector.
#[inline]
pub fn to_vector(v: &Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// parry → nalgebra vector.
#[inline]
pub fn from_vector(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// nalgebra position + attitude → parry pose.
#[inline]
pub fn to_pose(p: &Vec3, q: &Quat) -> Pose {
    let c = q.quaternion().coords; // (i, j, k, w)
    Pose::from_parts(to_vector(p), Rotation::from_xyzw(c.x, c.y, c.z, c.w))
}

/// A static obstacle.
#[derive(Clone)]
pub struct Obstacle {
    /// Name (for statistics and messages).
    pub name: String,
    /// Shape in its local frame.
    pub shape: SharedShape,
    /// Pose in the world.
    pub pose: Pose,
    /// World-space bounding box.
    pub aabb: Aabb,
}

impl Obstacle {
    /// The obstacle's outline seen from above: its projection on the horizontal plane as a
    /// convex polygon of `n` support points, world (x, y) \[m\]. Falls back to the bounding box
    /// for shapes without a support map.
    pub fn top_outline(&self, n: usize) -> Vec<(f64, f64)> {
        match self.shape.as_support_map() {
            Some(sm) => (0..n.max(3))
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / n.max(3) as f64;
                    let p = sm.support_point(&self.pose, Vector::new(a.cos(), a.sin(), 0.0));
                    (p.x, p.y)
                })
                .collect(),
            None => {
                let (lo, hi) = (self.aabb.mins, self.aabb.maxs);
                vec![(lo.x, lo.y), (hi.x, lo.y), (hi.x, hi.y), (lo.x, hi.y)]
            }
        }
    }
}

impl std::fmt::Debug for Obstacle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Obstacle")
            .field("name", &self.name)
            .field("aabb", &self.aabb)
            .finish()
    }
}

/// A contact of a hull with the static world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullContact {
    /// Unit normal in the world frame pointing out of the obstacle, into the hull: moving the
    /// hull along it by `depth` separates them.
    pub normal: Vec3,
    /// Penetration depth \[m\] (> 0 when overlapping).
    pub depth: f64,
    /// Index of the obstacle, or `None` for a pool wall or the floor.
    pub obstacle: Option<usize>,
}

/// The pool and its obstacles.
#[derive(Clone, Debug)]
pub struct Geometry {
    /// Pool length, width, depth \[m\] (corner at the origin, surface at z = 0).
    pub pool: Vec3,
    walls: Vec<(Pose, HalfSpace)>,
    /// Obstacles.
    pub obstacles: Vec<Obstacle>,
}

/// The hull collision shape: a box of the hull's outer extents \[m\].
pub fn hull_shape(hull_size: &Vec3) -> Cuboid {
    Cuboid::new(to_vector(&(hull_size * 0.5)))
}

impl Geometry {
    /// A pool of `size` \[m\] with `obstacles`.
    pub fn new(size: Vec3, obstacles: Vec<Obstacle>) -> Self {
        let wall = |p: Vector, n: Vector| (Pose::from_translation(p), HalfSpace::new(n));
        // A half-space is solid where `x·n ≤ 0`: the normals point out of the walls, into
        // the pool.
        let walls = vec![
            wall(Vector::ZERO, Vector::new(1.0, 0.0, 0.0)),
            wall(Vector::new(size.x, 0.0, 0.0), Vector::new(-1.0, 0.0, 0.0)),
            wall(Vector::ZERO, Vector::new(0.0, 1.0, 0.0)),
            wall(Vector::new(0.0, size.y, 0.0), Vector::new(0.0, -1.0, 0.0)),
            wall(Vector::new(0.0, 0.0, size.z), Vector::new(0.0, 0.0, -1.0)),
        ];
        Self {
            pool: size,
            walls,
            obstacles,
        }
    }

    /// An obstacle of `shape` at world `position` \[m\] with attitude `attitude`.
    pub fn obstacle(name: &str, shape: SharedShape, position: &Vec3, attitude: &Quat) -> Obstacle {
        let pose = to_pose(position, attitude);
        let aabb = shape.compute_aabb(&pose);
        Obstacle {
            name: name.into(),
            shape,
            pose,
            aabb,
        }
    }

    fn pool_interior(&self) -> Aabb {
        Aabb::new(
            Vector::new(0.0, 0.0, f64::NEG_INFINITY),
            to_vector(&self.pool),
        )
    }

    /// Whether nothing — walls, floor, obstacles — lies within the axis-aligned box of
    /// half-width `reach` \[m\] around `center` (world frame \[m\]), judged by bounding boxes
    /// only: `true` means that a hull within `reach` of `center` (its bounding sphere plus a
    /// contact margin) has no contact, whatever its attitude, and [`Geometry::contacts`] would
    /// find none; `false` means that it may have one. Costs a few comparisons, so a swarm in
    /// open water skips the shape queries.
    pub fn clear_around(&self, center: &Vec3, reach: f64) -> bool {
        let c = to_vector(center);
        let r = Vector::new(reach, reach, reach);
        let aabb = Aabb::new(c - r, c + r);
        self.pool_interior().contains(&aabb)
            && !self.obstacles.iter().any(|ob| ob.aabb.intersects(&aabb))
    }

    /// Every contact of `hull` at `pose` with walls, floor and obstacles closer than `margin`
    /// \[m\], appended to `out` (`depth` < 0 for a gap smaller than the margin).
    pub fn contacts(&self, hull: &Cuboid, pose: &Pose, margin: f64, out: &mut Vec<HullContact>) {
        let aabb = hull.compute_aabb(pose).loosened(margin);
        let interior = self.pool_interior();
        if !interior.contains(&aabb) {
            for (wp, hs) in &self.walls {
                push_contact(pose, hull, wp, hs, None, margin, out);
            }
        }
        for (i, ob) in self.obstacles.iter().enumerate() {
            if ob.aabb.intersects(&aabb) {
                push_contact(pose, hull, &ob.pose, &*ob.shape, Some(i), margin, out);
            }
        }
    }

    /// Earliest fraction `t ∈ [0, 1)` of the straight move `from → from + delta` \[m\] at which
    /// `hull` touches walls, floor or an obstacle, with the surface normal there. Impacts at
    /// t = 0 with separating motion are ignored.
    pub fn first_hit(&self, hull: &Cuboid, from: &Pose, delta: &Vec3) -> Option<(f64, Vec3)> {
        let vel = to_vector(delta);
        let opts = ShapeCastOptions {
            max_time_of_impact: 1.0,
            target_distance: 0.0,
            stop_at_penetration: false,
            compute_impact_geometry_on_penetration: true,
        };
        let swept = hull
            .compute_aabb(from)
            .merged(&hull.compute_aabb(&from.append_translation(vel)));
        let mut best: Option<(f64, Vec3)> = None;
        // The static shape goes first: parry 0.31 mishandles (support map, half-space) pairs
        // in the other order. normal1 is then in the static shape's frame, pointing out of it.
        let mut consider = |pose: &Pose, shape: &dyn Shape| {
            let hit = query::cast_shapes(pose, Vector::ZERO, shape, from, vel, hull, opts);
            if let Ok(Some(h)) = hit
                && h.time_of_impact < 1.0
                && best.is_none_or(|b| h.time_of_impact < b.0)
            {
                best = Some((h.time_of_impact, from_vector(pose.rotation * h.normal1)));
            }
        };
        if !self.pool_interior().contains(&swept) {
            for (wp, hs) in &self.walls {
                consider(wp, hs);
            }
        }
        for ob in &self.obstacles {
            if ob.aabb.intersects(&swept) {
                consider(&ob.pose, &*ob.shape);
            }
        }
        best
    }

    /// Whether `hull` at `pose` lies inside the pool walls and above the floor (it may stick
    /// out of the surface).
    pub fn inside_pool(&self, hull: &Cuboid, pose: &Pose) -> bool {
        self.pool_interior().contains(&hull.compute_aabb(pose))
    }

    /// Index of the first obstacle that `hull` at `pose` intersects.
    pub fn overlapping_obstacle(&self, hull: &Cuboid, pose: &Pose) -> Option<usize> {
        let aabb = hull.compute_aabb(pose);
        self.obstacles.iter().position(|ob| {
            ob.aabb.intersects(&aabb)
                && query::intersection_test(pose, hull, &ob.pose, &*ob.shape)
                    .is_ok_and(|i| i.intersecting)
        })
    }

    /// Whether the segment `a → b` \[m\] crosses no wall, floor or obstacle.
    pub fn line_of_sight(&self, a: &Vec3, b: &Vec3) -> bool {
        let d = b - a;
        // |d| (the root of |d|²) is 0 exactly when |d|² is.
        if d.norm_squared() == 0.0 {
            return true;
        }
        let inside = |p: &Vec3| {
            p.x >= 0.0
                && p.y >= 0.0
                && p.x <= self.pool.x
                && p.y <= self.pool.y
                && p.z <= self.pool.z
        };
        if !inside(a) || !inside(b) {
            return false;
        }
        if self.obstacles.is_empty() {
            // The common case of the medium's many rays: nothing to cast against.
            return true;
        }
        let len = d.norm();
        let ray = Ray::new(to_vector(a), to_vector(&(d / len)));
        let seg = Aabb::new(to_vector(&a.inf(b)), to_vector(&a.sup(b)));
        !self
            .obstacles
            .iter()
            .any(|ob| ob.aabb.intersects(&seg) && ob.shape.intersects_ray(&ob.pose, &ray, len))
    }
}

/// Whether the segment `a → b` \[m\] passes through a hull box of `hull_size` \[m\] at `position`
/// with `attitude`.
pub fn segment_hits_hull(
    a: &Vec3,
    b: &Vec3,
    hull_size: &Vec3,
    position: &Vec3,
    attitude: &Quat,
) -> bool {
    let d = b - a;
    let len = d.norm();
    if len == 0.0 {
        return false;
    }
    // Cheap reject: the hull's bounding sphere against the segment.
    let r = 0.5 * hull_size.norm();
    let s = ((position - a).dot(&d) / (len * len)).clamp(0.0, 1.0);
    if (a + d * s - position).norm() > r {
        return false;
    }
    let ray = Ray::new(to_vector(a), to_vector(&(d / len)));
    hull_shape(hull_size).intersects_ray(&to_pose(position, attitude), &ray, len)
}

/// Whether two hulls at their poses intersect.
pub fn hulls_intersect(h1: &Cuboid, p1: &Pose, h2: &Cuboid, p2: &Pose) -> bool {
    query::intersection_test(p1, h1, p2, h2).is_ok_and(|i| i.intersecting)
}

fn push_contact(
    pose: &Pose,
    hull: &Cuboid,
    other_pose: &Pose,
    other: &dyn Shape,
    obstacle: Option<usize>,
    margin: f64,
    out: &mut Vec<HullContact>,
) {
    // Static shape first (see `first_hit`): normal1 points out of it, towards the hull.
    if let Ok(Some(c)) = query::contact(other_pose, other, pose, hull, margin)
        && c.dist < margin
    {
        out.push(HullContact {
            normal: from_vector(c.normal1),
            depth: -c.dist,
            obstacle,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool() -> Geometry {
        let plate = Geometry::obstacle(
            "plate",
            SharedShape::cuboid(0.0005, 1.0, 1.0),
            &Vec3::new(5.0, 2.0, 1.0),
            &Quat::identity(),
        );
        Geometry::new(Vec3::new(10.0, 4.0, 2.0), vec![plate])
    }

    #[test]
    fn clear_around_holds_exactly_where_no_attitude_can_touch() {
        let g = pool();
        let size = Vec3::new(0.27, 0.156, 0.182);
        let hull = hull_shape(&size);
        let margin = 1e-3;
        let reach = 0.5 * size.norm() + margin;
        // Any attitude, sampled: where the box is clear, no contact within the margin.
        let attitudes: Vec<Quat> = (0..24)
            .map(|k| {
                let a = f64::from(k) * 0.37;
                Quat::from_euler_angles(a, 2.0 * a, 3.0 * a)
            })
            .collect();
        let mut clear = 0;
        for x in [0.05, 0.3, 2.0, 4.7, 4.85, 9.9] {
            for z in [-0.1, 0.2, 1.0, 1.8, 1.95] {
                let p = Vec3::new(x, 2.0, z);
                if !g.clear_around(&p, reach) {
                    continue;
                }
                clear += 1;
                for q in &attitudes {
                    let mut c = Vec::new();
                    g.contacts(&hull, &to_pose(&p, q), margin, &mut c);
                    assert!(c.is_empty(), "{p:?} {q:?}: {c:?}");
                }
            }
        }
        assert!(clear >= 6, "{clear}");
        // Near the floor, a wall and the plate it is not clear.
        for p in [
            Vec3::new(2.0, 2.0, 1.95),
            Vec3::new(0.05, 2.0, 1.0),
            Vec3::new(4.85, 2.0, 1.0),
        ] {
            assert!(!g.clear_around(&p, reach), "{p:?}");
        }
    }

    #[test]
    fn floor_contact_pushes_up() {
        let g = pool();
        let hull = hull_shape(&Vec3::new(0.27, 0.156, 0.182));
        let pose = to_pose(&Vec3::new(2.0, 2.0, 1.95), &Quat::identity());
        let mut c = Vec::new();
        g.contacts(&hull, &pose, 0.0, &mut c);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(
            (c[0].normal - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-9,
            "{c:?}"
        );
        assert!((c[0].depth - (1.95 + 0.091 - 2.0)).abs() < 1e-9);
    }

    #[test]
    fn swept_test_catches_a_thin_plate() {
        let g = pool();
        let hull = hull_shape(&Vec3::new(0.27, 0.156, 0.182));
        let from = to_pose(&Vec3::new(4.5, 2.0, 1.0), &Quat::identity());
        // 1 m in one step would jump clean over a 1 mm plate.
        let hit = g
            .first_hit(&hull, &from, &Vec3::new(1.0, 0.0, 0.0))
            .expect("hit");
        let expected = (5.0 - 0.0005 - 0.135 - 4.5) / 1.0;
        assert!((hit.0 - expected).abs() < 1e-6, "{hit:?}");
        assert!((hit.1 - Vec3::new(-1.0, 0.0, 0.0)).norm() < 1e-6);
        let mut c = Vec::new();
        g.contacts(
            &hull,
            &to_pose(&Vec3::new(5.5, 2.0, 1.0), &Quat::identity()),
            0.0,
            &mut c,
        );
        assert!(c.is_empty(), "the end pose alone shows nothing");
    }

    #[test]
    fn top_outline_of_a_vertical_cylinder_is_a_circle() {
        let c = Geometry::obstacle(
            "c",
            SharedShape::cylinder(1.0, 0.3),
            &Vec3::new(2.0, 1.0, 1.0),
            &Quat::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2),
        );
        for (x, y) in c.top_outline(32) {
            assert!(((x - 2.0).hypot(y - 1.0) - 0.3).abs() < 1e-9);
        }
    }

    #[test]
    fn segment_through_a_hull() {
        let size = Vec3::new(0.27, 0.156, 0.182);
        let c = Vec3::new(1.0, 0.0, 0.0);
        let q = Quat::identity();
        assert!(segment_hits_hull(
            &Vec3::zeros(),
            &Vec3::new(2.0, 0.0, 0.0),
            &size,
            &c,
            &q
        ));
        assert!(!segment_hits_hull(
            &Vec3::new(0.0, 0.2, 0.0),
            &Vec3::new(2.0, 0.2, 0.0),
            &size,
            &c,
            &q
        ));
        assert!(!segment_hits_hull(
            &Vec3::zeros(),
            &Vec3::new(0.8, 0.0, 0.0),
            &size,
            &c,
            &q
        ));
    }

    #[test]
    fn line_of_sight_blocked_by_obstacle() {
        let g = pool();
        assert!(!g.line_of_sight(&Vec3::new(4.0, 2.0, 1.0), &Vec3::new(6.0, 2.0, 1.0)));
        assert!(g.line_of_sight(&Vec3::new(4.0, 3.5, 1.0), &Vec3::new(6.0, 3.5, 1.0)));
        assert!(g.line_of_sight(&Vec3::new(1.0, 1.0, 1.0), &Vec3::new(2.0, 2.0, 1.5)));
    }

    /// Without obstacles a ray is clear exactly when both ends are inside the pool (walls and
    /// floor), whatever its length; a ray of length zero is clear wherever it is — the same
    /// answers as with an obstacle away from the ray.
    #[test]
    fn line_of_sight_without_obstacles_checks_the_ends_only() {
        let open = Geometry::new(Vec3::new(10.0, 4.0, 2.0), Vec::new());
        let far = Geometry::new(
            Vec3::new(10.0, 4.0, 2.0),
            vec![Geometry::obstacle(
                "far",
                SharedShape::cuboid(0.1, 0.1, 0.1),
                &Vec3::new(9.0, 3.5, 1.9),
                &Quat::identity(),
            )],
        );
        let cases = [
            (Vec3::new(0.5, 0.5, 0.5), Vec3::new(8.0, 3.0, 1.5), true),
            (Vec3::new(0.5, 0.5, 0.5), Vec3::new(10.5, 3.0, 1.5), false),
            (Vec3::new(0.5, -0.1, 0.5), Vec3::new(8.0, 3.0, 1.5), false),
            (Vec3::new(0.5, 0.5, 0.5), Vec3::new(8.0, 3.0, 2.5), false),
            (Vec3::new(12.0, 5.0, 3.0), Vec3::new(12.0, 5.0, 3.0), true),
            (Vec3::new(3.0, 2.0, 1.0), Vec3::new(3.0, 2.0, 1.0), true),
        ];
        for (a, b, clear) in cases {
            assert_eq!(open.line_of_sight(&a, &b), clear, "{a:?} → {b:?}");
            assert_eq!(
                far.line_of_sight(&a, &b),
                clear,
                "{a:?} → {b:?}, obstacle away"
            );
        }
    }
}
