//! Commands for many vehicles at once: setpoints ([`Sim::set_setpoints`]), raw actuator
//! commands ([`Sim::set_actuators`]) and frames ([`Sim::queue_frames`]), every value checked
//! before anything changes, against the limits shared with the agents' commands
//! ([`crate::orders`]); and the frames delivered in a step ([`Sim::collect_received`]).

use super::columns::{Column, Rows};
use super::error::CommandError;
use crate::comm::{FrameEvent, Inbox, Outbox, Received};
use crate::components::*;
use crate::orders::{FrameOrder, MAX_FRAME_DELAY, Peers, check_frame, force_limit};
use crate::sim::Sim;
use shoal_model::math::wrap_pi;
use shoal_model::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;

/// The controller modes a setpoint command may ask for, by code (the agent protocol's
/// codes): [`Mode::BY_CODE`] without `raw`, which [`Sim::set_actuators`] sets.
pub const MODES: [Mode; 6] = {
    let mut modes = [Mode::Off; 6];
    let mut i = 0;
    while i < modes.len() {
        modes[i] = Mode::BY_CODE[i];
        i += 1;
    }
    modes
};

/// The code of `mode` ([`Mode::code`]): its index in [`MODES`], or 6 for [`Mode::Raw`] (raw
/// actuator commands).
pub fn mode_code(mode: Mode) -> i64 {
    mode.code() as i64
}
/// New setpoints for the built-in controller; a field left `None` keeps each vehicle's
/// current value.
#[derive(Clone, Copy, Debug)]
pub struct SetpointOrder<'a> {
    /// Mode codes ([`MODES`]).
    pub mode: Column<'a, i64>,
    /// Depth [m, positive down], 0 … the pool's depth.
    pub depth: Option<Column<'a, f64>>,
    /// Heading \[rad\], any finite value (one outside [−π, π] is wrapped into (−π, π]).
    pub yaw: Option<Column<'a, f64>>,
    /// Surge force \[N\], |surge| ≤ [`force_limit`].
    pub surge: Option<Column<'a, f64>>,
    /// Sway force \[N\], |sway| ≤ [`force_limit`].
    pub sway: Option<Column<'a, f64>>,
}

/// Raw actuator commands (mode raw); a field left `None` keeps each vehicle's current raw
/// command. Columns beyond a vehicle's own thrusters or tilt drives must be 0.
#[derive(Clone, Copy, Debug)]
pub struct ActuatorOrder<'a> {
    /// Per thruster [% of full scale], within ± the thruster's `max_command`.
    pub thrusters: Option<Rows<'a>>,
    /// Per tilt drive \[rad\], within the drive's range.
    pub tilts: Option<Rows<'a>>,
    /// Pump: −1 empty, 0 off, +1 fill (only 0 for a vehicle without a tank).
    pub pump: Option<Column<'a, i64>>,
}
/// The world's delivery and outcome counts ([`crate::comm::Medium::delivered`],
/// [`crate::comm::Medium::ended`]) at the last [`Sim::collect_received`].
#[derive(bevy_ecs::prelude::Resource)]
struct Collected(u64, u64);

/// What reached vehicles' inboxes in a step, as [`Sim::collect_received`] copies it out.
#[derive(Clone, Debug, Default)]
pub struct Arrivals {
    /// Frames delivered: (receiving vehicle id, frame), in id order and, per vehicle, in
    /// order of arrival.
    pub frames: Vec<(u32, Received)>,
    /// Outcomes of acknowledged unicasts: (sending vehicle id, outcome), in id order and,
    /// per vehicle, in the order they ended.
    pub outcomes: Vec<(u32, FrameEvent)>,
}

impl Arrivals {
    /// Forgets everything.
    pub fn clear(&mut self) {
        self.frames.clear();
        self.outcomes.clear();
    }
}

/// The setpoints a command asks of one vehicle.
struct Wanted {
    mode: Mode,
    depth: f64,
    yaw: f64,
    surge: f64,
    sway: f64,
}

/// [`force_limit`] of the model last asked about (the vehicles of a group share theirs).
#[derive(Default)]
struct ForceLimits(Option<(*const VehicleModel, f64)>);

impl ForceLimits {
    /// The force limit of `m` \[N\].
    fn of(&mut self, m: &Arc<VehicleModel>) -> f64 {
        let p = Arc::as_ptr(m);
        match self.0 {
            Some((q, f)) if q == p => f,
            _ => {
                let f = force_limit(m);
                self.0 = Some((p, f));
                f
            }
        }
    }
}

