//! The whole world: top-level fields, pool, water, agents and output are checked, then the
//! obstacles, then every vehicle group; the result is a [`WorldDesc`].

use super::advice::advice;
use super::memory::{self, MemoryBudget};
use super::messages::suggest;
use super::names::{service_word, valid_service_word};
use super::obstacles::obstacle;
use super::placement::{check_overlaps, group};
use super::validator::Validator;
use crate::cancel::{Cancel, Interrupted};
use crate::desc::{AgentsDesc, OutputDesc, Ros2Desc, WorldDesc};
use crate::error::{FieldPath, ProblemKind};
use crate::geometry::Geometry;
use crate::spec::*;
use shoal_model::optics::Ambient;
use shoal_model::prelude::*;
use std::path::{Path, PathBuf};

/// Most steps a run may take \[count\].
const MAX_STEPS: f64 = 1e10;

/// What is wrong with `duration` \[s\] at steps of `dt` \[s\] when the run would take more
/// than [`MAX_STEPS`] steps.
pub fn too_many_steps(duration: f64, dt: f64) -> Option<String> {
    (duration / dt > MAX_STEPS).then(|| {
        format!(
            "duration / dt = {duration} / {dt} = {:e} steps, more than 1e10; raise dt or shorten the run",
            duration / dt
        )
    })
}

