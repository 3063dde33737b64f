//! The long closed-loop test set: μAUV² missions of many minutes ([`crate::mission`]) flown
//! by the vehicle's own controllers in gusting water with a hull a few per cent off its
//! nominal parameters, each with one effect hidden in it (or none), written as a real logger
//! writes them ([`crate::logger`]). Open loop from the first sample the replay of such a log
//! leaves the data within a minute; the set asks whether the search, replaying re-anchored,
//! still names exactly the hidden family.
//!
//! One case per catalogue family — its truth form whose law a fitting form has where there is
//! one ([`crate::truth_forms::MATCHED`]), else its first — with values over the form's whole
//! range (laws in run time stretched to the mission: [`STRETCHED`]), and three null missions
//! (disturbances only). `water_current` is left out: the
//! mission logs carry no position, and the wandering current is on every case already; so is
//! every family the search fits only on channels a mission does not log
//! ([`shoal_sysid::search::direct_channels`]: `tether_drag`, whose pull depends on where the
//! hull is). [`tracked_cases`] are missions that log the tracked position, for it.
//!
//! Everything is deterministic in the case's seed.

use crate::logger::logger_csv;
use crate::mission::{Disturbance, MissionPlan, fly, perturb, uauv2_mission};
use crate::testset::{DENSITY, Hidden, SIM_DT, families, fnv1a, stream, truth_of};
use crate::truth_forms::{self, TruthForm};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use shoal_model::math::euler_rpy;
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::log::run::{ChannelKind, MeasuredRun};
use shoal_sysid::search::direct_channels;
use shoal_world::desc::WorldDesc;

/// Mission length of the set \[s\] (10 minutes).
pub const MISSION_S: f64 = 600.0;

/// A closed-loop case before simulation.
#[derive(Clone, Debug)]
pub struct MissionCase {
    /// Name (the file stem), e.g. `m_thruster_lag__slew_rate_4` or `m_null_1`.
    pub name: String,
    /// Seed of the mission, the parameter noise, the gusts and the sensor noise.
    pub seed: u64,
    /// Mission length \[s\].
    pub duration: f64,
    /// The hidden forms (none for a null mission).
    pub hidden: Vec<Hidden>,
    /// Whether the position is tracked: logged as `y.x`, `y.y` with [`TRACKING_NOISE`].
    pub tracked: bool,
}

/// Standard deviation of a tracked mission's positions \[m\] (acoustic or camera tracking in
/// a pool).
pub const TRACKING_NOISE: f64 = 0.02;

impl MissionCase {
    /// The catalogue families of the hidden forms, sorted, without repeats: the exact verdict.
    pub fn expected(&self) -> Vec<String> {
        families(&self.hidden)
    }

    /// The mission flown under `dist`, as logged.
    pub fn run(&self, dist: &Disturbance) -> MeasuredRun {
        let mut plan = uauv2_mission(self.seed, self.duration);
        plan.name.clone_from(&self.name);
        self.fly_plan(dist, plan)
    }

    /// A second flight of the case's vehicle (the same hidden truth and hull) in the same
    /// water (`dist`, fresh gusts and sensor noise): the first vehicle of `world` — a flight
    /// such as `next_experiment.toml` describes, its own mission from its own start — logged
    /// as the mission is, named `name`.
    pub fn fly_world(&self, dist: &Disturbance, world: &WorldDesc, name: &str) -> MeasuredRun {
        let mut plan = uauv2_mission(self.seed, self.duration);
        let v = &world.vehicles[0];
        plan.name = name.to_string();
        plan.duration = world.duration;
        plan.mission = (*v.mission).clone();
        plan.position = v.position;
        plan.yaw = euler_rpy(&v.attitude).2;
        self.fly_plan(dist, plan)
    }

    /// `plan` flown by the case's truth (its hidden forms, the hull perturbed by the case's
    /// seed) under `dist`, gusts and sensor noise seeded by the case and the plan's name,
    /// logging the tracked position too where the case is tracked.
    fn fly_plan(&self, dist: &Disturbance, mut plan: MissionPlan) -> MeasuredRun {
        if self.tracked {
            plan.channels.extend([ChannelKind::X, ChannelKind::Y]);
            plan.tracking_noise = TRACKING_NOISE;
        }
        let noise_seed = self.seed ^ 0x5eed ^ fnv1a(&plan.name);
        let mut truth = truth_of(&self.hidden);
        let mut params = presets::uauv2();
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed ^ 0x7061_7261);
        perturb(&mut params, dist.param_noise, &mut rng);
        let model = truth.model(params, DENSITY);
        let designed = VehicleModel::new(presets::uauv2(), DENSITY);
        let env = Environment {
            density: DENSITY,
            ..Environment::default()
        };
        fly(
            &model, &designed, &env, &plan, dist, SIM_DT, noise_seed, &mut truth,
        )
    }

    /// The case's log as CSV text in the logger's format.
    pub fn csv(&self, dist: &Disturbance) -> String {
        logger_csv(&self.run(dist))
    }
}

