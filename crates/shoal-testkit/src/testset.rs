//! The misspecified-form test set: μAUV² logs with effects hidden in forms the fitting side
//! does not know ([`crate::truth_forms`]), written as a real logger writes them
//! ([`crate::logger`]), each with the catalogue families a correct verdict names.
//!
//! A case is a designed experiment ([`ExpKind`]: heave or yaw, [`crate::design`]) simulated at
//! 5 ms through the full sensor models ([`crate::synth::synthesize_with`]) with zero, one or two
//! truth forms hidden in it. Everything is deterministic: the experiment's levels and hold
//! times follow the case's seed, the form's parameters a ChaCha stream seeded by the form's
//! name, the experiment and the seed, the sensor noise another stream of the seed.
//!
//! * [`full`] — every truth form in every experiment that excites it with three seeds (lower
//!   half, upper half and all of each magnitude range), 14 pairs of families (each family in at
//!   least one pair, each pair in two combinations of its families' forms), 12 null runs.
//! * [`pinned_subset`] — 65 of them whose verdicts the tests pin: every form once, 8 pairs, 6
//!   nulls.
//!
//! [`Conditions`] change the log's length and the sensor noise (for the recovery benchmark).

use crate::logger::{format_g, logger_csv};
use crate::synth::{Experiment, synthesize_with};
use crate::truth_forms::{self, ExpKind, Truth, TruthForm};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_output::words::with_unit;
use shoal_sysid::log::run::MeasuredRun;
use std::collections::BTreeSet;

/// Physics step of the simulated truth \[s\].
pub const SIM_DT: f64 = 0.005;

/// Water density of the simulated pool [kg/m³] (fresh water).
pub const DENSITY: f64 = 1000.0;

/// Under what conditions a log is recorded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    /// Length of the log \[s\].
    pub duration: f64,
    /// Sensor noise (pressure, IMU, tracking) as a multiple of the μAUV² preset's \[-\]. The
    /// pressure sensor's 1.8 mm quantisation stays.
    pub noise: f64,
}

impl Default for Conditions {
    /// 120 s with the preset's noise.
    fn default() -> Self {
        Self {
            duration: 120.0,
            noise: 1.0,
        }
    }
}

/// A truth form hidden in a case, with its parameter values (units of its
/// [`TruthForm::params`]).
#[derive(Clone, Debug)]
pub struct Hidden {
    /// The form.
    pub form: TruthForm,
    /// Its parameter values.
    pub values: Vec<f64>,
}

impl Hidden {
    /// `form` with values drawn for `kind` and `seed` within magnitude `band` (see
    /// [`TruthForm::draw`]).
    pub fn draw(form: &TruthForm, kind: ExpKind, seed: u64, band: (f64, f64)) -> Self {
        Self::from_stream(form, stream(form.name, seed) ^ kind as u64, band)
    }

    /// `form` with values drawn from the ChaCha stream `stream` within magnitude `band`.
    pub fn from_stream(form: &TruthForm, stream: u64, band: (f64, f64)) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(stream);
        Self {
            form: form.clone(),
            values: form.draw(&mut rng, band),
        }
    }

    /// `form (name = value unit, …)`, values with four significant digits (no unit after a
    /// dimensionless value).
    pub fn describe(&self) -> String {
        let p: Vec<String> = self
            .form
            .params
            .iter()
            .zip(&self.values)
            .map(|(p, v)| format!("{} = {}", p.name, with_unit(&format_g(*v, 4), p.unit)))
            .collect();
        format!("{} ({})", self.form.name, p.join(", "))
    }
}

/// The catalogue families of `hidden`, sorted, without repeats: what an exact verdict names.
pub fn families(hidden: &[Hidden]) -> Vec<String> {
    let set: BTreeSet<&str> = hidden.iter().map(|h| h.form.family).collect();
    set.into_iter().map(str::to_string).collect()
}

/// The simulated truth of `hidden`: its forms with their values ([`Truth::new`]).
pub fn truth_of(hidden: &[Hidden]) -> Truth {
    let forms: Vec<(&TruthForm, &[f64])> = hidden
        .iter()
        .map(|h| (&h.form, h.values.as_slice()))
        .collect();
    Truth::new(&forms)
}

