//! Residual signatures: the residual of a model plotted against the quantity that shows an
//! effect — a dead band as a flat zone near zero command, a sagging battery as a trend in
//! time, a damping error as a slope against the speed. Before (the baseline) and after (the
//! final model) side by side show what the effect took out of the residual.

use super::correlations::channel_of;
use super::wording::label;
use crate::evaluate::dataset::{Dataset, RunData};
use crate::evaluate::evaluation::Evaluation;
use crate::log::run::ChannelKind;

pub use shoal_model::effects::Regressor;

/// The regressor that shows the family `name` (its
/// [`FamilyFacts::regressor`](shoal_model::effects::FamilyFacts::regressor)): thruster effects
/// against the command, damping against the rate, the others (battery sag, sensor bias, …)
/// against time. `None`: not a catalogue family.
pub fn regressor_of(name: &str) -> Option<Regressor> {
    shoal_model::effects::facts(name).map(|f| f.regressor)
}

/// Half-width of the differencing window of [`Regressor::Rate`] \[s\].
const RATE_HALF_WINDOW: f64 = 0.1;

/// Half-width of the differencing window of a residual's rate \[s\]: long enough that the
/// quantisation and noise of the reading average out (1.8 mm over 1 s is 2 mm/s), short
/// against the holds of a command.
const RESIDUAL_RATE_HALF_WINDOW: f64 = 0.5;

