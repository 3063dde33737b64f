//! Vehicle groups: the model, mission and behaviour of a group, then its vehicles placed (one
//! position, a grid, or random without overlaps) inside the pool and clear of obstacles, and
//! the whole swarm checked for overlapping hulls.

use super::behaviour::validate_behaviour;
use super::mission::mission;
use super::names::valid_service_word;
use super::validator::Validator;
use super::vehicle::vehicle_spec;
use crate::access::LinkParams;
use crate::cancel::{Cancel, Interrupted};
use crate::desc::VehicleDesc;
use crate::error::{FieldPath, ProblemKind};
use crate::geometry::{Geometry, hull_shape, hulls_intersect, to_pose};
use crate::spec::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use shoal_model::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// The base name of a group: its `name`, or `<preset>-g<index>`.
fn group_name(g: &VehicleGroupSpec, gi: usize) -> String {
    g.name
        .clone()
        .unwrap_or_else(|| format!("{}-g{gi}", g.preset.as_deref().unwrap_or("uauv2")))
}

/// Checks group `gi` (model, mission, behaviour, agent) and places its vehicles into `out`;
/// returns the group's base name.
pub(super) fn group(
    g: &VehicleGroupSpec,
    gi: usize,
    wf: &WorldFile,
    env: &Environment,
    geometry: &Geometry,
    v: &mut Validator<'_>,
    out: &mut Vec<VehicleDesc>,
    cancel: &Cancel,
) -> Result<String, Interrupted> {
    cancel.check()?;
    let base = &group_name(g, gi);
    let gp = FieldPath::root().key("vehicles").index(gi);
    let n0 = v.problems.len();
    v.field(&gp.key("heading_deg"), g.heading_deg);
    let Some(spec) = vehicle_spec((g.preset.as_deref(), g.model.as_ref(), &g.link()), &gp, v)
    else {
        return Ok(base.clone());
    };
    let params = spec.to_params();
    // The control period must be a whole number of physics steps.
    let k = (params.control.period / wf.dt).round();
    if k < 1.0 || (k * wf.dt - params.control.period).abs() > 1e-9 * params.control.period.max(1.0)
    {
        v.push(
            ProblemKind::Invalid,
            &gp.key("model").key("control").key("period"),
            format!(
                "{} s is not a whole multiple of dt = {} s",
                params.control.period, wf.dt
            ),
        );
    }
    let link: Arc<[LinkParams]> = spec.modems.iter().map(ModemSpec::link).collect();
    let effects = spec.effects(&params);
    let model = Arc::new(VehicleModel::with_effects(params, effects, env.density));
    let mission = Arc::new(mission(g, &gp, wf, &model, v));
    if let Some(b) = &g.behaviour {
        validate_behaviour(b, &model, &gp.key("behaviour"), wf.duration, v);
    }
    if let Some(a) = &g.agent {
        if !valid_service_word(a) {
            v.push(
                ProblemKind::Invalid,
                &gp.key("agent"),
                format!("agent name `{a}`: use 1–64 letters, digits, `_`, `-` or `.`"),
            );
        }
        if g.behaviour.is_some() {
            v.push(
                ProblemKind::Invalid,
                &gp.key("behaviour"),
                "a group driven by an `agent` takes its setpoints and frames from the agent: \
                 give either `agent` or `behaviour`"
                    .into(),
            );
        }
        if !g.mission.is_empty() {
            v.push(
                ProblemKind::Invalid,
                &gp.key("mission"),
                "a group driven by an `agent` takes its setpoints from the agent (and from \
                 `[agents] fallback` while it is absent): remove `mission`"
                    .into(),
            );
        }
    }
    if v.problems.len() > n0 {
        return Ok(base.clone());
    }
    // Placement.

    let names = |i: usize| {
        if g.count == 1 {
            base.to_string()
        } else {
            format!("{base}-{i}")
        }
    };
    // Vehicle `i` of the group at `pos` with attitude `att`.
    let vehicle = |i: usize, pos: Vec3, att: Quat| VehicleDesc {
        name: names(i),
        group: gi,
        model: model.clone(),
        mission: mission.clone(),
        behaviour: g.behaviour.clone(),
        agent: g.agent.clone(),
        link: link.clone(),
        position: pos,
        attitude: att,
    };
    let choices = usize::from(g.position.is_some())
        + usize::from(g.grid.is_some())
        + usize::from(g.random.is_some());
    if choices != 1 {
        v.push(ProblemKind::Invalid, &gp, format!(
            "give exactly one placement: `position` (one vehicle), `grid` or `random` ({} given)", choices));
        return Ok(base.clone());
    }
    let hull = hull_shape(&model.params.body.hull_size);
    let pool = geometry.pool;
    let yaw0 = g.heading_deg.to_radians();
    let mut place = |v: &mut Validator<'_>,
                     field: FieldPath,
                     i: usize,
                     pos: Vec3,
                     yaw: f64|
     -> bool {
        let att = quat_from_rpy(0.0, 0.0, yaw);
        let pose = to_pose(&pos, &att);
        if !geometry.inside_pool(&hull, &pose) {
            v.push(ProblemKind::Outside, &field, format!(
                "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m is not inside the pool: its hull must lie within 0 ≤ x ≤ {}, 0 ≤ y ≤ {} and above the floor at z = {} m",
                names(i), pos.x, pos.y, pos.z, pool.x, pool.y, pool.z));
            return false;
        }
        if let Some(k) = geometry.overlapping_obstacle(&hull, &pose) {
            v.push(
                ProblemKind::Overlap,
                &field,
                format!(
                    "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m overlaps obstacle `{}`",
                    names(i),
                    pos.x,
                    pos.y,
                    pos.z,
                    geometry.obstacles[k].name
                ),
            );
            return false;
        }
        out.push(vehicle(i, pos, att));
        true
    };
    if let Some(p) = g.position {
        if !v.fields(&gp.key("position"), &p) {
            return Ok(base.clone());
        }
        if g.count != 1 {
            v.push(
                ProblemKind::Invalid,
                &gp.key("count"),
                format!(
                    "`position` places one vehicle but count = {}; use `grid` or `random`",
                    g.count
                ),
            );
            return Ok(base.clone());
        }
        place(v, gp.key("position"), 0, Vec3::from(p), yaw0);
    } else if let Some(grid) = &g.grid {
        let gr = gp.key("grid");
        let ok = v.fields(&gr.key("origin"), &grid.origin)
            & v.fields(&gr.key("spacing"), &grid.spacing)
            & v.field(&gr.key("columns"), grid.columns as f64);
        if !ok {
            return Ok(base.clone());
        }
        for i in 0..g.count {
            cancel.check()?;
            let (c, r) = ((i % grid.columns) as f64, (i / grid.columns) as f64);
            let pos =
                Vec3::from(grid.origin) + Vec3::new(c * grid.spacing[0], r * grid.spacing[1], 0.0);
            if !place(v, gr.clone(), i, pos, yaw0) {
                return Ok(base.clone());
            }
        }
    } else if let Some(r) = &g.random {
        let rp = gp.key("random");
        let ok = v.fields(&rp.key("min"), &r.min) & v.fields(&rp.key("max"), &r.max);
        if !ok {
            return Ok(base.clone());
        }
        if (0..3).any(|k| r.max[k] < r.min[k]) {
            v.push(
                ProblemKind::Range,
                &rp.key("max"),
                "each coordinate of `max` must be ≥ the same coordinate of `min`".into(),
            );
            return Ok(base.clone());
        }
        // Placement draws from its own stream of the world seed, so vehicle RNG streams are
        // unaffected by how many tries placement needed.
        let mut rng = ChaCha8Rng::seed_from_u64(wf.seed);
        rng.set_stream(u64::MAX - gi as u64);
        let others: Vec<(Cuboid3, parry3d_f64::math::Pose)> = out
            .iter()
            .map(|d| {
                (
                    hull_shape(&d.model.params.body.hull_size),
                    to_pose(&d.position, &d.attitude),
                )
            })
            .collect();
        let mut mine: Vec<parry3d_f64::math::Pose> = Vec::new();
        for i in 0..g.count {
            let mut placed = false;
            for _ in 0..1000 {
                // Each try compares with every vehicle placed so far: look before each one.
                cancel.check()?;
                let u: [f64; 3] = [rng.random(), rng.random(), rng.random()];
                let pos = Vec3::new(
                    r.min[0] + u[0] * (r.max[0] - r.min[0]),
                    r.min[1] + u[1] * (r.max[1] - r.min[1]),
                    r.min[2] + u[2] * (r.max[2] - r.min[2]),
                );
                let yaw = if r.random_heading {
                    rng.random::<f64>() * std::f64::consts::TAU
                } else {
                    yaw0
                };
                let att = quat_from_rpy(0.0, 0.0, yaw);
                let pose = to_pose(&pos, &att);
                if !geometry.inside_pool(&hull, &pose)
                    || geometry.overlapping_obstacle(&hull, &pose).is_some()
                {
                    continue;
                }
                if mine.iter().any(|q| hulls_intersect(&hull, &pose, &hull, q))
                    || others
                        .iter()
                        .any(|(h, q)| hulls_intersect(&hull, &pose, h, q))
                {
                    continue;
                }
                mine.push(pose);
                out.push(vehicle(i, pos, att));
                placed = true;
                break;
            }
            if !placed {
                v.push(ProblemKind::Overlap, &rp, format!(
                    "could place only {i} of {} vehicles in the box without overlaps (1000 tries for the next); enlarge the box or lower `count`",
                    g.count));
                return Ok(base.clone());
            }
        }
    }
    Ok(base.clone())
}

