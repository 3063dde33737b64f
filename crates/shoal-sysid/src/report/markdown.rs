//! `report.md`: the page a person reads. The verdict first, saying plainly which effects are
//! named with strong evidence and which are only possible; then one section per named effect
//! (family, best form and the other forms' BIC, the held-out gain and the selection
//! statistics, parameters with 95 % confidence intervals, the residual signature before and
//! after); then what is possible, ambiguous or unexplained; then the tables, the candidates
//! and the plots of the runs.

use super::input::{ReportInput, Written};
use super::plots::PlotRefs;
use super::wording::{
    ci95, evidence, file_name, fmt_pm, form_candidate, label, sig, verdict_sentence, yes,
};
use crate::evaluate::evaluation::rmse_gain_pct;
use crate::log::run::ChannelKind;
use crate::search::{Candidate, FittedEffect, Outcome, SearchOptions};
use shoal_model::vehicle::VehicleParams;
use shoal_output::words::with_unit;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// The whole `report.md`.
pub(super) fn markdown(
    input: &ReportInput<'_>,
    corr: &BTreeMap<ChannelKind, Vec<(String, f64)>>,
    refs: &PlotRefs,
    written: &Written,
) -> String {
    let out = input.outcome;
    let mut s = String::new();
    let _ = writeln!(s, "# Validation report: `{}`\n", input.vehicle.name);
    let _ = writeln!(s, "Baseline model: {}.\n", input.vehicle_source);
    let _ = writeln!(s, "Replay: {}.\n", input.ds.anchoring.why);
    verdict(&mut s, input, written);
    named(&mut s, input, refs);
    possible(&mut s, out);
    ambiguous(&mut s, out);
    next_experiment(&mut s, input);
    unexplained(&mut s, out);
    channels(&mut s, out);
    runs(&mut s, input);
    diagnostics(&mut s, corr);
    candidates(&mut s, out, input.opts);
    if !refs.runs.is_empty() || !refs.acf.is_empty() {
        let _ = writeln!(s, "\n## Plots\n");
        for p in refs.runs.iter().chain(&refs.acf) {
            let _ = writeln!(s, "### {}\n\n![{}]({})\n", p.title, p.title, p.path);
        }
    }
    method(&mut s, input);
    s
}

