//! Missions: time-ordered setpoint steps, checked against the pool, the run's duration and
//! the vehicle's thrusters and tilt drives.

use super::validator::Validator;
use crate::error::{FieldPath, ProblemKind};
use crate::spec::*;
use shoal_model::prelude::*;

pub(super) fn mission(
    g: &VehicleGroupSpec,
    gp: &FieldPath,
    wf: &WorldFile,
    model: &VehicleModel,
    v: &mut Validator<'_>,
) -> Mission {
    let p = &model.params;
    let mut steps = Vec::new();
    let mut last_t = 0.0;
    for (i, s) in g.mission.iter().enumerate() {
        let mp = gp.key("mission").index(i);
        if v.field_with(&mp.key("t"), s.t, None, Some(wf.duration)) && s.t < last_t {
            v.push(
                ProblemKind::Invalid,
                &mp.key("t"),
                format!(
                    "mission steps must be in time order ({} s comes after {} s)",
                    s.t, last_t
                ),
            );
        }
        last_t = s.t;
        if let Some(d) = s.depth {
            v.field_with(&mp.key("depth"), d, None, Some(wf.pool.size[2]));
        }
        if let Some(y) = s.yaw_deg {
            v.field(&mp.key("yaw_deg"), y);
        }
        for (k, x) in [("surge", s.surge), ("sway", s.sway)] {
            if let Some(x) = x {
                v.field(&mp.key(k), x);
            }
        }
        let mode: Option<Mode> = s.mode.map(Into::into);
        if let Some(m) = mode
            && m.needs_layout()
            && model.uauv2.is_none()
        {
            v.push(ProblemKind::Invalid, &mp.key("mode"), format!(
                "mode `{}` needs the μAUV² layout (thrusters `top`, `port`, `stbd` on tilts `alpha`, `beta`); this vehicle accepts `off` and `raw`",
                m.name()));
        }
        let mut thrusters = Vec::new();
        for (name, c) in &s.thrusters {
            let tp = mp.key("thrusters").key(name);
            match p.thrusters.iter().position(|t| &t.name == name) {
                Some(k) => {
                    let lim = p.thrusters[k].max_command;
                    if v.field_with(&tp, *c, Some(-lim), Some(lim)) {
                        thrusters.push((k, *c));
                    }
                }
                None => {
                    let names: Vec<&str> = p.thrusters.iter().map(|t| t.name.as_str()).collect();
                    v.push(
                        ProblemKind::Reference,
                        &tp,
                        format!(
                            "no thruster named `{name}` (this vehicle has: {})",
                            names.join(", ")
                        ),
                    );
                }
            }
        }
        let mut tilts = Vec::new();
        for (name, a) in &s.tilts_deg {
            let tp = mp.key("tilts_deg").key(name);
            match p.tilts.iter().position(|t| &t.name == name) {
                Some(k) => {
                    let t = &p.tilts[k];
                    if v.field_with(&tp, *a, Some(t.min.to_degrees()), Some(t.max.to_degrees())) {
                        tilts.push((k, a.to_radians()));
                    }
                }
                None => {
                    let names: Vec<&str> = p.tilts.iter().map(|t| t.name.as_str()).collect();
                    v.push(
                        ProblemKind::Reference,
                        &tp,
                        format!(
                            "no tilt drive named `{name}` (this vehicle has: {})",
                            names.join(", ")
                        ),
                    );
                }
            }
        }
        steps.push(MissionStep {
            t: s.t,
            mode,
            depth: s.depth,
            yaw: s.yaw_deg.map(f64::to_radians),
            surge: s.surge,
            sway: s.sway,
            thrusters,
            tilts,
            pump: s.pump.map(Into::into),
        });
    }
    Mission { steps }
}
