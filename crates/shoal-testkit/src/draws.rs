//! The options of the benchmarks on independent draws (the `recovery` and `resolution`
//! examples): how many seeded draws, over which sensor noise and log lengths, with how many
//! search threads, for which forms, written where.

use std::path::PathBuf;

/// The benchmarks' options, as given on their command lines.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawOptions {
    /// Seeded draws per form and cell (draw d uses seed 1000 + d) (≥ 1).
    pub draws: usize,
    /// Sensor noise as multiples of the μAUV² preset's (≥ 0).
    pub noise: Vec<f64>,
    /// Log lengths \[s\] (≥ 10 s).
    pub length: Vec<f64>,
    /// Search worker threads (≥ 1).
    pub threads: usize,
    /// Only forms whose name contains this text (`null` for the null runs).
    pub forms: Option<String>,
    /// Where to write the table, besides printing it.
    pub out: Option<PathBuf>,
}

impl Default for DrawOptions {
    fn default() -> Self {
        Self {
            draws: 10,
            noise: vec![0.5, 1.0, 2.0],
            length: vec![60.0, 120.0],
            threads: 2,
            forms: None,
            out: None,
        }
    }
}

/// A comma-separated list of finite numbers ≥ 0.
fn list(v: &str) -> Option<Vec<f64>> {
    let out: Option<Vec<f64>> = v.split(',').map(|x| x.trim().parse::<f64>().ok()).collect();
    out.filter(|l| !l.is_empty() && l.iter().all(|x| x.is_finite() && *x >= 0.0))
}

impl DrawOptions {
    /// Reads `--draws N`, `--noise LIST`, `--length LIST`, `--threads T`, `--forms TEXT` and
    /// `--out FILE` from `args` over `defaults`; an unknown option, a missing value or one out
    /// of range is an error naming it.
    pub fn parse(
        defaults: DrawOptions,
        args: impl IntoIterator<Item = String>,
    ) -> Result<DrawOptions, String> {
        let mut o = defaults;
        let mut args = args.into_iter();
        while let Some(a) = args.next() {
            let v = args.next().ok_or_else(|| format!("{a} needs a value"))?;
            let ok = match a.as_str() {
                "--draws" => v.parse().map(|n| o.draws = n).is_ok() && o.draws > 0,
                "--threads" => v.parse().map(|n| o.threads = n).is_ok() && o.threads > 0,
                "--noise" => list(&v).map(|l| o.noise = l).is_some(),
                "--length" => {
                    list(&v).map(|l| o.length = l).is_some() && o.length.iter().all(|&s| s >= 10.0)
                }
                "--forms" => {
                    o.forms = Some(v.clone());
                    true
                }
                "--out" => {
                    o.out = Some(v.clone().into());
                    true
                }
                _ => return Err(format!("unknown option `{a}`")),
            };
            if !ok {
                return Err(format!(
                    "bad value `{v}` for {a} (counts ≥ 1, noise ≥ 0, lengths ≥ 10 s)"
                ));
            }
        }
        Ok(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    /// Given options replace the defaults; a bad value, an unknown option or a missing value
    /// is an error that names it.
    #[test]
    fn options_are_read_and_checked() {
        let o = DrawOptions::parse(
            DrawOptions::default(),
            args("--draws 3 --noise 1,2 --length 120 --forms lag --out t.md"),
        )
        .unwrap();
        assert_eq!((o.draws, o.threads), (3, 2));
        assert_eq!((o.noise, o.length), (vec![1.0, 2.0], vec![120.0]));
        assert_eq!(o.forms.as_deref(), Some("lag"));
        assert_eq!(o.out, Some(PathBuf::from("t.md")));
        let bad = |s: &str| DrawOptions::parse(DrawOptions::default(), args(s)).unwrap_err();
        assert!(bad("--length 5").contains("`5` for --length"));
        assert!(bad("--draws 0").contains("--draws"));
        assert!(bad("--noise -1").contains("--noise"));
        assert!(bad("--speed 2").contains("unknown option `--speed`"));
        assert_eq!(bad("--threads"), "--threads needs a value");
    }
}
