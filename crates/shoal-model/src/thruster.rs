//! Thrusters and tilt drives: thrust curves, tilting directions with rate limits, an optional
//! first-order thrust lag, and the generalised force τ they produce on the hull.

use crate::math::{PerActuator, Quat, Vec3, Vec6, join6};
use nalgebra::Unit;

/// Static thrust as a function of the command.
#[derive(Clone, Debug, PartialEq)]
pub enum ThrustCurve {
    /// `f = C⁺ n²` for n ≥ 0 and `f = −C⁻ n²` for n < 0, with n the command in percent of full
    /// scale (the μAUV² paper's eq. 3 with the propeller speed replaced by the command).
    Quadratic {
        /// C_t⁺ [N/%²], ≥ 0.
        ct_pos: f64,
        /// C_t⁻ magnitude [N/%²], ≥ 0 (reverse thrust is `−ct_neg n²`).
        ct_neg: f64,
    },
    /// Piecewise-linear table of (command [%], thrust \[N\]) points, strictly increasing in the
    /// command and non-decreasing in thrust; clamped at both ends.
    Table {
        /// The points, sorted by command.
        points: Vec<(f64, f64)>,
    },
}

impl ThrustCurve {
    /// Thrust \[N\] for command `n` [%].
    #[inline]
    pub fn thrust(&self, n: f64) -> f64 {
        match self {
            ThrustCurve::Quadratic { ct_pos, ct_neg } => {
                if n >= 0.0 {
                    ct_pos * n * n
                } else {
                    -ct_neg * n * n
                }
            }
            ThrustCurve::Table { points } => interp(points.iter().map(|&(c, f)| (c, f)), n),
        }
    }

    /// The command [%] that produces thrust `f` \[N\] (clamped to what the curve can give within
    /// ±`max_command`).
    pub fn command_for(&self, f: f64, max_command: f64) -> f64 {
        let n = match self {
            ThrustCurve::Quadratic { ct_pos, ct_neg } => {
                if f >= 0.0 {
                    if *ct_pos > 0.0 {
                        (f / ct_pos).sqrt()
                    } else {
                        0.0
                    }
                } else if *ct_neg > 0.0 {
                    -(-f / ct_neg).sqrt()
                } else {
                    0.0
                }
            }
            ThrustCurve::Table { points } => {
                // Inverse of a monotone table: interpolate command over thrust, taking the
                // middle of any flat (dead-band) segment at zero thrust.
                if f == 0.0 {
                    let zeros: Vec<f64> =
                        points.iter().filter(|p| p.1 == 0.0).map(|p| p.0).collect();
                    if let (Some(a), Some(b)) = (zeros.first(), zeros.last()) {
                        return (0.5 * (a + b)).clamp(-max_command, max_command);
                    }
                }
                interp(points.iter().map(|&(c, f)| (f, c)), f)
            }
        };
        n.clamp(-max_command, max_command)
    }

    /// Scales every thrust of the curve by `k` \[-\] (a motor that is stronger or weaker
    /// than the one the curve was measured on).
    pub fn scale(&mut self, k: f64) {
        match self {
            ThrustCurve::Quadratic { ct_pos, ct_neg } => {
                *ct_pos *= k;
                *ct_neg *= k;
            }
            ThrustCurve::Table { points } => {
                for p in points.iter_mut() {
                    p.1 *= k;
                }
            }
        }
    }

    /// Largest forward and largest reverse thrust magnitude \[N\] within ±`max_command`.
    pub fn limits(&self, max_command: f64) -> (f64, f64) {
        (
            self.thrust(max_command).max(0.0),
            (-self.thrust(-max_command)).max(0.0),
        )
    }
}

/// Linear interpolation in a table sorted by x, clamped at both ends.
fn interp(points: impl Iterator<Item = (f64, f64)> + Clone, x: f64) -> f64 {
    let mut prev: Option<(f64, f64)> = None;
    for (px, py) in points.clone() {
        match prev {
            None if x <= px => return py,
            Some((ax, ay)) if x <= px => {
                let t = if px > ax { (x - ax) / (px - ax) } else { 1.0 };
                return ay + t * (py - ay);
            }
            _ => {}
        }
        prev = Some((px, py));
    }
    prev.map_or(0.0, |p| p.1)
}

/// A tilt drive that turns one or more thrusters about a body axis.
#[derive(Clone, Debug, PartialEq)]
pub struct TiltParams {
    /// Name (e.g. `alpha`, `beta`).
    pub name: String,
    /// Rotation axis in the body frame (unit vector).
    pub axis: Unit<Vec3>,
    /// Lower angle limit \[rad\].
    pub min: f64,
    /// Upper angle limit \[rad\].
    pub max: f64,
    /// Maximum angular rate [rad/s] (> 0).
    pub rate_max: f64,
}

