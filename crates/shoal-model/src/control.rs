//! The μAUV² paper's control system (Sec. 5): PD controllers for heave and yaw with gains by
//! pole placement on the identified 1-DOF models, five modes with thrust allocation and
//! saturation, a moving-average low-pass on thruster commands and tilt angles, and a
//! bang-bang pump with a dead zone. Plus a mission: a time schedule of modes and setpoints.
//!
//! Controllers see only sensor readings ([`SensorReadings`]) and produce actuator commands
//! ([`ActuatorCommands`]) — the same interface a controller on the real vehicle has.
//!
//! Sign conventions: depth and heave force are positive down (NED); yaw torque is positive
//! clockwise seen from above (about body z, which points down).

use crate::ballast::Pump;
use crate::math::{PerActuator, Quat, Vec3, euler_rpy, wrap_pi};
use crate::thruster::{ThrusterParams, TiltParams};

/// Operating mode of the built-in controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Mode {
    /// Everything off (thrusters 0, tilts to 0, pump off).
    #[default]
    Off,
    /// Mode 1: α = 0, β = −π/2, top thruster off; heave only.
    Diving,
    /// Mode 2: diving plus bang-bang pump control with a dead zone on the heave error.
    Buoyancy,
    /// Mode 3: α = 0, β = 0, top thruster off; yaw only by differential side thrust.
    Turning,
    /// Mode 4: α = π/2, β = 0; yaw and surge by the side thrusters, sway by the top thruster.
    Drift,
    /// Mode 5: α = 0, β ∈ [−π/4, π/4]; heave, yaw and surge together, the top thruster
    /// cancels the side thrusters' surge, yaw has priority when side thrust saturates.
    Auto,
    /// Raw actuator commands (thruster %, tilt angles, pump) pass straight through.
    Raw,
}

impl Mode {
    /// Every mode, in paper order followed by `off` and `raw`.
    pub const ALL: [Mode; 7] = [
        Mode::Diving,
        Mode::Buoyancy,
        Mode::Turning,
        Mode::Drift,
        Mode::Auto,
        Mode::Off,
        Mode::Raw,
    ];

    /// Every mode by its command code (the index): 0 `off`, 1 `diving` … 5 `auto` (the
    /// agents' and Python's setpoint codes, the μAUV² paper's mode numbers) and 6 `raw`. The
    /// one table of mode codes.
    pub const BY_CODE: [Mode; 7] = [
        Mode::Off,
        Mode::Diving,
        Mode::Buoyancy,
        Mode::Turning,
        Mode::Drift,
        Mode::Auto,
        Mode::Raw,
    ];

    /// The command code of the mode: its index in [`Mode::BY_CODE`] (0 … 6).
    pub fn code(self) -> usize {
        // Every mode is in the table (a test checks it); `raw` is the last.
        Mode::BY_CODE
            .iter()
            .position(|m| *m == self)
            .unwrap_or(Mode::BY_CODE.len() - 1)
    }

    /// Lower-case name as used in world files.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Off => "off",
            Mode::Diving => "diving",
            Mode::Buoyancy => "buoyancy",
            Mode::Turning => "turning",
            Mode::Drift => "drift",
            Mode::Auto => "auto",
            Mode::Raw => "raw",
        }
    }

    /// Parses a lower-case mode name.
    pub fn from_name(s: &str) -> Option<Mode> {
        Mode::ALL.into_iter().find(|m| m.name() == s)
    }

    /// Whether the controller holds a depth in this mode (its heave loop runs on the depth
    /// setpoint: diving, buoyancy and auto); in the others a depth setpoint means nothing.
    pub fn holds_depth(self) -> bool {
        matches!(self, Mode::Diving | Mode::Buoyancy | Mode::Auto)
    }

    /// Whether the mode needs the μAUV² thruster layout.
    pub fn needs_layout(self) -> bool {
        !matches!(self, Mode::Off | Mode::Raw)
    }
}

/// Raw actuator commands (used by [`Mode::Raw`]).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ActuatorCommands {
    /// Command per thruster [% of full scale, −100…100].
    pub thrusters: PerActuator,
    /// Target angle per tilt drive \[rad\].
    pub tilts: PerActuator,
    /// Pump command.
    pub pump: Pump,
}

