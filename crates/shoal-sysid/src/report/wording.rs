//! How the report words and formats what the search found: the one-sentence verdict, the
//! candidate that stands as a family's evidence, confidence intervals, channel labels and
//! numbers.

use crate::log::run::ChannelKind;
use crate::search::{Candidate, Outcome, ParamEstimate};
use shoal_output::words::count;
use std::path::Path;

/// One sentence: what was found and what it gained.
pub fn verdict_sentence(out: &Outcome) -> String {
    let fin = &out.chosen;
    let mut tail = String::new();
    for p in &out.verdict.possible {
        tail.push_str(&format!(
            " Possible, not named: {} ({}) — {}.",
            p.effect, p.form, p.reason
        ));
    }
    for u in &out.verdict.unexplained {
        tail.push_str(&format!(
            " Unexplained structure on channel {}: held-out RMSE {} {} against a noise floor of {} (Ljung–Box p = {:.2e}); no catalogue family explains it.",
            u.channel.label(),
            sig(u.rmse),
            u.channel.unit(),
            sig(u.noise_floor),
            u.ljung_box_p
        ));
    }
    if fin.effects.is_empty() {
        return format!(
            "No effect is needed with strong evidence: no catalogue effect improves the held-out \
             error significantly and stably.{tail}"
        );
    }
    let parts: Vec<String> = fin
        .effects
        .iter()
        .map(|e| {
            let ps: Vec<String> = e
                .params
                .iter()
                .filter(|p| p.excited)
                .map(|p| format!("{} = {}", p.name, fmt_pm(p.value, p.sigma)))
                .collect();
            let stab = out
                .verdict
                .stability
                .get(e.effect.name())
                .map(|f| format!(", chosen in {:.0} % of resamples", 100.0 * f))
                .unwrap_or_default();
            format!(
                "{} [form {}{stab}] ({})",
                e.effect.name(),
                e.effect.form(),
                ps.join(", ")
            )
        })
        .collect();
    format!("Found {}: {}.{tail}", parts.join(" and "), headline(out))
}

/// The gain in words: the mean over the table's channels ([`Outcome::validation_gain_pct`]),
/// when the model changes only some of them the mean over those
/// ([`Outcome::changed_channels_gain_pct`]), and every channel the model makes worse with how
/// much ([`Outcome::worsened_channels`]) — a mean must not hide a channel made worse.
pub fn headline(out: &Outcome) -> String {
    let (changed, on_changed) = out.changed_channels_gain_pct();
    gain_words(
        out.baseline.eval.metrics.len(),
        out.validation_gain_pct(),
        &changed,
        on_changed,
        &out.worsened_channels(),
    )
}

/// [`headline`] from its figures: `n` channels with mean gain `mean` [%], the channels the
/// model changes with their mean gain `on_changed` [%], and the channels made worse with
/// their (negative) gains [%].
fn gain_words(
    n: usize,
    mean: f64,
    changed: &[ChannelKind],
    on_changed: f64,
    worse: &[(ChannelKind, f64)],
) -> String {
    let mut s = if n == 1 {
        format!("validation RMSE {mean:.1} % lower than the baseline's (on its 1 channel)")
    } else {
        format!(
            "validation RMSE {mean:.1} % lower than the baseline's (mean of the gains of {})",
            count(n, "channel")
        )
    };
    if !changed.is_empty() && changed.len() != n {
        let names: Vec<String> = changed.iter().map(|k| label(*k)).collect();
        let which = if changed.len() == 1 {
            "the channel".to_string()
        } else {
            format!("the {}", count(changed.len(), "channel"))
        };
        s.push_str(&format!(
            "; {on_changed:.1} % on {which} it changes ({})",
            names.join(", ")
        ));
    }
    if !worse.is_empty() {
        let each: Vec<String> = worse
            .iter()
            .map(|(k, g)| format!("{} (RMSE {:.1} % higher)", label(*k), -g))
            .collect();
        s.push_str(&format!("; made worse: {}", each.join(", ")));
    }
    s
}

/// The search's evidence for the family `name`: its last backward check (the stepwise model
/// with against without it) if it has one, else its last fitted forward candidate.
pub(super) fn evidence<'a>(out: &'a Outcome, name: &str) -> Option<&'a Candidate> {
    let fitted = |backward: bool| {
        out.candidates
            .iter()
            .rev()
            .find(|c| c.effect == name && c.backward == backward && c.fit.is_some())
    };
    fitted(true).or_else(|| fitted(false))
}

/// The candidate whose form comparison stands for the family `name`: the last forward one
/// that fitted forms, preferring one whose best form is `form`.
pub(super) fn form_candidate<'a>(
    out: &'a Outcome,
    name: &str,
    form: &str,
) -> Option<&'a Candidate> {
    let with_forms = || {
        out.candidates
            .iter()
            .rev()
            .filter(|c| c.effect == name && !c.backward && !c.forms.is_empty())
    };
    with_forms()
        .find(|c| c.form == form)
        .or_else(|| with_forms().next())
}