/// A case before simulation: what is hidden in which experiment.
#[derive(Clone, Debug)]
pub struct CaseSpec {
    /// Name (the file stem), e.g. `h_thruster_lag__slew_rate_1` or `y_pair_…_1`.
    pub name: String,
    /// The experiment.
    pub kind: ExpKind,
    /// Seed of the experiment's design and of the sensor noise.
    pub seed: u64,
    /// The hidden forms (none for a null run).
    pub hidden: Vec<Hidden>,
}

/// A simulated case.
#[derive(Clone, Debug)]
pub struct Case {
    /// Name (the file stem).
    pub name: String,
    /// The experiment.
    pub kind: ExpKind,
    /// The catalogue families of the hidden forms, sorted, without repeats: the exact verdict.
    pub expected: Vec<String>,
    /// The hidden forms with their values.
    pub hidden: Vec<Hidden>,
    /// The log as CSV text, in the logger's format.
    pub csv: String,
}

impl CaseSpec {
    /// The catalogue families of the hidden forms, sorted, without repeats.
    pub fn expected(&self) -> Vec<String> {
        families(&self.hidden)
    }

    /// Simulates the case under `cond` and writes its log.
    pub fn generate(&self, cond: &Conditions) -> Case {
        Case {
            name: self.name.clone(),
            kind: self.kind,
            expected: self.expected(),
            hidden: self.hidden.clone(),
            csv: self.csv(cond),
        }
    }

    /// The case's log under `cond`, as CSV text in the logger's format.
    pub fn csv(&self, cond: &Conditions) -> String {
        logger_csv(&self.run(cond))
    }

    /// The case's run under `cond` as simulated, before the logger prints it.
    pub fn run(&self, cond: &Conditions) -> MeasuredRun {
        let mut exp = self.kind.experiment(self.seed, cond.duration);
        exp.name.clone_from(&self.name);
        self.run_of(cond, &exp)
    }

    /// The experiment `exp` flown on the case's truth under `cond` (its sensor noise; the
    /// noise stream from the case's seed and `exp`'s name), before the logger prints it.
    pub fn run_of(&self, cond: &Conditions, exp: &Experiment) -> MeasuredRun {
        let mut truth = truth_of(&self.hidden);
        let mut params = presets::uauv2();
        params.pressure.noise_std *= cond.noise;
        params.imu.attitude_noise *= cond.noise;
        params.imu.gyro_noise *= cond.noise;
        params.imu.accel_noise *= cond.noise;
        let model = truth.model(params, DENSITY);
        let mut exp = exp.clone();
        exp.tracking_noise *= cond.noise;
        let noise_seed = self.seed ^ 0x5eed ^ fnv1a(&exp.name);
        let env = Environment {
            density: DENSITY,
            ..Environment::default()
        };
        synthesize_with(&model, &env, &exp, SIM_DT, noise_seed, &mut truth)
    }
}