/// The form hidden for `family`: its matched form if it has one, else its first.
fn form_of(family: &str) -> Option<TruthForm> {
    let forms = truth_forms::of_family(family);
    forms
        .iter()
        .find(|f| truth_forms::matched_by(f.name).is_some())
        .or(forms.first())
        .cloned()
}

/// Parameters of truth forms whose ranges say what the law does over a 120-s experiment (a
/// battery's sag, a sensor's thermal drift, both ∝ t²) rather than a physical rate: (form,
/// parameter, power of the time). Over a mission of T seconds their values are multiplied by
/// (120 s / T)^power, so that the effect reaches by the mission's end the size it reaches by
/// an experiment's. Physical rates (a leak's µl/s) and time constants stay as drawn.
pub const STRETCHED: [(&str, &str, i32); 2] = [
    ("battery_sag/quadratic", "c_per_s2", 2),
    ("depth_sensor_bias/quadratic_drift", "b2_m_s2", 2),
];

/// `hidden` with its [`STRETCHED`] parameters stretched to a mission of `duration` \[s\].
fn stretch(mut hidden: Hidden, duration: f64) -> Hidden {
    for (form, param, power) in STRETCHED {
        if hidden.form.name != form {
            continue;
        }
        if let Some(i) = hidden.form.params.iter().position(|p| p.name == param) {
            hidden.values[i] *= (120.0 / duration).powi(power);
        }
    }
    hidden
}

/// The set for missions of `duration` \[s\]: one case per catalogue family but
/// `water_current` (seeds 1, 2, … in catalogue order), then three null missions.
pub fn cases(duration: f64) -> Vec<MissionCase> {
    let mut out = Vec::new();
    let families = shoal_model::effects::names();
    let mut seed = 0;
    let logged = uauv2_mission(1, duration).channels;
    let fitted = |f: &&str| {
        *f != "water_current"
            && direct_channels(f).is_none_or(|(needs, _)| needs.iter().any(|c| logged.contains(c)))
    };
    for family in families.into_iter().filter(fitted) {
        let Some(form) = form_of(family) else {
            continue;
        };
        seed += 1;
        let hidden = Hidden::from_stream(&form, stream(form.name, seed) ^ 0x6d, (0.0, 1.0));
        out.push(MissionCase {
            name: format!("m_{}__{}_{seed}", form.family, form.form()),
            seed,
            duration,
            hidden: vec![stretch(hidden, duration)],
            tracked: false,
        });
    }
    for k in 1..=3 {
        out.push(MissionCase {
            name: format!("m_null_{k}"),
            seed: 100 + k,
            duration,
            hidden: Vec::new(),
            tracked: false,
        });
    }
    out
}

/// Missions of `duration` \[s\] with the position tracked, for what shows only where the hull
/// is: a tether with slack paid out (`tether_drag/slack_cable`, values over the form's whole
/// range) and a null mission. Meant to be flown in calm water ([`Disturbance::NONE`]): with a
/// tracked position a wandering current is a `water_current` of its own.
///
/// [`Disturbance::NONE`]: crate::mission::Disturbance::NONE
pub fn tracked_cases(duration: f64) -> Vec<MissionCase> {
    let form = truth_forms::by_name("tether_drag/slack_cable").expect("a truth form");
    let seed = 201;
    let hidden = Hidden::from_stream(&form, stream(form.name, seed) ^ 0x6d, (0.0, 1.0));
    vec![
        MissionCase {
            name: format!("mt_tether_drag__slack_cable_{seed}"),
            seed,
            duration,
            hidden: vec![hidden],
            tracked: true,
        },
        MissionCase {
            name: "mt_null_1".into(),
            seed: 202,
            duration,
            hidden: Vec::new(),
            tracked: true,
        },
    ]
}