impl Sim {
    /// Row of each vehicle in a command for `ids` (all vehicles in id order when `None`):
    /// `u32::MAX` for vehicles not commanded. Errors for an unknown or repeated id.
    fn command_rows(&self, ids: Option<&[usize]>) -> Result<(usize, Vec<u32>), CommandError> {
        let n = self.len();
        let Some(ids) = ids else {
            return Ok((n, (0..n as u32).collect()));
        };
        let mut rows = vec![u32::MAX; n];
        for (r, &id) in ids.iter().enumerate() {
            if id >= n {
                return Err(CommandError::field(
                    "vehicles",
                    format!(
                        "vehicle {id} does not exist (the world has 0 … {})",
                        n.max(1) - 1
                    ),
                ));
            }
            if rows[id] != u32::MAX {
                return Err(CommandError::field(
                    "vehicles",
                    format!("vehicle {id} is given twice"),
                ));
            }
            rows[id] = r as u32;
        }
        Ok((ids.len(), rows))
    }

    /// `e` completed with vehicle `id`'s id and name.
    fn at_vehicle(&self, id: usize, mut e: CommandError) -> CommandError {
        e.vehicle = Some(id);
        e.name = Some(self.name(id).to_owned());
        e
    }

    /// Sets the setpoints of vehicles `ids` (all, in id order, when `None`; the columns have
    /// one value per listed vehicle). Every value is checked first and nothing changes on an
    /// error: NaN or infinite values and unknown mode codes always fail; values outside their
    /// range fail unless `clip`, which clamps them to it.
    pub fn set_setpoints(
        &mut self,
        ids: Option<&[usize]>,
        order: &SetpointOrder<'_>,
        clip: bool,
    ) -> Result<(), CommandError> {
        let (count, rows) = self.command_rows(ids)?;
        order.mode.check_len("mode", count)?;
        for (name, col) in [
            ("depth", &order.depth),
            ("yaw", &order.yaw),
            ("surge", &order.surge),
            ("sway", &order.sway),
        ] {
            if let Some(c) = col {
                c.check_len(name, count)?;
            }
        }
        let pool_depth = self.pool_size().z;
        // Each listed vehicle's new setpoints (its force limit given), or the problem.
        let new = |r: usize, force: f64, sp: &Setpoints| -> Result<Wanted, CommandError> {
            let code = order.mode.get(r);
            let mode = usize::try_from(code)
                .ok()
                .and_then(|i| MODES.get(i))
                .copied()
                .ok_or_else(|| {
                    CommandError::field(
                        "mode",
                        format!(
                            "code {code} is not a mode: allowed 0 … 5 ({})",
                            MODES.map(Mode::name).join(", ")
                        ),
                    )
                })?;
            let value = |name: &str,
                         col: &Option<Column<'_, f64>>,
                         current: f64,
                         lo: f64,
                         hi: f64,
                         unit: &str| {
                let Some(c) = col else { return Ok(current) };
                let x = c.get(r);
                if !x.is_finite() {
                    return Err(CommandError::field(
                        name,
                        format!("{x} is not a number: allowed {lo} … {hi} {unit}"),
                    ));
                }
                if clip {
                    Ok(x.clamp(lo, hi))
                } else if x < lo || x > hi {
                    Err(CommandError::field(
                        name,
                        format!("{x} {unit} is outside the allowed {lo} … {hi} {unit}"),
                    ))
                } else {
                    Ok(x)
                }
            };
            let yaw = match order.yaw {
                None => sp.yaw,
                Some(c) => {
                    let x = c.get(r);
                    if !x.is_finite() {
                        return Err(CommandError::field(
                            "yaw",
                            format!("{x} is not a number: allowed any finite heading in rad"),
                        ));
                    }
                    // In range it is kept bit for bit (as a mission's heading is).
                    if (-PI..=PI).contains(&x) {
                        x
                    } else {
                        wrap_pi(x)
                    }
                }
            };
            Ok(Wanted {
                mode,
                depth: value("depth", &order.depth, sp.depth, 0.0, pool_depth, "m")?,
                yaw,
                surge: value("surge", &order.surge, sp.surge, -force, force, "N")?,
                sway: value("sway", &order.sway, sp.sway, -force, force, "N")?,
            })
        };
        let mut force = ForceLimits::default();
        self.check_then_apply(
            &rows,
            |r, k, c| new(r, force.of(k), &c.setpoints),
            |s, _, _, c| {
                let sp = &mut c.setpoints;
                sp.mode = s.mode;
                sp.depth = s.depth;
                sp.yaw = s.yaw;
                sp.surge = s.surge;
                sp.sway = s.sway;
            },
        )
    }