/// The 95 % confidence interval value ± 1.96 σ with the honest σ (allowing for
/// autocorrelated residuals); `None` where σ is unknown.
pub(crate) fn ci95(p: &ParamEstimate) -> Option<(f64, f64)> {
    p.sigma
        .filter(|s| s.is_finite() && *s > 0.0)
        .map(|s| (p.value - 1.96 * s, p.value + 1.96 * s))
}

pub(super) fn label(k: ChannelKind) -> String {
    k.label()
}

pub(super) fn fmt_pm(v: f64, s: Option<f64>) -> String {
    match s {
        Some(s) if s > 0.0 => format!("{} ± {}", sig(v), sig(s)),
        _ => sig(v),
    }
}

/// A number with about four significant digits.
pub(super) fn sig(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (0.01..10000.0).contains(&a) {
        let d = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.3e}")
    }
}

pub(super) fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

pub(super) fn file_name(p: &Path) -> String {
    p.file_name().map_or_else(
        || p.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// BlueROV yaw_3 with the damping error: the mean over y.depth and y.yaw is 24.9 % lower
    /// while y.depth got 37 % worse (gains 86.8 % and −37.0 %: mean 24.9 %).
    #[test]
    fn the_headline_names_every_channel_made_worse() {
        let (d, y) = (ChannelKind::Depth, ChannelKind::Yaw);
        let text = gain_words(2, 24.9, &[d, y], 24.9, &[(d, -37.0)]);
        assert_eq!(
            text,
            "validation RMSE 24.9 % lower than the baseline's (mean of the gains of 2 \
             channels); made worse: y.depth (RMSE 37.0 % higher)"
        );
        let two = gain_words(3, 5.0, &[d, y], 7.5, &[(d, -2.04), (y, -10.0)]);
        assert!(
            two.ends_with(
                "; 7.5 % on the 2 channels it changes (y.depth, y.yaw); made worse: y.depth \
                  (RMSE 2.0 % higher), y.yaw (RMSE 10.0 % higher)"
            ),
            "{two}"
        );
    }

    /// An outcome whose channels have these validation RMSEs before and after.
    fn outcome(rmse: &[(ChannelKind, f64, f64)]) -> Outcome {
        use crate::evaluate::evaluation::{ChannelMetrics, Evaluation};
        use crate::evaluate::stats::LjungBox;
        use crate::search::{Fit, Verdict};
        let fit = |after: bool| {
            let metrics = rmse
                .iter()
                .map(|&(k, b, a)| {
                    let m = ChannelMetrics {
                        n_est: 100,
                        sse_est: 1.0,
                        rho1_est: 0.0,
                        n_val: 100,
                        rmse: if after { a } else { b },
                        fit_pct: 50.0,
                        rmse_est: 0.1,
                        ljung_box: LjungBox {
                            q: 1.0,
                            lags: 10,
                            p_value: 0.5,
                        },
                        resolution: 0.001,
                    };
                    (k, m)
                })
                .collect();
            Fit {
                effects: Vec::new(),
                k: 0,
                eval: Evaluation {
                    runs: Vec::new(),
                    metrics,
                },
                evaluations: 0,
                free: Vec::new(),
                cov: None,
                cov_white: None,
            }
        };
        Outcome {
            baseline: fit(false),
            candidates: Vec::new(),
            chosen: fit(true),
            stepwise: fit(true),
            verdict: Verdict::default(),
            factors: Default::default(),
            rivals: Vec::new(),
        }
    }

    /// The BlueROV yaw_3 case as its table showed it: y.yaw 86.8 % better (RMSE 0.2 → 0.0264
    /// rad), y.depth 37 % worse (0.01 → 0.0137 m); the headline's mean is 24.9 %.
    #[test]
    fn an_outcome_that_worsens_a_channel_says_so_in_its_headline() {
        let (d, y) = (ChannelKind::Depth, ChannelKind::Yaw);
        let out = outcome(&[(d, 0.01, 0.0137), (y, 0.2, 0.0264)]);
        let worse = out.worsened_channels();
        assert_eq!(worse.len(), 1);
        assert_eq!(worse[0].0, d);
        assert!((worse[0].1 + 37.0).abs() < 1e-9, "{worse:?}");
        assert!((out.validation_gain_pct() - 24.9).abs() < 1e-9);
        let h = headline(&out);
        assert!(h.starts_with("validation RMSE 24.9 % lower"), "{h}");
        assert!(
            h.ends_with("; made worse: y.depth (RMSE 37.0 % higher)"),
            "{h}"
        );
        // Nothing made worse: nothing said.
        let fine = outcome(&[(d, 0.01, 0.009), (y, 0.2, 0.1)]);
        assert!(fine.worsened_channels().is_empty());
        assert!(!headline(&fine).contains("worse"));
    }

    #[test]
    fn one_channel_is_not_counted_as_many() {
        let d = ChannelKind::Depth;
        assert_eq!(
            gain_words(1, 12.0, &[d], 12.0, &[]),
            "validation RMSE 12.0 % lower than the baseline's (on its 1 channel)"
        );
        let some = gain_words(4, 3.0, &[d], 12.0, &[]);
        assert!(
            some.contains("of 4 channels); 12.0 % on the channel it changes (y.depth)"),
            "{some}"
        );
    }
}
