//! Truth forms: physically plausible ways a real vehicle can have a catalogue effect's physics
//! in a functional form that **differs from every form the fitting side knows** — an
//! underdamped motor instead of a first-order lag, a dead band that ramps instead of cutting,
//! a sensor that averages instead of delaying. They exist only to simulate test logs
//! ([`crate::testset`]): the search must name the effect's *family* (its catalogue name)
//! even when the data's law is not the catalogue's.
//!
//! Every family has at least two such forms. A few forms have since become fitting forms of
//! their family and stay in the set as *matched* forms ([`MATCHED`]).
//!
//! Each form is a [`TruthForm`]: a name `family/form`, the catalogue family it belongs to (the
//! verdict a correct search gives), its parameters with realistic ranges (magnitudes drawn per
//! seed, always clearly present), and the experiments that excite it. A form enters the
//! simulation in one of two ways ([`Part`]):
//! * as a [`shoal_model::effects::Effect`] whose hooks need no state of their own (a dead band
//!   with a ramp, a bias that drifts quadratically, a gas bubble that compresses with depth);
//! * as a [`TruthHook`] of [`crate::synth::synthesize_with`] where the law has state the effect
//!   hooks cannot carry: it filters the commands the truth sees (motor dynamics, slew limits,
//!   a sagging voltage) while the log keeps the commanded values, integrates a pump's flow,
//!   changes the water, couples an internal mass, or shows the sensors a filtered hull state.
//!
//! One file per catalogue family holds that family's forms. [`Truth`] assembles the forms
//! hidden in one run.

mod added_mass_error;
mod ballast_mass;
mod battery_sag;
mod buoyancy_offset;
mod damping_error;
mod depth_sensor_bias;
mod inflow_thrust_loss;
mod restoring_moment;
mod sensor_delay;
mod tether_drag;
mod thrust_asymmetry;
mod thrust_coupling;
mod thrust_gain;
mod thrust_saturation;
mod thruster_deadband;
mod thruster_lag;
mod water_current;

use crate::design;
use crate::synth::{Experiment, TruthHook};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use shoal_model::control::ActuatorCommands;
use shoal_model::dynamics::RigidState;
use shoal_model::effects::{Effect, EffectInstance, Effects};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams, VehicleState};
use shoal_output::words::with_unit;
use std::fmt;
use std::sync::Arc;

/// Typical speeds of the designed experiments per degree of freedom, the reference for forms
/// whose law depends on speed (the catalogue's, [`shoal_model::effects::NU_REF`]).
pub use shoal_model::effects::NU_REF;

/// Which designed μAUV² experiment ([`crate::design`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ExpKind {
    /// Diving mode, 1-DOF heave ([`design::uauv2_heave`]): logs depth, heading and yaw rate.
    Heave,
    /// Turning mode, 1-DOF yaw ([`design::uauv2_yaw`]): logs heading, yaw rate, depth and
    /// the tracked position.
    Yaw,
    /// Diving mode with the attitude logged ([`design::uauv2_trim`]): logs depth, roll,
    /// pitch, heading and yaw rate.
    Trim,
}

impl ExpKind {
    /// Every experiment.
    pub const ALL: [ExpKind; 3] = [ExpKind::Heave, ExpKind::Yaw, ExpKind::Trim];

    /// The experiment for `seed`, `duration` \[s\] long.
    pub fn experiment(self, seed: u64, duration: f64) -> Experiment {
        match self {
            ExpKind::Heave => design::uauv2_heave(seed, duration),
            ExpKind::Yaw => design::uauv2_yaw(seed, duration),
            ExpKind::Trim => design::uauv2_trim(seed, duration),
        }
    }

    /// Short tag used in case names: `h`, `y` or `t`.
    pub fn tag(self) -> &'static str {
        match self {
            ExpKind::Heave => "h",
            ExpKind::Yaw => "y",
            ExpKind::Trim => "t",
        }
    }

    /// Lower-case name: `heave`, `yaw` or `trim`.
    pub fn name(self) -> &'static str {
        match self {
            ExpKind::Heave => "heave",
            ExpKind::Yaw => "yaw",
            ExpKind::Trim => "trim",
        }
    }
}

/// How a parameter's value is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Draw {
    /// A magnitude: uniform within the part of `lo … hi` that the magnitude band selects.
    Magnitude,
    /// A magnitude as above, with a random sign.
    Signed,
    /// A magnitude whose effect grows as the value falls (a factor below one, a time
    /// constant's inverse): the band's weak end is `hi`, its strong end `lo`.
    Deficit,
    /// A shape parameter (phase, direction, …): uniform over all of `lo … hi`, whatever the
    /// band.
    Shape,
}