impl ActuatorCommands {
    /// All zero for a vehicle with `n_thrusters` thrusters and `n_tilts` tilt drives.
    pub fn zeros(n_thrusters: usize, n_tilts: usize) -> Self {
        Self {
            thrusters: PerActuator::from_elem(0.0, n_thrusters),
            tilts: PerActuator::from_elem(0.0, n_tilts),
            pump: Pump::Off,
        }
    }
}

/// What the controller is asked to do.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Setpoints {
    /// Active mode.
    pub mode: Mode,
    /// Depth setpoint \[m\] (positive down).
    pub depth: f64,
    /// Heading setpoint \[rad\].
    pub yaw: f64,
    /// Desired surge force \[N\] (drift and auto modes).
    pub surge: f64,
    /// Desired sway force \[N\] (drift mode).
    pub sway: f64,
    /// Commands for [`Mode::Raw`].
    pub raw: ActuatorCommands,
}

/// One entry of a mission: at time `t` the given fields replace the current setpoints.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct MissionStep {
    /// Time at which the step takes effect \[s\].
    pub t: f64,
    /// New mode.
    pub mode: Option<Mode>,
    /// New depth setpoint \[m\].
    pub depth: Option<f64>,
    /// New heading setpoint \[rad\].
    pub yaw: Option<f64>,
    /// New surge force \[N\].
    pub surge: Option<f64>,
    /// New sway force \[N\].
    pub sway: Option<f64>,
    /// New raw thruster commands [%] as (thruster index, command).
    pub thrusters: Vec<(usize, f64)>,
    /// New raw tilt targets \[rad\] as (tilt index, angle).
    pub tilts: Vec<(usize, f64)>,
    /// New raw pump command.
    pub pump: Option<Pump>,
}

/// A schedule of setpoints, sorted by time.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mission {
    /// Steps in non-decreasing time order.
    pub steps: Vec<MissionStep>,
}

/// Position of a vehicle in its mission.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct MissionCursor {
    /// Index of the next step not yet applied.
    pub next: usize,
}

impl MissionCursor {
    /// Time of the next step not yet applied \[s\] (+∞ when the mission is done).
    pub fn next_time(&self, mission: &Mission) -> f64 {
        mission.steps.get(self.next).map_or(f64::INFINITY, |s| s.t)
    }
}

/// Whether a mission step at `step_t` is due at time `t` \[s\] (a nanosecond early counts, so
/// that steps at multiples of dt are applied on time despite rounding).
pub fn step_due(step_t: f64, t: f64) -> bool {
    step_t <= t + 1e-9
}

impl MissionCursor {
    /// Applies every step with `step.t <= t` that has not been applied yet. Returns whether
    /// anything changed.
    pub fn advance(&mut self, mission: &Mission, t: f64, sp: &mut Setpoints) -> bool {
        let mut changed = false;
        while let Some(s) = mission.steps.get(self.next) {
            if !step_due(s.t, t) {
                break;
            }
            if let Some(m) = s.mode {
                sp.mode = m;
            }
            if let Some(d) = s.depth {
                sp.depth = d;
            }
            if let Some(y) = s.yaw {
                sp.yaw = y;
            }
            if let Some(x) = s.surge {
                sp.surge = x;
            }
            if let Some(y) = s.sway {
                sp.sway = y;
            }
            for &(i, c) in &s.thrusters {
                if let Some(slot) = sp.raw.thrusters.get_mut(i) {
                    *slot = c;
                }
            }
            for &(i, a) in &s.tilts {
                if let Some(slot) = sp.raw.tilts.get_mut(i) {
                    *slot = a;
                }
            }
            if let Some(p) = s.pump {
                sp.raw.pump = p;
            }
            self.next += 1;
            changed = true;
        }
        changed
    }
}

/// PD design by pole placement on a 1-DOF model `m ẍ = u`: K_P = m ω², K_D = 2 ζ ω m, unless
/// overridden.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PdDesign {
    /// Natural frequency ω [rad/s].
    pub omega: f64,
    /// Damping ratio ζ [-].
    pub zeta: f64,
    /// Explicit proportional gain (overrides m ω²) [N/m or N·m/rad].
    pub kp: Option<f64>,
    /// Explicit derivative gain (overrides 2 ζ ω m) [N·s/m or N·m·s/rad].
    pub kd: Option<f64>,
}