    /// Sets raw actuator commands (mode raw) of vehicles `ids` (see [`Self::set_setpoints`]
    /// for `ids`, checking and `clip`). A vehicle with fewer thrusters or tilt drives than the
    /// rows have columns needs 0 in the extra columns; a vehicle without a tank needs pump 0.
    pub fn set_actuators(
        &mut self,
        ids: Option<&[usize]>,
        order: &ActuatorOrder<'_>,
        clip: bool,
    ) -> Result<(), CommandError> {
        let (count, rows) = self.command_rows(ids)?;
        if let Some(t) = &order.thrusters {
            t.check_len("thrusters", count)?;
        }
        if let Some(t) = &order.tilts {
            t.check_len("tilts", count)?;
        }
        if let Some(p) = &order.pump {
            p.check_len("pump", count)?;
        }
        let check = |r: usize, m: &VehicleModel| -> Result<(), CommandError> {
            let p = &m.params;
            // Each column of a rows matrix against the vehicle's `count` actuators' ranges.
            let ranges = |name: &str,
                          rows: &Option<Rows<'_>>,
                          count: usize,
                          limit: &dyn Fn(usize) -> (f64, f64),
                          unit: &str| {
                let Some(rs) = rows else { return Ok(()) };
                for (i, &x) in rs.row(r).iter().enumerate() {
                    let field = format!("{name}[{i}]");
                    if !x.is_finite() {
                        return Err(CommandError::field(field, format!("{x} is not a number")));
                    }
                    if i >= count {
                        if x != 0.0 {
                            return Err(CommandError::field(
                                field,
                                format!(
                                    "{x} {unit}, but the vehicle has {count} {name}: must be 0"
                                ),
                            ));
                        }
                        continue;
                    }
                    let (lo, hi) = limit(i);
                    if !clip && (x < lo || x > hi) {
                        return Err(CommandError::field(
                            field,
                            format!("{x} {unit} is outside the allowed {lo} … {hi} {unit}"),
                        ));
                    }
                }
                Ok(())
            };
            let th = |i: usize| (-p.thrusters[i].max_command, p.thrusters[i].max_command);
            let tl = |i: usize| (p.tilts[i].min, p.tilts[i].max);
            ranges("thrusters", &order.thrusters, p.thrusters.len(), &th, "%")?;
            ranges("tilts", &order.tilts, p.tilts.len(), &tl, "rad")?;
            if let Some(pump) = &order.pump {
                let x = pump.get(r);
                if !(-1..=1).contains(&x) {
                    return Err(CommandError::field(
                        "pump",
                        format!("{x}: allowed −1 (empty), 0 (off), +1 (fill)"),
                    ));
                }
                if x != 0 && p.ballast.is_none() {
                    return Err(CommandError::field(
                        "pump",
                        format!("{x}, but the vehicle has no tank: must be 0"),
                    ));
                }
            }
            Ok(())
        };
        self.check_then_apply(
            &rows,
            |r, k, _| check(r, k),
            |(), r, k, c| {
                let p = &k.params;
                let sp = &mut c.setpoints;
                sp.mode = Mode::Raw;
                if let Some(rs) = &order.thrusters {
                    for ((out, x), t) in
                        sp.raw.thrusters.iter_mut().zip(rs.row(r)).zip(&p.thrusters)
                    {
                        *out = x.clamp(-t.max_command, t.max_command);
                    }
                }
                if let Some(rs) = &order.tilts {
                    for ((out, x), t) in sp.raw.tilts.iter_mut().zip(rs.row(r)).zip(&p.tilts) {
                        *out = x.clamp(t.min, t.max);
                    }
                }
                if let Some(pump) = &order.pump {
                    sp.raw.pump = Pump::from_sign(pump.get(r) as f64);
                }
            },
        )
    }

    /// The commanded vehicles (`rows[vehicle id]` is the vehicle's row, `u32::MAX` for a
    /// vehicle not commanded) checked by `check` before any is changed — on an error, the
    /// first failing row's, nothing changes — and then each given `apply` with its checked
    /// value; a vehicle driven by an agent no longer falls back to its mission.
    fn check_then_apply<T>(
        &mut self,
        rows: &[u32],
        mut check: impl FnMut(usize, &Arc<VehicleModel>, &Control) -> Result<T, CommandError>,
        mut apply: impl FnMut(T, usize, &VehicleModel, &mut Control),
    ) -> Result<(), CommandError> {
        let mut first: Option<(usize, usize, CommandError)> = None;
        for (id, v) in self.fleet().as_slice().iter().enumerate() {
            let r = rows[id];
            if r == u32::MAX || first.as_ref().is_some_and(|f| f.0 < r as usize) {
                continue;
            }
            if let Err(e) = check(r as usize, &v.model, &v.control) {
                first = Some((r as usize, id, e));
            }
        }
        if let Some((_, id, e)) = first {
            return Err(self.at_vehicle(id, e));
        }
        for (id, v) in self.fleet_mut().as_mut_slice().iter_mut().enumerate() {
            let r = rows[id];
            if r == u32::MAX {
                continue;
            }
            if let Ok(x) = check(r as usize, &v.model, &v.control) {
                apply(x, r as usize, &v.model, &mut v.control);
            }
        }
        let mut q = self.world_mut().query::<(&VehicleId, &mut External)>();
        for (id, mut x) in q.iter_mut(self.world_mut()) {
            if rows[id.0 as usize] != u32::MAX {
                x.fallback = false;
            }
        }
        Ok(())
    }