/// One parameter of a truth form.
#[derive(Clone, Debug, PartialEq)]
pub struct FormParam {
    /// Name with its unit as a suffix where it has one (e.g. `omega_rad_s`).
    pub name: &'static str,
    /// Unit in words (e.g. `rad/s`, `-`).
    pub unit: &'static str,
    /// Smallest value (magnitude for [`Draw::Signed`]; the strong end for [`Draw::Deficit`]),
    /// in [`FormParam::unit`].
    pub lo: f64,
    /// Largest value (magnitude for [`Draw::Signed`]; the weak end for [`Draw::Deficit`]), in
    /// [`FormParam::unit`].
    pub hi: f64,
    /// How it is drawn.
    pub draw: Draw,
    /// What it means.
    pub doc: &'static str,
}

impl FormParam {
    /// A magnitude in `lo … hi` [`unit`](FormParam::unit).
    pub const fn magnitude(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            lo,
            hi,
            draw: Draw::Magnitude,
            doc,
        }
    }

    /// A magnitude in `lo … hi` [`unit`](FormParam::unit) with a random sign.
    pub const fn signed(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Signed,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// A magnitude in `lo … hi` [`unit`](FormParam::unit) whose effect is the stronger the
    /// smaller it is.
    pub const fn deficit(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Deficit,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// A shape parameter uniform in `lo … hi` [`unit`](FormParam::unit).
    pub const fn shape(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Shape,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// The range as text, e.g. `±0.01 … 0.03 m` or `2.5 … 5 rad/s`.
    pub fn range_text(&self) -> String {
        let sign = if self.draw == Draw::Signed { "±" } else { "" };
        with_unit(&format!("{sign}{} … {}", self.lo, self.hi), self.unit)
    }
}

/// How a truth form enters the simulation.
pub enum Part {
    /// Through the model's effect hooks (stateless laws). The effect carries its own values;
    /// its [`Effect::params`] is empty.
    Effect(Arc<dyn Effect>),
    /// Around every physics step and sample (laws with state of their own).
    Hook(Box<dyn TruthHook>),
}

impl fmt::Debug for Part {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Part::Effect(e) => write!(f, "Effect({})", e.name()),
            Part::Hook(_) => write!(f, "Hook"),
        }
    }
}

/// A truth form: one law of one catalogue family's physics.
#[derive(Clone, Debug)]
pub struct TruthForm {
    /// `family/form`, e.g. `thruster_lag/slew_rate`.
    pub name: &'static str,
    /// The catalogue effect whose physics this is (`Effect::name()`), the expected verdict.
    pub family: &'static str,
    /// The law in one line.
    pub law: &'static str,
    /// The parameters, in the order [`TruthForm::part`] takes them.
    pub params: Vec<FormParam>,
    /// The designed experiments whose logs show it. Empty for a form none shows — a tether
    /// needs the hull to travel, which the designed experiments do not (and an open-loop
    /// surge leg cannot: the μAUV² is directionally unstable and spins within seconds); such
    /// forms are hidden only in the closed-loop missions ([`crate::closed_loop`]).
    pub excites: &'static [ExpKind],
    /// Builds the part from parameter values.
    build: fn(&[f64]) -> Part,
}

impl TruthForm {
    /// The form's own name (after the `/`).
    pub fn form(&self) -> &'static str {
        self.name.split_once('/').map_or(self.name, |(_, f)| f)
    }

    /// Draws parameter values: magnitudes uniformly within `band`, a sub-interval of 0 … 1 from
    /// the weak to the strong end of each magnitude's range ((0, 1) is the whole range,
    /// (0.5, 1) its stronger half); shapes over their whole range.
    pub fn draw(&self, rng: &mut ChaCha8Rng, band: (f64, f64)) -> Vec<f64> {
        let (b0, b1) = (band.0.clamp(0.0, 1.0), band.1.clamp(0.0, 1.0));
        self.params
            .iter()
            .map(|p| {
                let u = match p.draw {
                    Draw::Shape => rng.random_range(0.0..1.0),
                    _ => b0 + (b1 - b0) * rng.random_range(0.0..1.0),
                };
                let v = match p.draw {
                    Draw::Deficit => p.hi - (p.hi - p.lo) * u,
                    _ => p.lo + (p.hi - p.lo) * u,
                };
                if p.draw == Draw::Signed && rng.random_bool(0.5) {
                    -v
                } else {
                    v
                }
            })
            .collect()
    }

    /// The part for parameter `values` (in the order of [`TruthForm::params`]).
    ///
    /// # Panics
    /// If `values` has the wrong length.
    pub fn part(&self, values: &[f64]) -> Part {
        assert_eq!(
            values.len(),
            self.params.len(),
            "{} takes {} parameters",
            self.name,
            self.params.len()
        );
        (self.build)(values)
    }
}