impl PdDesign {
    /// (K_P, K_D) for effective mass or inertia `m` [kg or kg·m²].
    pub fn gains(&self, m: f64) -> (f64, f64) {
        (
            self.kp.unwrap_or(m * self.omega * self.omega),
            self.kd.unwrap_or(2.0 * self.zeta * self.omega * m),
        )
    }
}

/// Indices of the μAUV²'s actuators, needed by the paper's modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Uauv2Layout {
    /// The top thruster (turned by α).
    pub top: usize,
    /// The port side thruster (turned by β).
    pub port: usize,
    /// The starboard side thruster (turned by β).
    pub stbd: usize,
    /// The top thruster's tilt drive α.
    pub alpha: usize,
    /// The side thrusters' tilt drive β.
    pub beta: usize,
}

impl Uauv2Layout {
    /// Finds the layout by actuator names (`top`, `port`, `stbd`; tilts `alpha`, `beta`), if
    /// the vehicle has it.
    pub fn find(thrusters: &[ThrusterParams], tilts: &[TiltParams]) -> Option<Self> {
        let th = |n: &str| thrusters.iter().position(|t| t.name == n);
        let tl = |n: &str| tilts.iter().position(|t| t.name == n);
        let l = Uauv2Layout {
            top: th("top")?,
            port: th("port")?,
            stbd: th("stbd")?,
            alpha: tl("alpha")?,
            beta: tl("beta")?,
        };
        let ok = thrusters[l.top].tilt == Some(l.alpha)
            && thrusters[l.port].tilt == Some(l.beta)
            && thrusters[l.stbd].tilt == Some(l.beta);
        ok.then_some(l)
    }
}

/// Parameters of the built-in controller.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlParams {
    /// Control period \[s\] (the controller runs every this many seconds).
    pub period: f64,
    /// Heave PD in diving and auto mode.
    pub heave: PdDesign,
    /// Heave PD in buoyancy mode.
    pub heave_buoyancy: PdDesign,
    /// Yaw PD.
    pub yaw: PdDesign,
    /// Pump dead zone on the heave error: the pump runs only when |error| exceeds it \[m\].
    pub dead_zone: f64,
    /// Moving-average window on thruster commands and tilt angles \[samples\] (1 = no filter).
    pub filter_window: usize,
    /// Largest side-thruster tilt |β| in auto mode \[rad\].
    pub auto_tilt_max: f64,
    /// Time constant of the first-order filter on the depth rate estimated from the quantised
    /// depth reading \[s\] (0 = raw backward difference).
    pub rate_filter: f64,
}

/// Heading error \[rad\] for the PD: wrapped into (−π + δ, π + δ] with δ = 2°, so that a command
/// of exactly ±180° turns the same (positive) way whatever the sensor noise.
#[inline]
pub fn heading_error(setpoint: f64, yaw: f64) -> f64 {
    const DELTA: f64 = 2.0 * std::f64::consts::PI / 180.0;
    wrap_pi(setpoint - yaw - DELTA) + DELTA
}

/// What the controller can sense.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorReadings {
    /// Quantised depth from the pressure sensor \[m\].
    pub depth: f64,
    /// Attitude from the IMU's filter.
    pub attitude: Quat,
    /// Body rates from the gyros [rad/s].
    pub gyro: Vec3,
    /// Specific force from the accelerometer [m/s²].
    pub accel: Vec3,
    /// Tilt angles from the potentiometers \[rad\].
    pub tilts: PerActuator,
    /// The tank's full switch.
    pub tank_full: bool,
}

impl SensorReadings {
    /// Readings of a vehicle at rest, upright, at the surface.
    pub fn zeros(n_tilts: usize) -> Self {
        Self {
            depth: 0.0,
            attitude: Quat::identity(),
            gyro: Vec3::zeros(),
            accel: Vec3::zeros(),
            tilts: PerActuator::from_elem(0.0, n_tilts),
            tank_full: false,
        }
    }
}

/// Moving averages over the last `window` samples of several channels that are pushed
/// together (one heap block for all of them).
#[derive(Clone, Debug, PartialEq)]
pub struct MovingAverages {
    /// Samples, channel after channel: channel `c` owns `buf[c·window .. (c+1)·window]`.
    buf: Vec<f64>,
    window: usize,
    /// Slot the next push overwrites (the same in every channel).
    next: usize,
}