    /// Hands frames to vehicles' modems: `(vehicle id, frame)`, the delay counted from now
    /// \[s\], 0 … [`MAX_FRAME_DELAY`] (clamped to it when `clip`). Every frame is checked first
    /// ([`check_frame`]); nothing is queued on an error.
    pub fn queue_frames(
        &mut self,
        frames: &[(usize, FrameOrder)],
        clip: bool,
    ) -> Result<(), CommandError> {
        let n = self.len();
        for (i, (id, f)) in frames.iter().enumerate() {
            if *id >= n {
                return Err(CommandError::field(
                    format!("frames[{i}].vehicle"),
                    format!(
                        "vehicle {id} does not exist (the world has 0 … {})",
                        n.max(1) - 1
                    ),
                ));
            }
            let kind = &self.fleet().get(VehicleId(*id as u32)).model;
            let peers = Peers {
                me: *id as u32,
                count: n,
            };
            let problem = check_frame(&kind.params.modems, f, peers)
                .err()
                .map(|p| p.to_string())
                .or_else(|| {
                    (!clip && !(0.0..=MAX_FRAME_DELAY).contains(&f.delay)).then(|| {
                        format!(
                            "delay {} s is outside the allowed 0 … {MAX_FRAME_DELAY} s",
                            f.delay
                        )
                    })
                });
            if let Some(message) = problem {
                return Err(
                    self.at_vehicle(*id, CommandError::field(format!("frames[{i}]"), message))
                );
            }
        }
        let t = self.time();
        for (id, f) in frames {
            let e = self.vehicle_entity(*id);
            if let Some(mut out) = self.world_mut().get_mut::<Outbox>(e) {
                out.0.push(f.out_frame(t));
            }
        }
        Ok(())
    }

    /// Appends to `out` every frame delivered after time `since` \[s\] (call it after each
    /// step with the time before the step: a step delivers the frames whose reception ended
    /// in it: after `since`, up to now), and every outcome of an acknowledged unicast that
    /// ended from `since` on, before now (a sender gives up at the start of a step, an
    /// acknowledgement is decoded after it: the windows of consecutive steps meet without
    /// overlapping, so each outcome is copied once; see [`Arrivals`]). Vehicles driven by an external agent keep both until the agent takes
    /// them; with `drain_agents` (there is no agent host: the caller acts for the agents)
    /// their inboxes are emptied here instead. With `out` = `None` only that is done.
    pub fn collect_received(
        &mut self,
        since: f64,
        mut out: Option<&mut Arrivals>,
        drain_agents: bool,
    ) {
        // Nothing was delivered and nothing ended since the last call: nothing to copy or to
        // empty.
        let (delivered, ended) = (self.medium().delivered, self.medium().ended);
        if self
            .world()
            .get_resource::<Collected>()
            .is_some_and(|c| (c.0, c.1) == (delivered, ended))
        {
            return;
        }
        self.world_mut()
            .insert_resource(Collected(delivered, ended));
        let now = self.time();
        let start = out
            .as_ref()
            .map_or((0, 0), |o| (o.frames.len(), o.outcomes.len()));
        let mut q = self
            .world_mut()
            .query::<(&VehicleId, &mut Inbox, Option<&External>)>();
        for (id, mut inbox, ext) in q.iter_mut(self.world_mut()) {
            if inbox.is_empty() {
                continue;
            }
            if let Some(out) = out.as_deref_mut() {
                out.frames.extend(
                    (inbox.frames.iter())
                        .filter(|r| r.t > since)
                        .map(|r| (id.0, r.clone())),
                );
                out.outcomes.extend(
                    (inbox.outcomes.iter())
                        .filter(|e| (since..now).contains(&e.t))
                        .map(|e| (id.0, e.clone())),
                );
            }
            if drain_agents && ext.is_some() {
                inbox.clear();
            }
        }
        if let Some(out) = out {
            out.frames[start.0..].sort_by_key(|(id, _)| *id);
            out.outcomes[start.1..].sort_by_key(|(id, _)| *id);
        }
    }
}
