//! `sensor_delay` truth forms — measurements trail the truth, but neither by a pure delay δ nor
//! through a first-order filter as the fitting side assumes:
//!
//! * `sensor_delay/sample_hold` — the sensors sample on their own clock (period T_s, phase φ,
//!   slower than the logger), their samples arrive after a transport delay δ, and the logger
//!   repeats the newest one: y(t) = x(s) with s the latest sensor instant φ + j·T_s ≤ t − δ. The
//!   age of a reading saws between δ and δ + T_s.
//! * `sensor_delay/moving_average` — the sensors average their input over the last W seconds
//!   (a boxcar filter in the sensor's firmware): y(t) = mean of x over (t − W, t].
//!
//! Both apply to every sensor (pressure, IMU, tracking) before its noise and quantisation:
//! the sensors see a hull state taken from the history of the true one. Before the run the
//! vehicle is taken to have been at rest where it starts.

use super::exp_kind::ExpKind;
use super::form_param::FormParam;
use super::truth_form::{Part, TruthForm};
use crate::synth::TruthHook;
use shoal_model::control::ActuatorCommands;
use shoal_model::dynamics::RigidState;
use shoal_model::math::{Quat, Vec3, Vec6};
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::{VehicleModel, VehicleState};
use std::collections::VecDeque;

pub(super) fn forms() -> Vec<TruthForm> {
    vec![
        TruthForm {
            name: "sensor_delay/sample_hold",
            family: "sensor_delay",
            law: "y(t) = x(latest φ + j·T_s ≤ t − δ)",
            params: vec![
                FormParam::magnitude("period_s", "s", 0.08, 0.16, "sensor sample period T_s"),
                FormParam::magnitude("delay_s", "s", 0.06, 0.2, "transport delay δ"),
                FormParam::shape("phase", "-", 0.0, 1.0, "sensor clock phase φ / T_s"),
            ],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| {
                Part::Hook(Box::new(Seen::new(Law::SampleHold {
                    period: p[0],
                    delay: p[1],
                    phase: p[2] * p[0],
                })))
            },
        },
        TruthForm {
            name: "sensor_delay/moving_average",
            family: "sensor_delay",
            law: "y(t) = mean of x over (t − W, t]",
            params: vec![FormParam::magnitude(
                "window_s",
                "s",
                0.2,
                0.7,
                "averaging window W (group delay W/2)",
            )],
            excites: &[ExpKind::Heave, ExpKind::Yaw],
            build: |p| Part::Hook(Box::new(Seen::new(Law::MovingAverage { window: p[0] }))),
        },
    ]
}

/// What the sensors do with the hull state (times in s).
enum Law {
    SampleHold { period: f64, delay: f64, phase: f64 },
    MovingAverage { window: f64 },
}

/// See the module documentation.
struct Seen {
    law: Law,
    /// True hull states at every simulation step, oldest first, with their times \[s\].
    history: VecDeque<(f64, RigidState)>,
    /// Simulation step \[s\] (0 until the first step).
    dt: f64,
}

impl Seen {
    fn new(law: Law) -> Self {
        Self {
            law,
            history: VecDeque::new(),
            dt: 0.0,
        }
    }

    /// How far back the law looks \[s\].
    fn memory(&self) -> f64 {
        match self.law {
            Law::SampleHold { period, delay, .. } => delay + period,
            Law::MovingAverage { window } => window,
        }
    }

    fn record(&mut self, state: &VehicleState) {
        let t = state.time;
        if self.history.back().is_none_or(|(tb, _)| t > tb + 1e-12) {
            self.history.push_back((t, state.rigid.clone()));
        }
        // Keep one state older than the memory (and the start, never dropped while needed).
        let keep = t - self.memory() - self.dt - 1e-9;
        while self.history.len() > 2 && self.history[1].0 < keep {
            self.history.pop_front();
        }
    }

    /// The newest recorded state at or before `t` \[s\] (the first one before the start).
    fn at(&self, t: f64) -> &RigidState {
        let i = self.history.partition_point(|(ti, _)| *ti <= t + 1e-9);
        &self.history[i.saturating_sub(1)].1
    }

    /// Mean hull state over (`t` − `window`, `t`] \[s\], padded with the first state.
    fn mean(&self, t: f64, window: f64) -> RigidState {
        let first = &self.history[0];
        let reference = self
            .history
            .back()
            .map_or(first.1.attitude, |s| s.1.attitude);
        let mut w_sum = 0.0;
        let mut pos = Vec3::zeros();
        let mut quat = nalgebra::Vector4::zeros();
        let mut nu = Vec6::zeros();
        let mut add = |w: f64, s: &RigidState| {
            let q = s.attitude.coords;
            let sign = if q.dot(&reference.coords) < 0.0 {
                -1.0
            } else {
                1.0
            };
            w_sum += w;
            pos += w * s.position;
            quat += w * sign * q;
            nu += w * s.nu;
        };
        if self.dt > 0.0 {
            let before = (window - (t - first.0)) / self.dt;
            if before > 0.0 {
                add(before, &first.1);
            }
        }
        for (ti, s) in self.history.iter() {
            if *ti > t - window + 1e-9 && *ti <= t + 1e-9 {
                add(1.0, s);
            }
        }
        RigidState {
            position: pos / w_sum,
            attitude: Quat::new_normalize(nalgebra::Quaternion::from(quat)),
            nu: nu / w_sum,
        }
    }
}

impl TruthHook for Seen {
    fn before_actuate(
        &mut self,
        _model: &VehicleModel,
        state: &mut VehicleState,
        _cmd: &mut ActuatorCommands,
        _env: &mut Environment,
        dt: f64,
    ) {
        self.dt = dt;
        self.record(state);
    }

    fn sensed(&mut self, state: &VehicleState) -> Option<RigidState> {
        self.record(state);
        let t = state.time;
        Some(match self.law {
            Law::SampleHold {
                period,
                delay,
                phase,
            } => {
                let j = ((t - delay - phase) / period + 1e-9).floor();
                self.at(phase + j * period).clone()
            }
            Law::MovingAverage { window } => self.mean(t, window),
        })
    }
}