impl MovingAverages {
    /// `channels` filters with the given window (≥ 1), every sample at `initial`.
    pub fn new(channels: usize, window: usize, initial: f64) -> Self {
        let window = window.max(1);
        Self {
            buf: vec![initial; channels * window],
            window,
            next: 0,
        }
    }

    /// Number of channels.
    pub fn channels(&self) -> usize {
        self.buf.len() / self.window
    }

    /// Pushes one sample per channel (`xs[c]` into channel `c`, for the first
    /// `min(xs.len(), channels)` channels) and replaces each with its channel's average.
    pub fn push(&mut self, xs: &mut [f64]) {
        let w = self.window;
        for (x, ch) in xs.iter_mut().zip(self.buf.chunks_exact_mut(w)) {
            ch[self.next] = *x;
            *x = ch.iter().sum::<f64>() / w as f64;
        }
        self.next = (self.next + 1) % w;
    }

    /// Sets every sample of channel `c` to `x` (nothing when there is no such channel).
    pub fn reset(&mut self, c: usize, x: f64) {
        let w = self.window;
        if let Some(ch) = self.buf.get_mut(c * w..(c + 1) * w) {
            ch.iter_mut().for_each(|b| *b = x);
        }
    }
}

/// Internal state of the controller of one vehicle, plus its last outputs for recording.
#[derive(Clone, Debug, PartialEq)]
pub struct ControllerState {
    prev_depth: Option<f64>,
    depth_rate: f64,
    auto_tilt_down: bool,
    prev_mode: Mode,
    thruster_filters: MovingAverages,
    tilt_filters: MovingAverages,
    /// Last heave force demand after saturation \[N\].
    pub heave_force: f64,
    /// Last yaw torque demand after saturation [N·m].
    pub yaw_torque: f64,
}

/// Precomputed constants of the μAUV² modes.
#[derive(Clone, Debug, PartialEq)]
pub struct Uauv2Control {
    /// Actuator indices.
    pub layout: Uauv2Layout,
    /// Heave PD gains (K_P [N/m], K_D [N·s/m]) for diving/auto.
    pub heave_gains: (f64, f64),
    /// Heave PD gains for buoyancy mode.
    pub buoyancy_gains: (f64, f64),
    /// Yaw PD gains (K_P [N·m/rad], K_D [N·m·s/rad]).
    pub yaw_gains: (f64, f64),
    /// Half the lateral distance between the side thrusters \[m\].
    pub side_arm: f64,
    /// (forward, reverse) thrust limits of a side thruster \[N\].
    pub side_limits: (f64, f64),
    /// (forward, reverse) thrust limits of the top thruster \[N\].
    pub top_limits: (f64, f64),
}

impl Uauv2Control {
    /// Gains and limits for a vehicle with effective heave mass `m_heave` \[kg\] and effective
    /// yaw inertia `i_yaw` [kg·m²].
    pub fn new(
        layout: Uauv2Layout,
        params: &ControlParams,
        thrusters: &[ThrusterParams],
        m_heave: f64,
        i_yaw: f64,
    ) -> Self {
        let port = &thrusters[layout.port];
        let stbd = &thrusters[layout.stbd];
        let top = &thrusters[layout.top];
        let pl = port.curve.limits(port.max_command);
        let sl = stbd.curve.limits(stbd.max_command);
        Self {
            layout,
            heave_gains: params.heave.gains(m_heave),
            buoyancy_gains: params.heave_buoyancy.gains(m_heave),
            yaw_gains: params.yaw.gains(i_yaw),
            side_arm: 0.5 * (stbd.position.y - port.position.y).abs(),
            side_limits: (pl.0.min(sl.0), pl.1.min(sl.1)),
            top_limits: top.curve.limits(top.max_command),
        }
    }
}

impl ControllerState {
    /// Fresh state for a vehicle with the given actuators.
    pub fn new(params: &ControlParams, n_thrusters: usize, n_tilts: usize) -> Self {
        Self {
            prev_depth: None,
            depth_rate: 0.0,
            auto_tilt_down: true,
            prev_mode: Mode::Off,
            thruster_filters: MovingAverages::new(n_thrusters, params.filter_window, 0.0),
            tilt_filters: MovingAverages::new(n_tilts, params.filter_window, 0.0),
            heave_force: 0.0,
            yaw_torque: 0.0,
        }
    }

