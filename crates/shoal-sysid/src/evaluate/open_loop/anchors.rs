//! Re-anchored replays (multiple shooting with the measured states as the shooting nodes): a
//! long run is replayed in horizons, and at the start of each horizon the states the log
//! measures — depth, roll, pitch, yaw, the body rates and a tracked horizontal position — are
//! set to what the measurements
//! show there, while every state the log does not measure (velocities, ballast, actuator
//! states, the attitude angles it lacks) runs on through the model. An open-loop replay of a
//! closed-loop mission drifts away from the vehicle and never returns (a model a few per cent
//! off integrates a heading error of radians over minutes); re-anchored, each horizon shows
//! how the model predicts the next seconds from where the vehicle really was — the errors an
//! effect can explain — instead of how far an early error has carried it.
//!
//! The horizontal velocities u and v are the exception: no sensor ties them, and a hull that
//! coasts forward turns under its own Munk moment (∝ u·v), an instability that carries a
//! replay's sway error from horizon to horizon and spins it off within seconds. They come from
//! a filter through the same model instead — its replay re-anchored every [`OBSERVER_S`]
//! ([`super::InitialState::filter`]), where the measured attitude, rates and depth drive
//! them — at each anchor. The heave velocity and the unlogged rates run
//! on: the depth and the attitude tie them within each horizon, and the filter's are noisier
//! (on a null mission its heave velocity made the depth RMSE 4.3 mm instead of 1.1 mm).
//!
//! The measured value at an anchor is a local straight-line fit through the samples within
//! [`ANCHOR_WINDOW`] of it (not one noisy sample), read through the inverse of the model's
//! sensor: at the time the sensor's delay puts it, the depth less the model's depth-sensor
//! offset and the pressure port's depth below the body origin, the rates less the gyro bias.
//! So a sensor effect stays visible to the fit, and the state is the model's own belief of
//! what the sensor saw.

use crate::log::run::{ChannelKind, MeasuredRun};
use shoal_model::dynamics::RigidState;
use shoal_model::math::{euler_rpy, quat_from_rpy, wrap_pi};
use shoal_model::vehicle::VehicleModel;

/// Half-width of the window of samples whose straight-line fit gives a measured state at an
/// anchor \[s\].
pub const ANCHOR_WINDOW: f64 = 0.1;

/// Anchor spacing of the filter that estimates the unmeasured states at each anchor \[s\]:
/// short enough that the measured states keep it on the data, long enough that its unmeasured
/// states are the model's response to them rather than to one noisy fit.
pub const OBSERVER_S: f64 = 0.2;

/// A measured channel near an anchor: value and slope of the local fit at the anchor's time
/// (channel units, per second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Fitted value at the anchor's time.
    pub value: f64,
    /// Fitted slope (unit per s).
    pub slope: f64,
}

impl Local {
    /// The fitted value `dt` \[s\] after the anchor's time.
    pub fn at(&self, dt: f64) -> f64 {
        self.value + self.slope * dt
    }
}

/// The measured states at one re-anchoring point of a replay.
#[derive(Clone, Debug, PartialEq)]
pub struct Anchor {
    /// The physics step before which the state is set.
    pub step: usize,
    /// Depth reading.
    pub depth: Option<Local>,
    /// Roll, pitch and yaw readings \[rad\].
    pub rpy: [Option<Local>; 3],
    /// Gyro readings p, q, r [rad/s].
    pub rates: [Option<Local>; 3],
    /// Tracked position x, y of the body origin \[m\].
    pub position: [Option<Local>; 2],
}

impl Anchor {
    /// The anchor of `run` at physics step `step` of `dt` \[s\] (time `t₀ + step·dt`), or
    /// `None` when no anchored channel has a sample near it.
    pub fn at(run: &MeasuredRun, step: usize, dt: f64) -> Option<Anchor> {
        let t = run.t[0] + step as f64 * dt;
        let fit = |k: ChannelKind| local_fit(run, k, t);
        let a = Anchor {
            step,
            depth: fit(ChannelKind::Depth),
            rpy: [
                fit(ChannelKind::Roll),
                fit(ChannelKind::Pitch),
                fit(ChannelKind::Yaw),
            ],
            rates: [
                fit(ChannelKind::P),
                fit(ChannelKind::Q),
                fit(ChannelKind::R),
            ],
            position: [fit(ChannelKind::X), fit(ChannelKind::Y)],
        };
        let any = a.depth.is_some()
            || a.rpy.iter().any(Option::is_some)
            || a.rates.iter().any(Option::is_some)
            || a.position.iter().any(Option::is_some);
        any.then_some(a)
    }