fn list(names: &[String]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names
            .iter()
            .map(|n| format!("`{n}`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

fn verdict(s: &mut String, input: &ReportInput<'_>, written: &Written) {
    let out = input.outcome;
    let _ = writeln!(s, "## Verdict\n\n{}\n", verdict_sentence(out));
    let named: Vec<String> = out
        .chosen
        .effects
        .iter()
        .map(|e| format!("{} ({})", e.effect.name(), e.effect.form()))
        .collect();
    let possible: Vec<String> = out
        .verdict
        .possible
        .iter()
        .map(|p| p.effect.clone())
        .collect();
    let _ = writeln!(
        s,
        "- **Named with strong evidence** (selected stepwise, stable under resampling, \
         identifiable): {}.",
        list(&named)
    );
    let _ = writeln!(
        s,
        "- **Only possible, not named** (too little, unstable or ambiguous evidence): {}.",
        list(&possible)
    );
    if !out.verdict.unexplained.is_empty() {
        let ch: Vec<String> = out
            .verdict
            .unexplained
            .iter()
            .map(|u| label(u.channel))
            .collect();
        let _ = writeln!(s, "- **Unexplained structure** on {}.", list(&ch));
    }
    let _ = writeln!(
        s,
        "\nResiduals white (Ljung–Box, 5 %) before: **{}**, after: **{}**.\n",
        yes(out.baseline.eval.residuals_white()),
        yes(out.chosen.eval.residuals_white())
    );
    let _ = writeln!(
        s,
        "The extended model is in [`{}`]({}) — run it with `shoal run {}`.\n",
        file_name(&written.vehicle),
        file_name(&written.vehicle),
        written.vehicle.display()
    );
}

/// One subsection per named effect.
fn named(s: &mut String, input: &ReportInput<'_>, refs: &PlotRefs) {
    let out = input.outcome;
    let opts = input.opts;
    let _ = writeln!(s, "## Named effects (strong evidence)\n");
    if out.chosen.effects.is_empty() {
        let _ = writeln!(s, "None: the baseline needs no extension on these runs.\n");
        return;
    }
    let _ = writeln!(
        s,
        "Each effect's evidence compares the stepwise model with and without it (its backward \
         check): the *held-out gain* is the relative reduction of the validation RMSE (data the \
         fit never saw, mean over the channels whose prediction it moves by at least their \
         sensor's resolution; the verdict's headline averages over every channel); the \
         *effective ΔBIC* is the BIC difference with each channel's sample count replaced by its \
         effective count n·(1−ρ₁)/(1+ρ₁); the *held-out block t* tests that the gain is consistent over {} s blocks; *Wald z* is the distance \
         of its parameters from their null values. The 95 % confidence intervals are value ± \
         1.96 σ with the honest σ, which allows for autocorrelated residuals (each channel's \
         information divided by κ = (1+ρ₁)/(1−ρ₁)); the white-residual σ is shown for \
         comparison (it is smaller whenever the residuals are positively correlated).\n",
        opts.block_s
    );
    for (i, e) in out.chosen.effects.iter().enumerate() {
        effect_section(s, input, refs, i + 1, e);
    }
}

fn effect_section(
    s: &mut String,
    input: &ReportInput<'_>,
    refs: &PlotRefs,
    n: usize,
    e: &FittedEffect,
) {
    let out = input.outcome;
    let opts = input.opts;
    let name = e.effect.name();
    let form = e.effect.form();
    let _ = writeln!(s, "### {n}. `{name}` — form `{form}`\n");
    let _ = writeln!(
        s,
        "{}. *Why:* {}\n",
        e.effect.summary(),
        e.effect.explanation()
    );
    // Evidence.
    let stab = out.verdict.stability.get(name).copied();
    let _ = writeln!(s, "| statistic | value | needed |");
    let _ = writeln!(s, "|---|---|---|");
    match evidence(out, name) {
        Some(c) => {
            let _ = writeln!(
                s,
                "| held-out gain | {:.1} % | ≥ {:.0} % |",
                100.0 * c.gain,
                100.0 * opts.min_gain
            );
            let _ = writeln!(
                s,
                "| ΔBIC | {:.1} | < {} |",
                c.delta_bic, opts.bic_threshold
            );
            let _ = writeln!(
                s,
                "| effective ΔBIC | {:.1} | < {} (backward) |",
                c.delta_bic_eff, opts.backward_eff_bic_threshold
            );
            let _ = writeln!(
                s,
                "| held-out block t | {:.1} | ≥ {} |",
                c.heldout_t, opts.t_threshold
            );
            let _ = writeln!(s, "| Wald z | {:.1} σ | ≥ {} σ |", c.z, opts.z_threshold);
        }
        None => {
            let _ = writeln!(s, "| held-out gain, ΔBIC, t, z | — (no fitted check) | |");
        }
    }
    let _ = writeln!(
        s,
        "| stability selection | {} | ≥ {:.0} % |",
        stab.map_or("not measured".into(), |f| format!(
            "{:.0} % of {} block-bootstrap resamples",
            100.0 * f,
            opts.stability_draws
        )),
        100.0 * opts.stability_threshold
    );
    if let Some(c) = evidence(out, name) {
        let _ = writeln!(
            s,
            "\n*Source:* round {}, {} check{}.",
            c.round,
            if c.backward { "backward" } else { "forward" },
            if c.backward {
                " (the stepwise model with against without it)"
            } else {
                " (the model it was added to against the model with it)"
            }
        );
    }
    forms(s, out, name, form);
    params(s, e, &input.vehicle.to_params());
    match refs.signatures.get(name) {
        Some(sg) => {
            let _ = writeln!(
                s,
                "\n**Residual signature** on {}: {} against {}, of the baseline (before, red) \
                 and of the final model (after, green), every sample of every run; RMS {} → {}.\n\n\
                 ![residual signature of {name}]({})\n",
                label(sg.channel),
                sg.y_label,
                sg.x_label,
                sig(sg.rms.0),
                sig(sg.rms.1),
                sg.path
            );
        }
        None if input.plots => {
            let _ = writeln!(s, "\n(No residual-signature plot could be drawn.)\n");
        }
        None => {}
    }
}

/// The forms of the family as fitted where it was added, with their BIC.
fn forms(s: &mut String, out: &Outcome, name: &str, form: &str) {
    let Some(c) = form_candidate(out, name, form) else {
        return;
    };
    let best = c.forms.iter().map(|f| f.bic).fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        s,
        "\nForms compared in round {} (BIC on the estimation data, lower is better):\n",
        c.round
    );
    let _ = writeln!(
        s,
        "| form | BIC | BIC − best | held-out gain | free parameters |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    let mut fs = c.forms.clone();
    fs.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    for f in fs {
        let mark = if f.form == form { " (named)" } else { "" };
        let _ = writeln!(
            s,
            "| `{}`{mark} | {:.1} | {:+.1} | {:.1} % | {} |",
            f.form,
            f.bic,
            f.bic - best,
            100.0 * f.gain,
            f.k
        );
    }
}

fn params(s: &mut String, e: &FittedEffect, vehicle: &VehicleParams) {
    let _ = writeln!(
        s,
        "\nParameters (95 % confidence interval = value ± 1.96 σ, σ allowing for autocorrelated \
         residuals):\n"
    );
    let _ = writeln!(
        s,
        "| parameter | value | 95 % confidence interval | σ | σ (white residuals) | null |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    let infos = e.effect.params(vehicle);
    for p in &e.params {
        // " m" after a value, nothing after a dimensionless one.
        let unit = with_unit("", &p.unit);
        let doc = infos
            .iter()
            .find(|i| i.name == p.name)
            .map_or(String::new(), |i| format!(" — {}", i.doc));
        if !p.excited {
            let _ = writeln!(
                s,
                "| `{}`{doc} | {}{unit} | held at its null value: the data do not excite it | — | — | {} |",
                p.name,
                sig(p.value),
                sig(p.null)
            );
            continue;
        }
        let ci = ci95(p).map_or("— (σ not determined)".into(), |(a, b)| {
            format!("[{}, {}]{unit}", sig(a), sig(b))
        });
        let shape = if p.shape { " (shape parameter)" } else { "" };
        let _ = writeln!(
            s,
            "| `{}`{shape}{doc} | {}{unit} | {ci} | {} | {} | {} |",
            p.name,
            sig(p.value),
            p.sigma.map_or("—".into(), sig),
            p.sigma_white.map_or("—".into(), sig),
            sig(p.null)
        );
    }
}

/// The evidence of a candidate in one line.
fn evidence_line(c: &Candidate) -> String {
    format!(
        "held-out gain {:.1} %, effective ΔBIC {:.1}, held-out block t {:.1}, Wald z {:.1} σ \
         (round {}, {})",
        100.0 * c.gain,
        c.delta_bic_eff,
        c.heldout_t,
        c.z,
        c.round,
        if c.backward {
            "backward check"
        } else {
            "forward"
        }
    )
}

fn possible(s: &mut String, out: &Outcome) {
    let _ = writeln!(s, "## Possible (not named)\n");
    if out.verdict.possible.is_empty() {
        let _ = writeln!(s, "None.\n");
        return;
    }
    let _ = writeln!(
        s,
        "These effects have some evidence, but not enough to be named (unstable under \
         resampling, or not separable from another family); they are **not** part of the \
         extended model.\n"
    );
    for p in &out.verdict.possible {
        let stab = p
            .stability
            .map(|f| format!(" Selected in {:.0} % of the resamples.", 100.0 * f))
            .unwrap_or_default();
        let ev = evidence(out, &p.effect)
            .map(|c| format!(" Evidence: {}.", evidence_line(c)))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "- **`{}`** (form `{}`): {}.{stab}{ev}",
            p.effect, p.form, p.reason
        );
    }
    let _ = writeln!(s);
}

fn ambiguous(s: &mut String, out: &Outcome) {
    let _ = writeln!(s, "## Ambiguous\n");
    if out.verdict.ambiguous.is_empty() {
        let _ = writeln!(
            s,
            "None: no alternative family explains the held-out data as well as a named one, \
             and none takes a named one's place on enough of the resamples.\n"
        );
        inclusion(s, out);
        return;
    }
    for a in &out.verdict.ambiguous {
        let p = a
            .inclusion
            .map(|[p, q]| format!(" (P {:.0} % and {:.0} %)", 100.0 * p, 100.0 * q))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "- **`{}` or `{}`**{p}: {}.",
            a.effects[0],
            a.effects[1],
            a.why()
        );
    }
    let _ = writeln!(s);
    inclusion(s, out);
}

/// P(family): each family's share of the resamples on which it holds a place of the model.
fn inclusion(s: &mut String, out: &Outcome) {
    if out.verdict.inclusion.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "**P(family)** — on each block-bootstrap resample of the log, every effect of the \
         stepwise model and every family fitted in its place are refitted; a place goes to an \
         alternative that beats the model on both halves of the resample, else to the chosen \
         effect if it passes its backward test there. The share of resamples on which a \
         family holds a place:\n"
    );
    let _ = writeln!(s, "| family | P(family) | in the verdict |");
    let _ = writeln!(s, "|---|---|---|");
    let named = out.chosen.names();
    for (family, p) in out.verdict.inclusion_ranked() {
        let role = if named.iter().any(|n| n == family) {
            "named"
        } else if out
            .verdict
            .ambiguous
            .iter()
            .any(|a| a.effects.iter().any(|e| e == family))
        {
            "A or B"
        } else if out.verdict.possible.iter().any(|x| x.effect == family) {
            "possible"
        } else {
            "not named"
        };
        let _ = writeln!(s, "| `{family}` | {:.0} % | {role} |", 100.0 * p);
    }
    let _ = writeln!(s);
}

fn next_experiment(s: &mut String, input: &ReportInput<'_>) {
    let Some(x) = input.next else {
        return;
    };
    let _ = writeln!(s, "## Next experiment\n");
    let _ = writeln!(
        s,
        "`next_experiment.toml` flies the vehicle through **{}** ({}) for {:.0} s: of the \
         library's manoeuvres, the one whose smallest separation of the rival models below is \
         largest. Fly it, log the same channels and validate both logs together.\n",
        x.manoeuvre, x.what, x.schedule.duration
    );
    let _ = writeln!(
        s,
        "| question | apart on this log (held-out) | apart on the flight (predicted) |\n|---|---|---|"
    );
    let sep = |v: &Option<crate::experiment::predict::Separation>| {
        v.as_ref()
            .map_or("—".to_string(), crate::experiment::describe)
    };
    for q in &x.questions {
        let _ = writeln!(
            s,
            "| `{}` or `{}` | {} | {} |",
            q.a,
            q.b,
            sep(&q.on_log),
            sep(&q.on_flight)
        );
    }
    let tried: Vec<String> = x.tried.iter().map(|(m, r)| format!("{m} {r:.2}")).collect();
    let _ = writeln!(
        s,
        "\nSmallest separation ratio of each manoeuvre tried: {}. (A ratio is the RMS \
         difference of the two models' predictions over the larger of their held-out RMSEs on \
         the log; the evidence, samples × ratio², is the expected difference of their χ² were \
         that residual white.)\n",
        tried.join(", ")
    );
}

fn unexplained(s: &mut String, out: &Outcome) {
    let _ = writeln!(s, "## Unexplained structure\n");
    if out.verdict.unexplained.is_empty() {
        let _ = writeln!(
            s,
            "None: on every channel the final model's held-out residuals are white or close to \
             the noise floor.\n"
        );
        return;
    }
    for u in &out.verdict.unexplained {
        let _ = writeln!(
            s,
            "- {}: held-out RMSE {} {} against a noise floor of {} {} (from sample-to-sample \
             differences), Ljung–Box p = {:.2e}. No catalogue family explains it.",
            label(u.channel),
            sig(u.rmse),
            u.channel.unit(),
            sig(u.noise_floor),
            u.channel.unit(),
            u.ljung_box_p
        );
    }
    let _ = writeln!(s);
}

fn channels(s: &mut String, out: &Outcome) {
    let _ = writeln!(s, "## Validation error per channel\n");
    let _ = writeln!(
        s,
        "| channel | RMSE baseline | RMSE extended | gain | fit % baseline | fit % extended | white before (p) | white after (p) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for (k, mb) in &out.baseline.eval.metrics {
        let Some(mf) = out.chosen.eval.metrics.get(k) else {
            continue;
        };
        let g = rmse_gain_pct(mb.rmse, mf.rmse);
        let _ = writeln!(
            s,
            "| {} [{}] | {} | {} | {:.1} % | {:.1} | {:.1} | {} ({:.3}) | {} ({:.3}) |",
            label(*k),
            k.unit(),
            sig(mb.rmse),
            sig(mf.rmse),
            g,
            mb.fit_pct,
            mf.fit_pct,
            yes(mb.ljung_box.white()),
            mb.ljung_box.p_value,
            yes(mf.ljung_box.white()),
            mf.ljung_box.p_value
        );
    }
}

fn runs(s: &mut String, input: &ReportInput<'_>) {
    let _ = writeln!(s, "\n## Runs\n");
    let _ = writeln!(s, "| run | role | duration [s] | channels | inputs |");
    let _ = writeln!(s, "|---|---|---|---|---|");
    for rd in &input.ds.runs {
        let role = if rd.holdout {
            "hold-out (scored only)".to_string()
        } else if rd.split_time.is_finite() {
            format!(
                "estimation until t = {:.1} s, validation after",
                rd.split_time
            )
        } else {
            "estimation".to_string()
        };
        let chans: Vec<String> = rd
            .channels
            .iter()
            .map(|&i| label(rd.run.channels[i].kind))
            .collect();
        let inputs: Vec<String> = rd
            .run
            .inputs
            .iter()
            .map(|i| format!("u.{}", i.name))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {} | {} |",
            rd.run.name,
            role,
            rd.run.duration(),
            chans.join(", "),
            inputs.join(", ")
        );
    }
    // How each file was read, and what was clamped: a user checks that the reader understood
    // the log as it was meant.
    let _ = writeln!(s);
    for rd in &input.ds.runs {
        if rd.run.ingest.time_column > 0 {
            let _ = writeln!(s, "- `{}` read as: {}", rd.run.name, rd.run.ingest);
        }
        for note in &rd.map.clamped {
            let _ = writeln!(s, "- `{}`: {note}", rd.run.name);
        }
    }
}