pub(super) fn build(
    wf: &WorldFile,
    file: &Path,
    budget: Option<&MemoryBudget>,
    v: &mut Validator<'_>,
    cancel: &Cancel,
) -> Result<Option<WorldDesc>, Interrupted> {
    let root = FieldPath::root();
    v.field(&root.key("duration"), wf.duration);
    let dt_ok = v.field(&root.key("dt"), wf.dt);
    if dt_ok && let Some(message) = too_many_steps(wf.duration, wf.dt) {
        // Point at whichever of the two the file writes (dt when both are).
        let at = if v.sm.locate(&root.key("dt")).is_some() {
            "dt"
        } else {
            "duration"
        };
        v.push(ProblemKind::Range, &root.key(at), message);
    }
    let pool = root.key("pool");
    v.fields(&pool.key("size"), &wf.pool.size);
    let water = root.key("water");
    v.field(&water.key("density"), wf.water.density);
    v.fields(&water.key("current"), &wf.water.current);
    v.field(
        &water.key("ambient_irradiance"),
        wf.water.ambient_irradiance,
    );
    v.field(
        &water.key("diffuse_attenuation"),
        wf.water.diffuse_attenuation,
    );
    let attenuation = match &wf.water.attenuation {
        AttenuationSpec::Coefficient(c) => {
            v.field(&water.key("attenuation"), *c);
            *c
        }
        AttenuationSpec::Named(n) => match WATER_TYPES.iter().find(|w| w.0 == n) {
            Some(w) => w.1,
            None => {
                let names: Vec<&str> = WATER_TYPES.iter().map(|w| w.0).collect();
                let hint = suggest(n, &names)
                    .map(|s| format!(" — did you mean `{s}`?"))
                    .unwrap_or_default();
                v.push(
                    ProblemKind::Reference,
                    &water.key("attenuation"),
                    format!(
                        "unknown water type `{n}`{hint} (allowed: {}, or a number in 1/m)",
                        names.join(", ")
                    ),
                );
                0.0
            }
        },
    };
    let ag = root.key("agents");
    if let Some(pfx) = &wf.agents.prefix
        && !valid_service_word(pfx)
    {
        v.push(
            ProblemKind::Invalid,
            &ag.key("prefix"),
            format!("prefix `{pfx}`: use 1–64 letters, digits, `_`, `-` or `.`"),
        );
    }
    v.field(&ag.key("timeout"), wf.agents.timeout);
    v.field(&ag.key("attach_timeout"), wf.agents.attach_timeout);
    v.field(&ag.key("pace"), wf.agents.pace);
    if let Some(r) = &wf.ros2 {
        let rk = root.key("ros2");
        v.field(&rk.key("domain_id"), f64::from(r.domain_id));
        v.field(&rk.key("rtf"), r.rtf);
        let ok = r.namespace.len() <= 64
            && r.namespace.starts_with(|c: char| c.is_ascii_alphabetic())
            && r.namespace
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !ok {
            v.push(
                ProblemKind::Invalid,
                &rk.key("namespace"),
                format!(
                    "namespace `{}`: use 1–64 letters, digits or `_`, starting with a letter \
                     (a ROS 2 name)",
                    r.namespace
                ),
            );
        }
    }
    let out = root.key("output");
    v.field(&out.key("record_hz"), wf.output.record_hz);
    for (gi, g) in wf.vehicles.iter().enumerate() {
        v.field(&root.key("vehicles").index(gi).key("count"), g.count as f64);
    }
    if v.problems.is_empty() {
        // Before anything is placed: a count this machine cannot hold.
        memory::check(wf, budget, v);
    }
    if !v.problems.is_empty() {
        return Ok(None);
    }
    let env = Environment {
        density: wf.water.density,
        gravity: shoal_model::math::GRAVITY,
        current: Vec3::from(wf.water.current),
    };
    let pool_size = Vec3::from(wf.pool.size);

    // Obstacles.
    let mut obstacles = Vec::new();
    for (i, o) in wf.obstacles.iter().enumerate() {
        let p = root.key("obstacles").index(i);
        if let Some(ob) = obstacle(o, &p, i, v) {
            let lo = ob.aabb.mins;
            let hi = ob.aabb.maxs;
            if hi.x < 0.0
                || hi.y < 0.0
                || lo.x > pool_size.x
                || lo.y > pool_size.y
                || lo.z > pool_size.z
            {
                v.push(
                    ProblemKind::Outside,
                    &p.key("position"),
                    format!(
                        "obstacle `{}` lies entirely outside the pool (0…{} × 0…{} × 0…{} m)",
                        ob.name, pool_size.x, pool_size.y, pool_size.z
                    ),
                );
            }
            obstacles.push(ob);
        }
    }
    let geometry = Geometry::new(pool_size, obstacles);

    // Vehicle groups (the memory check above has bounded the total count).
    let mut vehicles = Vec::with_capacity(wf.vehicles.iter().map(|g| g.count).sum());
    let mut groups = Vec::new();
    for (gi, g) in wf.vehicles.iter().enumerate() {
        groups.push(group(g, gi, wf, &env, &geometry, v, &mut vehicles, cancel)?);
    }
    check_overlaps(&vehicles, v, cancel)?;
    super::behaviour::check_destinations(wf, &vehicles, v);
    if !v.problems.is_empty() {
        return Ok(None);
    }

    let name = wf.name.clone().unwrap_or_else(|| {
        file.file_stem()
            .map_or_else(|| "world".into(), |s| s.to_string_lossy().into_owned())
    });
    let mut agent_names: Vec<String> = vehicles.iter().filter_map(|d| d.agent.clone()).collect();
    // The ROS 2 bridge's agent last, so that the iceoryx2 agents keep the indices below it.
    agent_names.sort_by_key(|n| (n == ROS2_AGENT, n.clone()));
    agent_names.dedup();
    let ros2 = agent_names
        .iter()
        .position(|n| n == ROS2_AGENT)
        .map(|agent| {
            let r = wf.ros2.clone().unwrap_or_default();
            Ros2Desc {
                domain_id: r.domain_id,
                namespace: r.namespace,
                rtf: r.rtf,
                localhost_only: r.localhost_only,
                agent,
            }
        });
    let prefix = wf
        .agents
        .prefix
        .clone()
        .unwrap_or_else(|| service_word(&name));
    let agents = AgentsDesc {
        prefix,
        lockstep: wf.agents.timing == TimingSpec::Lockstep,
        timeout: wf.agents.timeout,
        attach_timeout: wf.agents.attach_timeout,
        fallback: wf.agents.fallback,
        grant_position: wf.agents.grant_position,
        pace: wf.agents.pace,
        names: agent_names,
        ros2,
    };
    let warnings = advice(&vehicles, &groups, &env);
    Ok(Some(WorldDesc {
        warnings,
        agents,
        name,
        source: PathBuf::from(file),
        seed: wf.seed,
        duration: wf.duration,
        dt: wf.dt,
        integrator: match wf.integrator {
            IntegratorSpec::Rk4 => Integrator::Rk4,
            IntegratorSpec::SemiImplicitEuler => Integrator::SemiImplicitEuler,
        },
        env,
        attenuation,
        ambient: Ambient {
            surface_irradiance: wf.water.ambient_irradiance,
            diffuse_attenuation: wf.water.diffuse_attenuation,
        },
        geometry,
        vehicles,
        groups,
        output: OutputDesc {
            record_hz: wf.output.record_hz,
            plots: wf.output.plots,
            replay: wf.output.replay,
            mcap: wf.output.mcap,
        },
    }))
}