impl TiltParams {
    /// Moves `angle` \[rad\] towards `target` \[rad\] for `dt` \[s\] within the rate and range limits.
    #[inline]
    pub fn advance(&self, angle: f64, target: f64, dt: f64) -> f64 {
        let target = target.clamp(self.min, self.max);
        let step = self.rate_max * dt;
        (angle + (target - angle).clamp(-step, step)).clamp(self.min, self.max)
    }
}

/// One thruster.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrusterParams {
    /// Name (e.g. `top`, `port`, `stbd`).
    pub name: String,
    /// Position of the propeller in the body frame \[m\].
    pub position: Vec3,
    /// Thrust direction at tilt angle 0, body frame (unit vector): positive thrust pushes the
    /// hull along this direction.
    pub direction: Unit<Vec3>,
    /// Index of the tilt drive that turns this thruster, if any.
    pub tilt: Option<usize>,
    /// Static thrust curve.
    pub curve: ThrustCurve,
    /// Largest command magnitude [%] (commands are clamped to ±this).
    pub max_command: f64,
    /// Time constant of a first-order lag between static and actual thrust \[s\]; 0 = none.
    pub lag: f64,
    /// Time constant of the lag while the thrust magnitude falls (spin-down) \[s\]; a
    /// negative value means "the same as `lag`".
    pub lag_down: f64,
    /// Lag stages in series, each with the time constant above (1: first order, 2: critically
    /// damped second order, as a motor whose speed and current both lag).
    pub lag_stages: u8,
    /// Time the motor command takes to ramp through 100 % of command \[s\]: a slew-rate limit
    /// of 100/`ramp` %/s on the command the thrust curve sees (an ESC with a soft start or a
    /// current limit); 0 = none.
    pub ramp: f64,
}

/// Exact response of a first-order lag with time constant `tau` \[s\] from `x0` towards the
/// constant `target` over `dt` \[s\]: (value at the end, mean over the step).
#[inline]
fn first_order_step(x0: f64, target: f64, tau: f64, dt: f64) -> (f64, f64) {
    if tau <= 0.0 {
        return (target, target);
    }
    let e = (-dt / tau).exp();
    (
        target + (x0 - target) * e,
        target + (x0 - target) * (1.0 - e) * tau / dt,
    )
}

impl ThrusterParams {
    /// The lag's time constant \[s\] for a thrust moving from `from` towards `to` \[N\]:
    /// `lag_down` while the magnitude falls (if set), `lag` otherwise.
    #[inline]
    pub fn lag_towards(&self, from: f64, to: f64) -> f64 {
        if self.lag_down >= 0.0 && to.abs() < from.abs() {
            self.lag_down
        } else {
            self.lag
        }
    }

    /// Largest thrust magnitude \[N\] the curve gives at the largest command in the
    /// direction of the thrust `f` \[N\]: forward for f ≥ 0, reverse otherwise.
    #[inline]
    pub fn max_thrust_towards(&self, f: f64) -> f64 {
        let (fwd, rev) = self.curve.limits(self.max_command);
        if f >= 0.0 { fwd } else { rev }
    }

    /// Thrust direction [unit, body frame] when the thruster's tilt drive stands at `angle` \[rad\].
    #[inline]
    pub fn direction_at(&self, axis: Option<&Unit<Vec3>>, angle: f64) -> Vec3 {
        match axis {
            Some(a) if angle != 0.0 => {
                Quat::from_axis_angle(a, angle) * self.direction.into_inner()
            }
            _ => self.direction.into_inner(),
        }
    }
}

/// Per-vehicle actuator state: tilt angles and actual thrust of each thruster.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ActuatorState {
    /// Current tilt angle of each tilt drive \[rad\].
    pub tilt: PerActuator,
    /// Actual thrust of each thruster after the lag, at the end of the last step \[N\].
    pub thrust: PerActuator,
    /// Output of the first stage of a two-stage lag, at the end of the last step \[N\] (empty
    /// until a thruster with a two-stage lag first runs, then one per thruster; on the heap,
    /// so that the many vehicles without such a lag do not carry it inline).
    pub stage: Vec<f64>,
    /// The command each motor applies after its slew-rate limit ([`ThrusterParams::ramp`]),
    /// at the end of the last step [%] (empty until a thruster with a limit first runs, then
    /// one per thruster; on the heap like `stage`).
    pub command: Vec<f64>,
}