    /// One control period: reads `sensors`, follows `sp`, writes `out`.
    ///
    /// `uauv2` is `None` for vehicles without the μAUV² layout; they accept only
    /// [`Mode::Off`] and [`Mode::Raw`] (anything else behaves as off).
    pub fn update(
        &mut self,
        params: &ControlParams,
        uauv2: Option<&Uauv2Control>,
        thrusters: &[ThrusterParams],
        sensors: &SensorReadings,
        sp: &Setpoints,
        out: &mut ActuatorCommands,
    ) {
        let period = params.period;
        let raw_rate = self
            .prev_depth
            .map_or(0.0, |d| (sensors.depth - d) / period);
        self.prev_depth = Some(sensors.depth);
        let a = period / (params.rate_filter + period);
        self.depth_rate += a * (raw_rate - self.depth_rate);
        let depth_rate = self.depth_rate;
        let mode_changed = sp.mode != self.prev_mode;
        self.prev_mode = sp.mode;

        out.pump = Pump::Off;
        self.heave_force = 0.0;
        self.yaw_torque = 0.0;
        if sp.mode == Mode::Raw {
            let n = thrusters.len().min(out.thrusters.len());
            for i in 0..n {
                let c = sp.raw.thrusters.get(i).copied().unwrap_or(0.0);
                out.thrusters[i] = c;
                self.thruster_filters.reset(i, c);
            }
            for i in 0..self.tilt_filters.channels().min(out.tilts.len()) {
                let a = sp.raw.tilts.get(i).copied().unwrap_or(0.0);
                out.tilts[i] = a;
                self.tilt_filters.reset(i, a);
            }
            out.pump = sp.raw.pump;
            return;
        }
        let raw = out;
        raw.thrusters.iter_mut().for_each(|c| *c = 0.0);
        raw.tilts.iter_mut().for_each(|c| *c = 0.0);
        if let (Some(u), true) = (uauv2, sp.mode.needs_layout()) {
            if mode_changed {
                // A new mode starts from the measured tilt angles, not from stale samples.
                for (i, a) in sensors.tilts.iter().enumerate() {
                    self.tilt_filters.reset(i, *a);
                }
            }
            self.uauv2_mode(params, u, thrusters, sensors, sp, depth_rate, raw);
        }
        self.thruster_filters.push(&mut raw.thrusters);
        self.tilt_filters.push(&mut raw.tilts);
    }