/// The truth forms whose law a fitting form of their family has: (truth form, fitting form).
/// They stay in the test set; the other forms of each family differ from every fitting form.
pub const MATCHED: [(&str, &str); 19] = [
    ("thruster_deadband/asymmetric_soft", "soft_asymmetric"),
    ("thrust_asymmetry/reverse_exponent", "curve"),
    ("inflow_thrust_loss/quadratic", "power"),
    ("thruster_lag/slew_rate", "slew"),
    ("thrust_gain/command_dependent", "curve"),
    ("thrust_saturation/asymmetric_caps", "asymmetric"),
    ("thrust_saturation/algebraic_soft", "smooth"),
    ("thruster_deadband/asymmetric", "asymmetric"),
    ("battery_sag/quadratic", "power"),
    ("damping_error/direction_dependent", "direction"),
    ("depth_sensor_bias/quadratic_drift", "power_drift"),
    ("buoyancy_offset/slow_leak", "drift"),
    ("buoyancy_offset/venting_air", "settling"),
    ("damping_error/speed_exponent", "power"),
    ("thrust_coupling/direction_dependent", "direction"),
    ("thrust_gain/two_slope", "knee"),
    ("thrust_asymmetry/reverse_per_thruster", "sided"),
    ("restoring_moment/flooding_end", "settling"),
    ("thrust_gain/per_thruster", "per_thruster"),
];

/// The logistic function 1/(1 + e^(−x)): the S-shaped law of several truth forms (a battery's
/// knee, a thermocline, a throttle map that bends smoothly).
pub(super) fn logistic(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}

/// The fitting form whose law truth form `name` (`family/form`) has, if any ([`MATCHED`]).
pub fn matched_by(name: &str) -> Option<&'static str> {
    MATCHED.iter().find(|(t, _)| *t == name).map(|(_, f)| *f)
}