fn diagnostics(s: &mut String, corr: &BTreeMap<ChannelKind, Vec<(String, f64)>>) {
    let _ = writeln!(s, "\n## What the baseline gets wrong\n");
    let _ = writeln!(
        s,
        "Correlation of the baseline's estimation residuals with candidate regressors (the strongest three per channel):\n"
    );
    for (k, list) in corr {
        let top: Vec<String> = list
            .iter()
            .take(3)
            .map(|(n, r)| format!("{n} (r = {r:+.2})"))
            .collect();
        let _ = writeln!(s, "- {}: {}", label(*k), top.join("; "));
    }
}

fn candidates(s: &mut String, out: &Outcome, opts: &SearchOptions) {
    let _ = writeln!(s, "\n## Candidates\n");
    let _ = writeln!(
        s,
        "Stage *forward*: each family fitted alone on the baseline (round 1, its forms \
         competing), then added to the chosen ones; *backward*: each chosen effect tested against \
         the model without it; *swap*: one effect exchanged for another. Significant = ΔBIC < {} \
         (backward also effective ΔBIC < {}), held-out gain ≥ {:.0} %, held-out block t ≥ {}, \
         material, and parameters jointly ≥ {} σ from their null values.\n",
        opts.bic_threshold,
        opts.backward_eff_bic_threshold,
        100.0 * opts.min_gain,
        opts.t_threshold,
        opts.z_threshold
    );
    let _ = writeln!(
        s,
        "| round | stage | effect | form | ΔBIC | effective ΔBIC | held-out gain | block t | z | parameters | result |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for c in &out.candidates {
        let stage = if c.backward {
            "backward"
        } else if c.note.starts_with("swap") {
            "swap"
        } else {
            "forward"
        };
        let Some(f) = &c.fit else {
            let _ = writeln!(
                s,
                "| {} | {} | {} | — | — | — | — | — | — | — | {} |",
                c.round, stage, c.effect, c.note
            );
            continue;
        };
        let params = f
            .effects
            .iter()
            .filter(|e| e.effect.name() == c.effect)
            .flat_map(|e| e.params.iter())
            .filter(|p| p.excited)
            .map(|p| format!("{} = {}", p.name, fmt_pm(p.value, p.sigma)))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.1} | {:.1} | {:.1} % | {:.1} | {:.1} | {} | {} |",
            c.round,
            stage,
            c.effect,
            c.form,
            c.delta_bic,
            c.delta_bic_eff,
            100.0 * c.gain,
            c.heldout_t,
            c.z,
            params,
            c.note
        );
    }
}

fn method(s: &mut String, input: &ReportInput<'_>) {
    let _ = writeln!(s, "\n## Method\n");
    let _ = writeln!(
        s,
        "The baseline is replayed open-loop with the measured inputs (zero-order hold) from the measured initial state, through the sensor models, every {} s. Residual = measured − replayed; heading and position offsets are estimated from the estimation samples (from the run itself for hold-out runs); angles are compared as continuous (unwrapped) series. Each effect's parameters are fitted by bounded Levenberg–Marquardt (maximum likelihood, per-channel noise estimated) on the estimation data only; validation samples are never fitted. Parameter σ allow for autocorrelated residuals; see `docs/validation.md`.",
        input.ds.replay.dt
    );
}