    fn uauv2_mode(
        &mut self,
        params: &ControlParams,
        u: &Uauv2Control,
        thrusters: &[ThrusterParams],
        sensors: &SensorReadings,
        sp: &Setpoints,
        depth_rate: f64,
        out: &mut ActuatorCommands,
    ) {
        use std::f64::consts::FRAC_PI_2;
        let l = u.layout;
        let (ff, fr) = u.side_limits;
        let (_, _, yaw) = euler_rpy(&sensors.attitude);
        let yaw_error = heading_error(sp.yaw, yaw);
        let depth_error = sp.depth - sensors.depth;
        let beta = sensors.tilts.get(l.beta).copied().unwrap_or(0.0);
        let (s, c) = (-beta.sin(), beta.cos());
        let yaw_torque = |gains: (f64, f64)| gains.0 * yaw_error - gains.1 * sensors.gyro.z;
        let heave_force = |gains: (f64, f64)| gains.0 * depth_error - gains.1 * depth_rate;
        let cmd = |i: usize, f: f64| thrusters[i].curve.command_for(f, thrusters[i].max_command);
        let mut f_port = 0.0;
        let mut f_stbd = 0.0;
        let mut f_top = 0.0;
        match sp.mode {
            Mode::Diving | Mode::Buoyancy => {
                out.tilts[l.alpha] = 0.0;
                out.tilts[l.beta] = -FRAC_PI_2;
                let gains = if sp.mode == Mode::Buoyancy {
                    u.buoyancy_gains
                } else {
                    u.heave_gains
                };
                // Both side thrusters push along +z at β = −π/2: forward thrust pushes down.
                let z = heave_force(gains).clamp(-2.0 * fr, 2.0 * ff);
                self.heave_force = z;
                if s > 0.5 {
                    f_port = 0.5 * z / s;
                    f_stbd = f_port;
                }
                if sp.mode == Mode::Buoyancy {
                    out.pump = if depth_error > params.dead_zone && !sensors.tank_full {
                        Pump::Fill
                    } else if depth_error < -params.dead_zone {
                        Pump::Empty
                    } else {
                        Pump::Off
                    };
                }
            }
            Mode::Turning => {
                out.tilts[l.alpha] = 0.0;
                out.tilts[l.beta] = 0.0;
                // Balanced differential thrust: no net surge, so the smaller (reverse) limit
                // bounds the torque.
                let n_max = 2.0 * u.side_arm * c * ff.min(fr);
                let n = yaw_torque(u.yaw_gains).clamp(-n_max, n_max);
                self.yaw_torque = n;
                if c > 0.5 {
                    f_port = 0.5 * n / (u.side_arm * c);
                    f_stbd = -f_port;
                }
            }
            Mode::Drift => {
                out.tilts[l.alpha] = FRAC_PI_2;
                out.tilts[l.beta] = 0.0;
                let alpha = sensors.tilts.get(l.alpha).copied().unwrap_or(0.0);
                let n = yaw_torque(u.yaw_gains);
                if c > 0.5 {
                    let (d, ssum) = split_sum_diff(n / (u.side_arm * c), sp.surge / c, ff, fr);
                    self.yaw_torque = d * u.side_arm * c;
                    f_port = 0.5 * (ssum + d);
                    f_stbd = 0.5 * (ssum - d);
                }
                if alpha.sin() > 0.5 {
                    f_top = sp.sway / alpha.sin();
                }
            }
            Mode::Auto => {
                let z_des = heave_force(u.heave_gains);
                // β sits at ±β_max (down for a downward force, up for an upward one) and
                // flips only when the demand clearly changes sign (hysteresis), so that noise
                // on the depth reading does not make the slow tilt drive hunt (paper 5.7: β
                // changes only at setpoint steps).
                let z_switch = 0.1 * ff;
                if z_des > z_switch {
                    self.auto_tilt_down = true;
                } else if z_des < -z_switch {
                    self.auto_tilt_down = false;
                }
                let beta_t = if self.auto_tilt_down {
                    -params.auto_tilt_max
                } else {
                    params.auto_tilt_max
                };
                out.tilts[l.alpha] = 0.0;
                out.tilts[l.beta] = beta_t;
                let n = yaw_torque(u.yaw_gains);
                if c > 0.5 {
                    // Yaw first: the differential part D is saturated alone.
                    let d = (n / (u.side_arm * c)).clamp(-(ff + fr), ff + fr);
                    // Then the common part S, within what is left for the side thrusters ...
                    let (lo, hi) = (-2.0 * fr + d.abs(), 2.0 * ff - d.abs());
                    // ... and within what the top thruster can cancel in surge.
                    let (tf, tr) = u.top_limits;
                    let (clo, chi) = ((sp.surge - tf) / c, (sp.surge + tr) / c);
                    // Heave only once the drive has tilted far enough the right way.
                    let s_des = if s * z_des > 0.0 && s.abs() > 0.25 {
                        z_des / s
                    } else {
                        0.0
                    };
                    let (lo2, hi2) = (lo.max(clo), hi.min(chi));
                    let ssum = if lo2 <= hi2 {
                        s_des.clamp(lo2, hi2)
                    } else {
                        s_des.clamp(lo, hi)
                    };
                    f_port = 0.5 * (ssum + d);
                    f_stbd = 0.5 * (ssum - d);
                    f_top = (sp.surge - c * ssum).clamp(-tr, tf);
                    self.heave_force = s * ssum;
                    self.yaw_torque = d * u.side_arm * c;
                }
            }
            Mode::Off | Mode::Raw => {}
        }
        out.thrusters[l.port] = cmd(l.port, f_port);
        out.thrusters[l.stbd] = cmd(l.stbd, f_stbd);
        out.thrusters[l.top] = cmd(l.top, f_top);
    }
}