/// Every truth form, in catalogue order of their families.
pub fn all() -> Vec<TruthForm> {
    [
        thruster_lag::forms(),
        thrust_gain::forms(),
        thrust_asymmetry::forms(),
        thruster_deadband::forms(),
        battery_sag::forms(),
        inflow_thrust_loss::forms(),
        buoyancy_offset::forms(),
        ballast_mass::forms(),
        damping_error::forms(),
        added_mass_error::forms(),
        restoring_moment::forms(),
        water_current::forms(),
        depth_sensor_bias::forms(),
        sensor_delay::forms(),
        thrust_coupling::forms(),
        thrust_saturation::forms(),
        tether_drag::forms(),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The truth forms that some designed experiment shows (all but those hidden only in the
/// closed-loop missions, [`TruthForm::excites`]), in catalogue order of their families: what
/// the designed test sets and the recovery benchmark draw from.
pub fn designed() -> Vec<TruthForm> {
    all()
        .into_iter()
        .filter(|f| !f.excites.is_empty())
        .collect()
}

/// The catalogue families with a [`designed`] truth form, in catalogue order.
pub fn designed_families() -> Vec<&'static str> {
    let forms = designed();
    shoal_model::effects::names()
        .into_iter()
        .filter(|n| forms.iter().any(|f| f.family == *n))
        .collect()
}

/// The truth form named `name` (`family/form`).
pub fn by_name(name: &str) -> Option<TruthForm> {
    all().into_iter().find(|f| f.name == name)
}

/// The truth forms of catalogue family `family`.
pub fn of_family(family: &str) -> Vec<TruthForm> {
    all().into_iter().filter(|f| f.family == family).collect()
}

/// The hidden truth of one simulated run: forms with their values, assembled into effects for
/// the vehicle model and hooks for the simulation.
pub struct Truth {
    /// The stateless forms, for [`Truth::model`].
    pub effects: Vec<EffectInstance>,
    hooks: Vec<Box<dyn TruthHook>>,
}

impl fmt::Debug for Truth {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.effects.iter().map(|e| e.effect.name()).collect();
        write!(
            f,
            "Truth {{ effects: {names:?}, hooks: {} }}",
            self.hooks.len()
        )
    }
}

impl Truth {
    /// Assembles `hidden` forms with their parameter values. Hooks run in the given order; at
    /// most one of them should change what the sensors see (the first that does wins).
    pub fn new(hidden: &[(&TruthForm, &[f64])]) -> Self {
        let mut effects = Vec::new();
        let mut hooks = Vec::new();
        for (form, values) in hidden {
            match form.part(values) {
                Part::Effect(effect) => effects.push(EffectInstance {
                    effect,
                    params: Vec::new(),
                }),
                Part::Hook(h) => hooks.push(h),
            }
        }
        Self { effects, hooks }
    }

    /// The vehicle model of the truth: `base` with the stateless forms as its effects, in water
    /// of `density` [kg/m³].
    pub fn model(&self, base: VehicleParams, density: f64) -> VehicleModel {
        VehicleModel::with_effects(base, Effects::new(self.effects.clone()), density)
    }
}

impl TruthHook for Truth {
    fn before_actuate(
        &mut self,
        model: &VehicleModel,
        state: &mut VehicleState,
        cmd: &mut ActuatorCommands,
        env: &mut Environment,
        dt: f64,
    ) {
        for h in &mut self.hooks {
            h.before_actuate(model, state, cmd, env, dt);
        }
    }

    fn before_integrate(
        &mut self,
        model: &VehicleModel,
        state: &mut VehicleState,
        env: &Environment,
        dt: f64,
    ) {
        for h in &mut self.hooks {
            h.before_integrate(model, state, env, dt);
        }
    }

    fn sensed(&mut self, state: &VehicleState) -> Option<RigidState> {
        let mut seen = None;
        for h in &mut self.hooks {
            // Every hook is asked, so that each keeps its own history.
            let s = h.sensed(state);
            if seen.is_none() {
                seen = s;
            }
        }
        seen
    }
}

/// The descriptive methods of an [`Effect`] that is a truth form: not fittable (no parameters;
/// the values live in the struct), named after its form, summarised and explained by its law.
macro_rules! truth_effect_meta {
    // A type that carries its name and law in fields `name` and `law`.
    (fields) => {
        fn name(&self) -> &'static str {
            self.name
        }
        fn summary(&self) -> &'static str {
            self.law
        }
        fn explanation(&self) -> &'static str {
            self.law
        }
        fn params(
            &self,
            _vehicle: &shoal_model::vehicle::VehicleParams,
        ) -> Vec<shoal_model::effects::ParamInfo> {
            Vec::new()
        }
    };
    ($name:expr, $law:expr) => {
        fn name(&self) -> &'static str {
            $name
        }
        fn summary(&self) -> &'static str {
            $law
        }
        fn explanation(&self) -> &'static str {
            $law
        }
        fn params(
            &self,
            _vehicle: &shoal_model::vehicle::VehicleParams,
        ) -> Vec<shoal_model::effects::ParamInfo> {
            Vec::new()
        }
    };
}
pub(crate) use truth_effect_meta;

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use std::collections::BTreeSet;

    #[test]
    fn every_family_has_two_unmatched_forms_and_names_are_unique() {
        let forms = all();
        let names: BTreeSet<&str> = forms.iter().map(|f| f.name).collect();
        assert_eq!(names.len(), forms.len(), "duplicate form names");
        for family in shoal_model::effects::names() {
            let n = forms
                .iter()
                .filter(|f| f.family == family && matched_by(f.name).is_none())
                .count();
            assert!(
                n >= 2,
                "{family} has {n} truth forms no fitting form matches"
            );
        }
        for (name, _) in MATCHED {
            assert!(
                names.contains(name),
                "matched form {name} is not a truth form"
            );
        }
        for f in &forms {
            assert!(
                shoal_model::effects::by_name(f.family).is_some(),
                "{}: unknown family",
                f.name
            );
            assert!(f.name.starts_with(&format!("{}/", f.family)), "{}", f.name);
            for p in &f.params {
                assert!(p.lo <= p.hi, "{}.{}", f.name, p.name);
                if p.draw != Draw::Shape {
                    assert!(p.lo >= 0.0, "{}.{}: magnitudes are ≥ 0", f.name, p.name);
                }
            }
        }
    }

    #[test]
    fn draws_stay_in_range_and_are_reproducible() {
        for f in all() {
            let mut a = ChaCha8Rng::seed_from_u64(3);
            let mut b = ChaCha8Rng::seed_from_u64(3);
            let x = f.draw(&mut a, (0.5, 1.0));
            assert_eq!(x, f.draw(&mut b, (0.5, 1.0)), "{}", f.name);
            for (p, v) in f.params.iter().zip(&x) {
                let m = if p.draw == Draw::Signed { v.abs() } else { *v };
                assert!(m >= p.lo && m <= p.hi, "{}.{} = {v}", f.name, p.name);
                let mid = p.lo + 0.5 * (p.hi - p.lo);
                match p.draw {
                    Draw::Magnitude | Draw::Signed => assert!(m >= mid - 1e-12, "{}", p.name),
                    Draw::Deficit => assert!(m <= mid + 1e-12, "{}", p.name),
                    Draw::Shape => {}
                }
            }
            // Every form builds.
            let _ = Truth::new(&[(&f, &x)]);
        }
    }
}
