//! `shoal effects`: the effect catalogue of `validate` for a vehicle — every effect and form
//! with its parameters, units, bounds (some scale with the vehicle) and null values. Plain
//! text for people by default (no Markdown escapes on a terminal); `--markdown` prints the
//! table that docs/validation.md shows.

use crate::exit::Failure;
use shoal_model::effects::{self, ParamInfo};
use shoal_model::presets;
use shoal_world::load::load_vehicle;
use std::path::Path;
use std::process::ExitCode;

/// One parameter line: name, unit, bounds, null value, meaning.
type Row = [String; 5];

/// An effect form as printed: name, form, what it is, and its parameters, or why it does not
/// apply to the vehicle.
struct Entry {
    name: &'static str,
    form: &'static str,
    summary: &'static str,
    params: Result<Vec<Row>, String>,
}

/// Prints the catalogue for the vehicle in `vehicle` (default: the μAUV² preset), as plain
/// text or, with `markdown`, as the Markdown table of docs/validation.md.
pub fn print(vehicle: Option<&Path>, markdown: bool) -> Result<ExitCode, Failure> {
    let (params, name) = match vehicle {
        Some(p) => {
            let vf = load_vehicle(p).map_err(|e| Failure::Input(e.to_string()))?;
            (vf.spec.to_params(), p.display().to_string())
        }
        None => (presets::uauv2(), String::new()),
    };
    let entries: Vec<Entry> = effects::catalogue()
        .iter()
        .map(|e| Entry {
            name: e.name(),
            form: e.form(),
            summary: e.summary(),
            params: match e.not_applicable(&params) {
                Some(why) => Err(why),
                None => Ok(e.params(&params).iter().map(row).collect()),
            },
        })
        .collect();
    let text = if markdown {
        let vehicle = if name.is_empty() {
            "the μAUV² preset".to_string()
        } else {
            format!("`{name}`")
        };
        markdown_table(&vehicle, &entries)
    } else {
        let vehicle = if name.is_empty() {
            "the μAUV² preset".to_string()
        } else {
            name
        };
        plain(&vehicle, &entries)
    };
    print!("{text}");
    Ok(ExitCode::SUCCESS)
}

fn row(p: &ParamInfo) -> Row {
    let null = if p.shape {
        "(shape)".to_string()
    } else {
        short(p.null)
    };
    [
        p.name.to_string(),
        p.unit.to_string(),
        format!("{} … {}", short(p.lo), short(p.hi)),
        null,
        p.doc.to_string(),
    ]
}

/// The catalogue as plain text: a heading line per effect form, then its parameters in
/// aligned columns.
fn plain(vehicle: &str, entries: &[Entry]) -> String {
    let mut out = format!("Effect catalogue for {vehicle} (bounds in the parameter's unit):\n");
    let head = ["parameter", "unit", "bounds", "null"];
    let mut width = head.map(|h| h.chars().count());
    for r in entries
        .iter()
        .filter_map(|e| e.params.as_ref().ok())
        .flatten()
    {
        for (w, cell) in width.iter_mut().zip(r) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let pad = |s: &str, w: usize| format!("{s}{}", " ".repeat(w.saturating_sub(s.chars().count())));
    let line = |cells: [&str; 5]| {
        let [a, b, c, d, e] = cells;
        format!(
            "  {}  {}  {}  {}  {e}\n",
            pad(a, width[0]),
            pad(b, width[1]),
            pad(c, width[2]),
            pad(d, width[3])
        )
    };
    out.push('\n');
    out.push_str(&line([head[0], head[1], head[2], head[3], "meaning"]));
    for e in entries {
        out.push_str(&format!("\n{} ({}): {}\n", e.name, e.form, e.summary));
        match &e.params {
            Err(why) => out.push_str(&format!("  does not apply: {why}\n")),
            Ok(rows) => {
                for r in rows {
                    out.push_str(&line([&r[0], &r[1], &r[2], &r[3], &r[4]]));
                }
            }
        }
    }
    out
}

/// The catalogue as the Markdown table of docs/validation.md.
fn markdown_table(vehicle: &str, entries: &[Entry]) -> String {
    let cell = |s: &str| s.replace('|', "\\|");
    let mut out = format!("Effect catalogue for {vehicle} (bounds in the parameter's unit):\n\n");
    out.push_str("| effect | form | what | parameter | unit | bounds | null | meaning |\n");
    out.push_str("|---|---|---|---|---|---|---|---|\n");
    for e in entries {
        let (name, form, what) = (
            format!("`{}`", e.name),
            format!("`{}`", e.form),
            cell(e.summary),
        );
        match &e.params {
            Err(why) => out.push_str(&format!(
                "| {name} | {form} | {what} | — | | | | does not apply: {why} |\n"
            )),
            Ok(rows) => {
                for (i, r) in rows.iter().enumerate() {
                    let first = i == 0;
                    out.push_str(&format!(
                        "| {} | {} | {} | `{}` | {} | {} | {} | {} |\n",
                        if first { name.as_str() } else { "" },
                        if first { form.as_str() } else { "" },
                        if first { what.as_str() } else { "" },
                        r[0],
                        r[1],
                        r[2],
                        r[3],
                        cell(&r[4])
                    ));
                }
            }
        }
    }
    out
}

/// A bound or null value, short.
fn short(x: f64) -> String {
    let t = format!("{x}");
    if t.len() <= 8 {
        t
    } else {
        let s = format!("{x:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}