/// Splits a desired (differential, common) side-thrust pair into a feasible one with the
/// differential part first: port = (S+D)/2 and stbd = (S−D)/2 must lie in [−fr, ff].
fn split_sum_diff(d_des: f64, s_des: f64, ff: f64, fr: f64) -> (f64, f64) {
    let d = d_des.clamp(-(ff + fr), ff + fr);
    let s = s_des.clamp(-2.0 * fr + d.abs(), 2.0 * ff - d.abs());
    (d, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_codes_are_the_paper_numbers_with_off_and_raw() {
        // The μAUV² paper numbers its modes 1 (diving) … 5 (auto); off is 0 and raw 6.
        let want = [
            (Mode::Off, 0, "off"),
            (Mode::Diving, 1, "diving"),
            (Mode::Buoyancy, 2, "buoyancy"),
            (Mode::Turning, 3, "turning"),
            (Mode::Drift, 4, "drift"),
            (Mode::Auto, 5, "auto"),
            (Mode::Raw, 6, "raw"),
        ];
        assert_eq!(Mode::BY_CODE.len(), want.len());
        for (mode, code, name) in want {
            assert_eq!(mode.code(), code, "{name}");
            assert_eq!(Mode::BY_CODE[code], mode, "{name}");
            assert_eq!(Mode::BY_CODE[code].name(), name);
        }
    }

    #[test]
    fn heading_error_turns_positive_at_180() {
        use std::f64::consts::PI;
        assert!((heading_error(PI, 0.001) - (PI - 0.001)).abs() < 1e-12);
        assert!((heading_error(PI, -0.001) - (PI + 0.001)).abs() < 1e-12);
        assert!((heading_error(0.5, 0.2) - 0.3).abs() < 1e-12);
        assert!((heading_error(-3.0, 3.0) - (2.0 * PI - 6.0)).abs() < 1e-12);
    }

    #[test]
    fn pole_placement_gains() {
        let pd = PdDesign {
            omega: 0.6,
            zeta: 1.0,
            kp: None,
            kd: None,
        };
        let (kp, kd) = pd.gains(1.96);
        assert!((kp - 1.96 * 0.36).abs() < 1e-12);
        assert!((kd - 2.0 * 0.6 * 1.96).abs() < 1e-12);
        let pd = PdDesign {
            kd: Some(0.016),
            ..pd
        };
        assert_eq!(pd.gains(4.9e-3).1, 0.016);
    }

    #[test]
    fn moving_average_window() {
        let mut f = MovingAverages::new(2, 4, 0.0);
        let push = |f: &mut MovingAverages, a: f64, b: f64| {
            let mut x = [a, b];
            f.push(&mut x);
            x
        };
        assert_eq!(push(&mut f, 4.0, 8.0), [1.0, 2.0]);
        assert_eq!(push(&mut f, 4.0, 8.0), [2.0, 4.0]);
        push(&mut f, 4.0, 8.0);
        assert_eq!(push(&mut f, 4.0, 8.0), [4.0, 8.0]);
        assert_eq!(push(&mut f, 0.0, 8.0), [3.0, 8.0]);
        // A reset channel averages its reset value; the other keeps its samples.
        f.reset(1, 2.0);
        assert_eq!(push(&mut f, 0.0, 2.0), [2.0, 2.0]);
    }

    #[test]
    fn feasible_split_keeps_yaw_first() {
        let (d, s) = split_sum_diff(0.5, 0.3, 0.132, 0.0832);
        assert!((d - (0.132 + 0.0832)).abs() < 1e-12);
        let (p, q) = (0.5 * (s + d), 0.5 * (s - d));
        assert!(p <= 0.132 + 1e-12 && q >= -0.0832 - 1e-12);
    }

    #[test]
    fn mission_cursor_applies_steps_in_order() {
        let mission = Mission {
            steps: vec![
                MissionStep {
                    t: 0.0,
                    mode: Some(Mode::Diving),
                    depth: Some(0.0),
                    ..Default::default()
                },
                MissionStep {
                    t: 10.0,
                    depth: Some(0.4),
                    ..Default::default()
                },
                MissionStep {
                    t: 25.0,
                    depth: Some(0.2),
                    ..Default::default()
                },
            ],
        };
        let mut sp = Setpoints::default();
        let mut cur = MissionCursor::default();
        assert!(cur.advance(&mission, 0.0, &mut sp));
        assert_eq!((sp.mode, sp.depth), (Mode::Diving, 0.0));
        assert!(!cur.advance(&mission, 9.99, &mut sp));
        assert!(cur.advance(&mission, 30.0, &mut sp));
        assert_eq!(sp.depth, 0.2);
    }
}