/// The thruster input the command regressor uses: the thruster column with the largest spread
/// of commands over all runs (the first such in column order).
pub(super) fn command_input(ds: &Dataset) -> Option<String> {
    let mut best: Option<(String, f64)> = None;
    let mut names: Vec<String> = Vec::new();
    for rd in &ds.runs {
        for &(_, col) in &rd.map.thrusters {
            let n = &rd.run.inputs[col].name;
            if !names.contains(n) {
                names.push(n.clone());
            }
        }
    }
    for n in names {
        let v: Vec<f64> = ds
            .runs
            .iter()
            .filter_map(|rd| rd.run.inputs.iter().find(|i| i.name == n))
            .flat_map(|i| i.values.iter().copied())
            .collect();
        let spread =
            crate::evaluate::stats::rms(&v.iter().map(|x| x - mean(&v)).collect::<Vec<_>>());
        if spread > 0.0 && best.as_ref().is_none_or(|b| spread > b.1) {
            best = Some((n, spread));
        }
    }
    best.map(|b| b.0)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// The horizontal axis label of `reg` on channel `kind`.
pub(super) fn axis_label(reg: Regressor, kind: ChannelKind, input: Option<&str>) -> String {
    match reg {
        Regressor::Command => format!("u.{} [%]", input.unwrap_or("?")),
        Regressor::Time => "t since the run's start [s]".into(),
        Regressor::Rate if is_rate(kind) => format!("{} (measured) [{}]", label(kind), kind.unit()),
        Regressor::Rate => format!(
            "d/dt {} (measured, differenced over {:.1} s) [{}/s]",
            label(kind),
            2.0 * RATE_HALF_WINDOW,
            kind.unit()
        ),
    }
}

fn is_rate(kind: ChannelKind) -> bool {
    use ChannelKind::*;
    matches!(kind, P | Q | R | U | V | W)
}

/// Whether the signature of `reg` on channel `kind` shows the residual's rate rather than the
/// residual: a command acts on the rate of a position or heading, whose residual integrates
/// the error over every earlier command — against the command in force only its rate lines
/// up (a dead band's missing speed at small commands, a gain's at large ones).
pub fn residual_rate(reg: Regressor, kind: ChannelKind) -> bool {
    reg == Regressor::Command && kind.has_free_offset()
}

/// The vertical axis label of the signature of `reg` on channel `kind`.
pub(super) fn residual_label(reg: Regressor, kind: ChannelKind) -> String {
    if residual_rate(reg, kind) {
        format!(
            "d/dt residual {} (differenced over {:.1} s) [{}/s]",
            label(kind),
            2.0 * RESIDUAL_RATE_HALF_WINDOW,
            kind.unit()
        )
    } else {
        format!("residual {} [{}]", label(kind), kind.unit())
    }
}

/// (regressor, residual) of every sample of channel `kind` in `ev`, all runs — the residual's
/// rate where [`residual_rate`] says so; for [`Regressor::Command`] the input `input` in force
/// at each sample (runs without it are left out).
pub(super) fn points(
    ds: &Dataset,
    ev: &Evaluation,
    kind: ChannelKind,
    reg: Regressor,
    input: Option<&str>,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (rd, rr) in ds.runs.iter().zip(&ev.runs) {
        for c in rr.channels.iter().filter(|c| c.kind == kind) {
            let Some(x) = regressor(rd, kind, &c.times, &c.measured, reg, input) else {
                continue;
            };
            let y = if residual_rate(reg, kind) {
                differenced(&c.times, &c.resid, RESIDUAL_RATE_HALF_WINDOW)
            } else {
                c.resid.clone()
            };
            out.extend(x.into_iter().zip(y));
        }
    }
    out
}

/// The regressor's value at each sample of one channel of one run.
fn regressor(
    rd: &RunData,
    kind: ChannelKind,
    times: &[f64],
    measured: &[f64],
    reg: Regressor,
    input: Option<&str>,
) -> Option<Vec<f64>> {
    match reg {
        Regressor::Time => {
            let t0 = rd.run.t.first().copied().unwrap_or(0.0);
            Some(times.iter().map(|t| t - t0).collect())
        }
        Regressor::Command => {
            let inp = rd
                .run
                .inputs
                .iter()
                .find(|i| Some(i.name.as_str()) == input)?;
            let ch = channel_of(rd, kind)?;
            Some(ch.rows.iter().map(|&r| inp.values[r]).collect())
        }
        Regressor::Rate if is_rate(kind) => Some(measured.to_vec()),
        Regressor::Rate => Some(differenced(times, measured, RATE_HALF_WINDOW)),
    }
}

/// Central differences of `y` over the samples within ±`half` of each time (one-sided at the
/// ends): robust to quantisation, which a sample-to-sample difference turns into spikes.
pub(super) fn differenced(t: &[f64], y: &[f64], half: f64) -> Vec<f64> {
    let n = t.len();
    let mut out = Vec::with_capacity(n);
    let (mut a, mut b) = (0, 0);
    for i in 0..n {
        while t[a] < t[i] - half && a < i {
            a += 1;
        }
        b = b.max(i);
        while b + 1 < n && t[b + 1] <= t[i] + half {
            b += 1;
        }
        let dt = t[b] - t[a];
        out.push(if dt > 0.0 { (y[b] - y[a]) / dt } else { 0.0 });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_map_to_the_regressor_that_shows_them() {
        assert_eq!(regressor_of("thruster_deadband"), Some(Regressor::Command));
        assert_eq!(regressor_of("thrust_asymmetry"), Some(Regressor::Command));
        assert_eq!(regressor_of("battery_sag"), Some(Regressor::Time));
        assert_eq!(regressor_of("depth_sensor_bias"), Some(Regressor::Time));
        assert_eq!(regressor_of("damping_error"), Some(Regressor::Rate));
        assert_eq!(regressor_of("water_current"), Some(Regressor::Time));
        assert_eq!(regressor_of("no_such_family"), None);
    }

    #[test]
    fn differencing_recovers_a_ramp_through_quantisation() {
        // 0.05 m/s sampled at 50 Hz, quantised to 1.8 mm.
        let t: Vec<f64> = (0..500).map(|i| i as f64 * 0.02).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| (0.05 * t / 0.0018).round() * 0.0018)
            .collect();
        let d = differenced(&t, &y, 0.1);
        for v in &d[10..490] {
            assert!((v - 0.05).abs() < 0.01, "{v}");
        }
    }
}