    /// Anchors of `run` every `horizon` \[s\] after its start (none at the start itself, where
    /// the replay's initial state already comes from the data), on a replay grid of `dt` \[s\].
    pub fn every(run: &MeasuredRun, horizon: f64, dt: f64) -> Vec<Anchor> {
        let span = run.duration();
        if !(horizon > 0.0 && horizon < span) {
            return Vec::new();
        }
        let per = (horizon / dt).round().max(1.0) as usize;
        let last = (span / dt).floor() as usize;
        (1..)
            .map(|k| k * per)
            .take_while(|&s| s < last)
            .filter_map(|s| Anchor::at(run, s, dt))
            .collect()
    }

    /// Sets the measured parts of `rigid` (the replay of `model` at `time` \[s\] since the
    /// run's start) to what this anchor's measurements show, through the inverse of the
    /// model's sensors; the rest of the state is left as the model has it.
    pub fn apply(&self, model: &VehicleModel, time: f64, rigid: &mut RigidState) {
        let p = &model.params;
        // The sensors show the state `delay` earlier: the state now is what they show
        // `delay` later.
        let ahead = model.effects.delay();
        let (r0, p0, y0) = euler_rpy(&rigid.attitude);
        let mut rpy = [r0, p0, y0];
        for (a, m) in rpy.iter_mut().zip(&self.rpy) {
            if let Some(m) = m {
                // The measured angle, taken within half a turn of the model's (both wrap).
                *a += wrap_pi(m.at(ahead) - *a);
            }
        }
        rigid.attitude = quat_from_rpy(rpy[0], rpy[1], rpy[2]);
        for (i, m) in self.rates.iter().enumerate() {
            if let Some(m) = m {
                rigid.nu[3 + i] = m.at(ahead) - p.imu.gyro_bias[i];
            }
        }
        for (i, m) in self.position.iter().enumerate() {
            if let Some(m) = m {
                rigid.position[i] = m.at(ahead);
            }
        }
        if let Some(d) = self.depth {
            let reading = d.at(ahead) - model.effects.depth_offset(time);
            let port = rigid.attitude.transform_vector(&p.pressure.position).z;
            rigid.position.z = reading - port;
        }
    }
}

/// The straight-line least-squares fit of channel `kind` of `run` through its samples within
/// [`ANCHOR_WINDOW`] of time `t` \[s\], at `t`; the nearest sample alone when fewer than
/// three lie there; `None` without the channel or any sample within a second. Angles are
/// unwrapped within the window and the value wrapped into (−π, π].
fn local_fit(run: &MeasuredRun, kind: ChannelKind, t: f64) -> Option<Local> {
    let c = run.channel(kind)?;
    let time = |i: usize| run.t[c.rows[i]];
    let from = c.rows.partition_point(|&r| run.t[r] < t - ANCHOR_WINDOW);
    let to = c.rows.partition_point(|&r| run.t[r] <= t + ANCHOR_WINDOW);
    if to - from < 3 {
        let near = c.rows.partition_point(|&r| run.t[r] < t);
        let best = [
            near.saturating_sub(1),
            near.min(c.rows.len().checked_sub(1)?),
        ]
        .into_iter()
        .min_by(|&a, &b| (time(a) - t).abs().total_cmp(&(time(b) - t).abs()))?;
        return ((time(best) - t).abs() <= 1.0).then_some(Local {
            value: c.values[best],
            slope: 0.0,
        });
    }
    let mut ys: Vec<f64> = c.values[from..to].to_vec();
    if kind.is_angle() {
        crate::evaluate::stats::unwrap(&mut ys);
    }
    let xs: Vec<f64> = (from..to).map(|i| time(i) - t).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let (sxx, sxy) = xs.iter().zip(&ys).fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (x - mx), b + (x - mx) * (y - my))
    });
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let value = my - slope * mx;
    Some(Local {
        value: if kind.is_angle() {
            wrap_pi(value)
        } else {
            value
        },
        slope,
    })
}
