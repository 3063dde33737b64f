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
mod effect_meta;
mod exp_kind;
mod form_param;
mod inflow_thrust_loss;
mod logistic;
mod restoring_moment;
mod sensor_delay;
mod tether_drag;
mod thrust_asymmetry;
mod thrust_coupling;
mod thrust_gain;
mod thrust_saturation;
mod thruster_deadband;
mod thruster_lag;
mod truth_form;
mod water_current;

use crate::synth::TruthHook;
pub use exp_kind::ExpKind;
pub use form_param::{Draw, FormParam};
use shoal_model::control::ActuatorCommands;
use shoal_model::dynamics::RigidState;
use shoal_model::effects::{EffectInstance, Effects};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleParams, VehicleState};
use std::fmt;
pub use truth_form::{Part, TruthForm};

/// Typical speeds of the designed experiments per degree of freedom, the reference for forms
/// whose law depends on speed (the catalogue's, [`shoal_model::effects::NU_REF`]).
pub use shoal_model::effects::NU_REF;

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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
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