type Cuboid3 = parry3d_f64::shape::Cuboid;

/// Rejects overlapping vehicles (spatial hash, so large swarms stay fast).
pub(super) fn check_overlaps(
    vehicles: &[VehicleDesc],
    v: &mut Validator<'_>,
    cancel: &Cancel,
) -> Result<(), Interrupted> {
    let Some(cell) = vehicles
        .iter()
        .map(|d| d.model.params.body.hull_size.norm())
        .reduce(f64::max)
    else {
        return Ok(());
    };
    let key = |p: &Vec3| {
        (
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        )
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    let shapes: Vec<_> = vehicles
        .iter()
        .map(|d| {
            (
                hull_shape(&d.model.params.body.hull_size),
                to_pose(&d.position, &d.attitude),
            )
        })
        .collect();
    for (i, d) in vehicles.iter().enumerate() {
        cancel.check()?;
        let (kx, ky, kz) = key(&d.position);
        let mut hit = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&(kx + dx, ky + dy, kz + dz))
                        .map_or(&[][..], |c| c.as_slice())
                    {
                        if hulls_intersect(&shapes[i].0, &shapes[i].1, &shapes[j].0, &shapes[j].1) {
                            hit = Some(j);
                            break 'search;
                        }
                    }
                }
            }
        }
        if let Some(j) = hit {
            let gp = FieldPath::root().key("vehicles").index(d.group);
            v.push(ProblemKind::Overlap, &gp, format!(
                "vehicle `{}` at ({:.3}, {:.3}, {:.3}) m overlaps vehicle `{}` at ({:.3}, {:.3}, {:.3}) m; hulls need room ({} m long)",
                d.name, d.position.x, d.position.y, d.position.z,
                vehicles[j].name, vehicles[j].position.x, vehicles[j].position.y, vehicles[j].position.z,
                d.model.params.body.hull_size.x));
            return Ok(());
        }
        grid.entry((kx, ky, kz)).or_default().push(i);
    }
    Ok(())
}