/// Advances tilt drives and thrust lags by `dt` \[s\] and returns the generalised force τ
/// (body frame) [N, N·m]. `submerged[i]` is false for a thruster above the water surface
/// (it then produces no thrust). The static thrust of each thruster comes from its curve.
pub fn actuate(
    thrusters: &[ThrusterParams],
    tilts: &[TiltParams],
    state: &mut ActuatorState,
    commands: &[f64],
    tilt_targets: &[f64],
    submerged: impl Fn(&Vec3) -> bool,
    dt: f64,
) -> Vec6 {
    actuate_with(
        thrusters,
        tilts,
        state,
        commands,
        tilt_targets,
        submerged,
        |th, n, _| th.curve.thrust(n),
        dt,
    )
}

/// [`actuate`] with a custom static-thrust model: `static_thrust(thruster, command [%],
/// thrust direction (unit, body frame))` returns the thrust \[N\] before the lag.
pub fn actuate_with(
    thrusters: &[ThrusterParams],
    tilts: &[TiltParams],
    state: &mut ActuatorState,
    commands: &[f64],
    tilt_targets: &[f64],
    submerged: impl Fn(&Vec3) -> bool,
    static_thrust: impl Fn(&ThrusterParams, f64, &Vec3) -> f64,
    dt: f64,
) -> Vec6 {
    // Each drive's rotation once, however many thrusters it turns.
    let mut rotations: smallvec::SmallVec<[Option<Quat>; 4]> = smallvec::SmallVec::new();
    for (i, tp) in tilts.iter().enumerate() {
        let target = tilt_targets.get(i).copied().unwrap_or(0.0);
        let angle = tp.advance(state.tilt[i], target, dt);
        state.tilt[i] = angle;
        rotations.push((angle != 0.0).then(|| Quat::from_axis_angle(&tp.axis, angle)));
    }
    let mut force = Vec3::zeros();
    let mut moment = Vec3::zeros();
    for (i, th) in thrusters.iter().enumerate() {
        let n = commands
            .get(i)
            .copied()
            .unwrap_or(0.0)
            .clamp(-th.max_command, th.max_command);
        // A slew-rate limit: the motor's command moves towards the commanded one by at most
        // 100/ramp %/s and holds for the step.
        let n = if th.ramp > 0.0 {
            if state.command.len() < thrusters.len() {
                state.command.resize(thrusters.len(), 0.0);
            }
            let step = 100.0 / th.ramp * dt;
            let c = state.command[i] + (n - state.command[i]).clamp(-step, step);
            state.command[i] = c;
            c
        } else {
            n
        };
        // As `th.direction_at(axis, angle)`, with the drive's rotation computed once.
        let dir = match th.tilt.and_then(|k| rotations[k]) {
            Some(r) => r * th.direction.into_inner(),
            None => th.direction.into_inner(),
        };
        let f_static = if submerged(&th.position) {
            static_thrust(th, n, &dir)
        } else {
            0.0
        };
        // Exact first-order response over the step: the thrust at its end is kept as state,
        // its mean over the step is what the hull receives (the exact impulse).
        let f = if th.lag > 0.0 || th.lag_down > 0.0 {
            let mut target = f_static;
            if th.lag_stages >= 2 {
                if state.stage.len() < thrusters.len() {
                    state.stage.resize(thrusters.len(), 0.0);
                }
                // First stage: exact over the step; the second stage follows its mean.
                let s0 = state.stage[i];
                let tau = th.lag_towards(s0, target);
                let (end, mean) = first_order_step(s0, target, tau, dt);
                state.stage[i] = end;
                target = mean;
            }
            let f0 = state.thrust[i];
            let (end, mean) = first_order_step(f0, target, th.lag_towards(f0, target), dt);
            state.thrust[i] = end;
            mean
        } else {
            state.thrust[i] = f_static;
            f_static
        };
        let d = dir * f;
        force += d;
        moment += th.position.cross(&d);
    }
    join6(&force, &moment)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_curve_matches_paper_table() {
        // The paper's heave forces Z = 2·C⁺·n² for n = 30…70 % (Sec. 4.3).
        let c = ThrustCurve::Quadratic {
            ct_pos: 13.2e-6,
            ct_neg: 8.32e-6,
        };
        let paper = [
            0.0238, 0.0324, 0.0423, 0.0535, 0.0661, 0.08, 0.0952, 0.1117, 0.1295,
        ];
        for (k, z) in paper.iter().enumerate() {
            let n = 30.0 + 5.0 * k as f64;
            assert!(
                (2.0 * c.thrust(n) - z).abs() < 6e-4,
                "n={n}: {} vs {z}",
                2.0 * c.thrust(n)
            );
        }
        assert!((c.thrust(-100.0) + 0.0832).abs() < 1e-12);
        assert!((c.command_for(c.thrust(-37.0), 100.0) + 37.0).abs() < 1e-9);
        assert!((c.command_for(c.thrust(81.0), 100.0) - 81.0).abs() < 1e-9);
        assert_eq!(c.command_for(1.0, 100.0), 100.0);
    }

    #[test]
    fn table_curve_interpolates_and_inverts() {
        let c = ThrustCurve::Table {
            points: vec![(-100.0, -2.0), (-10.0, 0.0), (10.0, 0.0), (100.0, 4.0)],
        };
        assert_eq!(c.thrust(0.0), 0.0);
        assert!((c.thrust(55.0) - 2.0).abs() < 1e-12);
        assert_eq!(c.thrust(150.0), 4.0);
        assert!((c.command_for(2.0, 100.0) - 55.0).abs() < 1e-12);
        assert_eq!(c.command_for(0.0, 100.0), 0.0);
        assert_eq!(c.limits(100.0), (4.0, 2.0));
    }

    #[test]
    fn tilt_respects_rate_and_range() {
        let t = TiltParams {
            name: "beta".into(),
            axis: Vec3::y_axis(),
            min: -1.5,
            max: 1.5,
            rate_max: 1.0,
        };
        assert!((t.advance(0.0, -3.0, 0.1) + 0.1).abs() < 1e-15);
        assert_eq!(t.advance(-1.45, -3.0, 0.1), -1.5);
        assert_eq!(t.advance(0.2, 0.25, 0.1), 0.25);
    }

    /// A thruster without tilt drive, C⁺ = 1e-4 N/%², C⁻ = `ct_neg`, with a lag `lag` \[s\]
    /// and a slew-rate limit `ramp` \[s per 100 %\].
    fn plain(ct_neg: f64, lag: f64, ramp: f64) -> ThrusterParams {
        ThrusterParams {
            name: "a".into(),
            position: Vec3::zeros(),
            direction: Vec3::x_axis(),
            tilt: None,
            curve: ThrustCurve::Quadratic {
                ct_pos: 1e-4,
                ct_neg,
            },
            max_command: 100.0,
            lag,
            lag_down: -1.0,
            lag_stages: 1,
            ramp,
        }
    }

    /// One thruster's state at rest.
    fn at_rest() -> ActuatorState {
        ActuatorState {
            tilt: PerActuator::new(),
            thrust: PerActuator::from_elem(0.0, 1),
            stage: Vec::new(),
            command: Vec::new(),
        }
    }

    #[test]
    fn lag_is_first_order() {
        let th = plain(1e-4, 0.5, 0.0);
        let mut st = at_rest();
        let dt = 0.001;
        let mut t = 0.0;
        while t < 0.5 - 1e-12 {
            actuate(
                std::slice::from_ref(&th),
                &[],
                &mut st,
                &[100.0],
                &[],
                |_| true,
                dt,
            );
            t += dt;
        }
        // After one time constant: 1 − e⁻¹ of the static thrust (1 N).
        assert!(
            (st.thrust[0] - (1.0 - (-1.0f64).exp())).abs() < 1e-9,
            "{}",
            st.thrust[0]
        );
    }

    #[test]
    fn slew_rate_limit_turns_a_step_into_a_ramp_whose_length_grows_with_the_step() {
        // 0.8 s per 100 %: 125 %/s. A step to 50 % arrives after 0.4 s, one to 100 % after
        // 0.8 s; on the way the thrust is the curve's at the ramped command.
        let th = plain(2e-4, 0.0, 0.8);
        let dt = 0.01;
        for (step, arrival) in [(50.0, 0.4), (100.0, 0.8), (-100.0, 0.8)] {
            let mut st = at_rest();
            for k in 1..=100 {
                let tau = actuate(
                    std::slice::from_ref(&th),
                    &[],
                    &mut st,
                    &[step],
                    &[],
                    |_| true,
                    dt,
                );
                let t = k as f64 * dt;
                let n = if t < arrival {
                    125.0 * t * f64::signum(step)
                } else {
                    step
                };
                let ct = if n >= 0.0 { 1e-4 } else { 2e-4 };
                let f = ct * n * n.abs();
                assert!(
                    (st.command[0] - n).abs() < 1e-9,
                    "t {t}: {} %",
                    st.command[0]
                );
                assert!(
                    (tau[0] - f).abs() < 1e-12,
                    "t {t}: {} N, expected {f}",
                    tau[0]
                );
            }
        }
    }
}