/// The draw stream of a form named `name` with `seed`.
pub(crate) fn stream(name: &str, seed: u64) -> u64 {
    fnv1a(name) ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

/// FNV-1a hash of `s`: a stable seed from a name.
pub(crate) fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Magnitude band for a single-form seed: 1 the lower half of each range, 2 the upper half,
/// any other the whole range.
pub fn band_of_seed(seed: u64) -> (f64, f64) {
    match seed {
        1 => (0.0, 0.5),
        2 => (0.5, 1.0),
        _ => (0.0, 1.0),
    }
}

/// `form` hidden alone in `kind` with `seed` (magnitudes in [`band_of_seed`]).
pub fn single(form: &TruthForm, kind: ExpKind, seed: u64) -> CaseSpec {
    CaseSpec {
        name: format!("{}_{}__{}_{seed}", kind.tag(), form.family, form.form()),
        kind,
        seed,
        hidden: vec![Hidden::draw(form, kind, seed, band_of_seed(seed))],
    }
}

/// Two forms hidden together in `kind` with `seed` (magnitudes over their whole ranges).
pub fn pair(a: &TruthForm, b: &TruthForm, kind: ExpKind, seed: u64) -> CaseSpec {
    CaseSpec {
        name: format!(
            "{}_pair_{}+{}_{seed}",
            kind.tag(),
            a.name.replace('/', "__"),
            b.name.replace('/', "__")
        ),
        kind,
        seed,
        hidden: vec![
            Hidden::draw(a, kind, seed, (0.0, 1.0)),
            Hidden::draw(b, kind, seed, (0.0, 1.0)),
        ],
    }
}

/// Nothing hidden: the baseline is the truth.
pub fn null(kind: ExpKind, seed: u64) -> CaseSpec {
    CaseSpec {
        name: format!("{}_null_{seed}", kind.tag()),
        kind,
        seed,
        hidden: Vec::new(),
    }
}

/// The pairs of families (first, second, experiment): plausible combinations, every family in
/// at least one, each in an experiment that excites both.
pub const PAIRS: [(&str, &str, ExpKind); 14] = [
    ("buoyancy_offset", "thruster_lag", ExpKind::Heave),
    ("battery_sag", "thruster_deadband", ExpKind::Heave),
    ("depth_sensor_bias", "damping_error", ExpKind::Heave),
    ("sensor_delay", "thrust_gain", ExpKind::Yaw),
    ("ballast_mass", "thruster_lag", ExpKind::Heave),
    ("inflow_thrust_loss", "buoyancy_offset", ExpKind::Heave),
    ("added_mass_error", "thruster_deadband", ExpKind::Yaw),
    ("water_current", "thruster_lag", ExpKind::Yaw),
    ("thrust_coupling", "battery_sag", ExpKind::Heave),
    ("thrust_asymmetry", "depth_sensor_bias", ExpKind::Heave),
    ("thrust_saturation", "buoyancy_offset", ExpKind::Heave),
    ("damping_error", "sensor_delay", ExpKind::Yaw),
    ("thrust_gain", "ballast_mass", ExpKind::Heave),
    ("restoring_moment", "buoyancy_offset", ExpKind::Trim),
];

/// Pair `i` of [`PAIRS`] with `seed`: seed s takes form (s − 1) of the first family and form s
/// of the second (cyclically), so seeds 1 and 2 cover both crossed combinations of two-form
/// families (with three forms in the second family, seed 2 takes its third).
pub fn pair_case(i: usize, seed: u64) -> CaseSpec {
    let (fa, fb, kind) = PAIRS[i];
    let (a, b) = (truth_forms::of_family(fa), truth_forms::of_family(fb));
    let s = seed as usize;
    pair(&a[(s + a.len() - 1) % a.len()], &b[s % b.len()], kind, seed)
}

/// The whole test set (328 cases): every form in every experiment that excites it with seeds
/// 1, 2, 3; every pair of [`PAIRS`] with seeds 1, 2; null runs in every experiment with seeds
/// 1 … 4.
pub fn full() -> Vec<CaseSpec> {
    let mut out = Vec::new();
    for form in truth_forms::designed() {
        for &kind in form.excites {
            for seed in 1..=3 {
                out.push(single(&form, kind, seed));
            }
        }
    }
    for i in 0..PAIRS.len() {
        for seed in 1..=2 {
            out.push(pair_case(i, seed));
        }
    }
    for kind in ExpKind::ALL {
        for seed in 1..=4 {
            out.push(null(kind, seed));
        }
    }
    out
}

/// Pairs of [`PAIRS`] in [`pinned_subset`] (the first ones: twelve families, both experiments).
pub const PINNED_PAIRS: usize = 8;

/// The subset of [`full`] whose verdicts the tests pin (65 cases, about 45 CPU-minutes of
/// search): every form once with seed 3 (whole magnitude range; the first form of a family in
/// its first experiment, the later ones in its last, so both experiments appear where both
/// excite the family), the first [`PINNED_PAIRS`] pairs with seed 1, null runs in every
/// experiment with seeds 1 and 2.
pub fn pinned_subset() -> Vec<CaseSpec> {
    let mut out = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for form in &truth_forms::designed() {
        let first = !seen.contains(&form.family);
        seen.push(form.family);
        let kind = if first {
            form.excites[0]
        } else {
            form.excites[form.excites.len() - 1]
        };
        out.push(single(form, kind, 3));
    }
    for i in 0..PINNED_PAIRS {
        out.push(pair_case(i, 1));
    }
    for kind in ExpKind::ALL {
        for seed in 1..=2 {
            out.push(null(kind, seed));
        }
    }
    out
}

/// `expected.json` of a set of cases: `{ "<name>": ["<family>", …], … }` (names sorted), the
/// format of the shared `validation_dev/expected.json`.
pub fn expected_json(cases: &[CaseSpec]) -> String {
    let map: std::collections::BTreeMap<&str, Vec<String>> = cases
        .iter()
        .map(|c| (c.name.as_str(), c.expected()))
        .collect();
    serde_json::to_string_pretty(&map).expect("a map of strings serialises")
}

/// `truth.json` of a set of cases: per case its experiment, seed, expected families and the
/// hidden forms with their parameter values (for whoever debugs a verdict, not for the tool).
pub fn truth_json(cases: &[CaseSpec]) -> String {
    let list: Vec<serde_json::Value> = cases
        .iter()
        .map(|c| {
            let hidden: Vec<serde_json::Value> = c
                .hidden
                .iter()
                .map(|h| {
                    let params: serde_json::Map<String, serde_json::Value> = h
                        .form
                        .params
                        .iter()
                        .zip(&h.values)
                        .map(|(p, v)| (p.name.to_string(), serde_json::json!(v)))
                        .collect();
                    serde_json::json!({
                        "form": h.form.name,
                        "family": h.form.family,
                        "law": h.form.law,
                        "params": params,
                    })
                })
                .collect();
            serde_json::json!({
                "name": c.name,
                "experiment": c.kind.name(),
                "seed": c.seed,
                "expected": c.expected(),
                "hidden": hidden,
            })
        })
        .collect();
    serde_json::to_string_pretty(&list).expect("JSON values serialise")
}

#[cfg(test)]
mod tests {
    use super::*;
    use shoal_sysid::log::run::ChannelKind;

    /// A dimensionless parameter prints without a unit ("a = 0.25", not "a = 0.25 -"); the
    /// others with theirs.
    #[test]
    fn descriptions_print_no_unit_after_a_dimensionless_value() {
        let hidden = Hidden {
            form: truth_forms::by_name("battery_sag/knee").expect("the knee form"),
            values: vec![0.25, 60.0, 10.0],
        };
        assert_eq!(
            hidden.describe(),
            "battery_sag/knee (a = 0.25, t_k_s = 60 s, w_s = 10 s)"
        );
        let a = &hidden.form.params[0];
        assert_eq!(a.range_text(), "0.2 … 0.35");
    }

    #[test]
    fn sets_cover_every_form_and_family_and_names_are_unique() {
        let all = full();
        let ci = pinned_subset();
        assert_eq!(all.len(), 328);
        assert_eq!(ci.len(), 65);
        for family in truth_forms::designed_families() {
            assert!(
                all.iter()
                    .any(|c| c.hidden.len() == 2 && c.expected().iter().any(|e| e == family)),
                "{family} in no pair"
            );
        }
        for set in [&all, &ci] {
            let names: BTreeSet<&str> = set.iter().map(|c| c.name.as_str()).collect();
            assert_eq!(names.len(), set.len(), "duplicate case names");
            for form in truth_forms::designed() {
                assert!(
                    set.iter()
                        .any(|c| c.hidden.len() == 1 && c.hidden[0].form.name == form.name),
                    "{} missing",
                    form.name
                );
            }
            assert!(set.iter().any(|c| c.hidden.len() == 2));
            for kind in ExpKind::ALL {
                assert!(set.iter().any(|c| c.hidden.is_empty() && c.kind == kind));
            }
        }
        // Every case's experiment excites every form hidden in it.
        for c in &all {
            for h in &c.hidden {
                assert!(h.form.excites.contains(&c.kind), "{}", c.name);
            }
        }
        let p = pair_case(0, 1);
        assert_eq!(p.expected(), vec!["buoyancy_offset", "thruster_lag"]);
    }

    /// Every form, at the weak end of its magnitude ranges and without noise, moves some logged
    /// channel of every experiment it excites by at least 5 noise standard deviations (RMS
    /// over the run), as the catalogue's realistic ranges do: "clearly present".
    #[test]
    fn every_form_is_clearly_present_at_the_weak_end_of_its_ranges() {
        let p = presets::uauv2();
        let quantisation = p.pressure.depth_step / 12f64.sqrt();
        let cond = Conditions {
            duration: 120.0,
            noise: 0.0,
        };
        for kind in ExpKind::ALL {
            let tracking = kind.experiment(1, 1.0).tracking_noise;
            let sigma = |k: ChannelKind| match k {
                ChannelKind::Depth => p.pressure.noise_std.hypot(quantisation),
                ChannelKind::Roll | ChannelKind::Pitch | ChannelKind::Yaw => p.imu.attitude_noise,
                ChannelKind::P | ChannelKind::Q | ChannelKind::R => p.imu.gyro_noise,
                _ => tracking,
            };
            let base = null(kind, 1).run(&cond);
            for form in truth_forms::all() {
                if !form.excites.contains(&kind) {
                    continue;
                }
                let spec = CaseSpec {
                    name: format!("weak_{}", form.name.replace('/', "__")),
                    kind,
                    seed: 1,
                    hidden: vec![Hidden::draw(&form, kind, 1, (0.0, 0.0))],
                };
                let run = spec.run(&cond);
                let snr: Vec<(ChannelKind, f64)> = run
                    .channels
                    .iter()
                    .zip(&base.channels)
                    .map(|(a, b)| {
                        let ms = a
                            .values
                            .iter()
                            .zip(&b.values)
                            .map(|(x, y)| {
                                let d = if a.kind.is_angle() {
                                    shoal_model::math::wrap_pi(x - y)
                                } else {
                                    x - y
                                };
                                d * d
                            })
                            .sum::<f64>()
                            / a.values.len() as f64;
                        (a.kind, ms.sqrt() / sigma(a.kind))
                    })
                    .collect();
                let best = snr.iter().map(|s| s.1).fold(0.0, f64::max);
                assert!(
                    best >= 5.0,
                    "{} in {kind:?}: {snr:?}",
                    spec.hidden[0].describe()
                );
            }
        }
    }

    /// The log is what a logger writes and what the tool reads: every row filled, six
    /// significant digits (the tilt at its limit reads −1.5708), 50 Hz, depth on the sensor's
    /// 1.8 mm grid — and the generator is deterministic.
    #[test]
    fn logs_are_in_logger_format_and_reproducible() {
        let spec = single(
            &truth_forms::by_name("thruster_lag/slew_rate").unwrap(),
            ExpKind::Heave,
            1,
        );
        let cond = Conditions {
            duration: 10.0,
            noise: 1.0,
        };
        let csv = spec.csv(&cond);
        assert_eq!(csv, spec.csv(&cond), "deterministic");
        let mut lines = csv.lines();
        assert_eq!(
            lines.next(),
            Some("t,u.alpha,u.beta,u.top,u.port,u.stbd,u.pump,y.depth,y.yaw,y.r")
        );
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 501);
        let step = presets::uauv2().pressure.depth_step;
        let c2 = presets::uauv2().pressure.c2;
        for (k, r) in rows.iter().enumerate() {
            assert_eq!(r.len(), 10);
            assert!(r.iter().all(|c| !c.is_empty()), "row {k}: {r:?}");
            assert_eq!(r[2], "-1.5708");
            let t: f64 = r[0].parse().unwrap();
            assert!((t - 0.02 * k as f64).abs() < 1e-9);
            for c in r {
                let digits = c
                    .trim_start_matches('-')
                    .split('e')
                    .next()
                    .unwrap()
                    .replace('.', "")
                    .trim_start_matches('0')
                    .len();
                assert!(digits <= 6, "{c}");
            }
            let d: f64 = r[7].parse().unwrap();
            let steps = (d - c2) / step;
            assert!(
                (steps - steps.round()).abs() < 1e-3,
                "depth {d} off the grid"
            );
        }
        // Yaw logs have a level tilt, so they parse today (the heave tilt of −1.5708 is a
        // rounded −π/2 that the parser's tolerance decides on).
        let yaw = null(ExpKind::Yaw, 1).csv(&cond);
        let run = MeasuredRun::parse(&yaw, std::path::Path::new("y_null_1.csv")).unwrap();
        assert_eq!(run.t.len(), 501);
        assert!(run.channel(ChannelKind::X).is_some());
    }
}
