//! The [`Validator`]: collects located problems and checks numbers against allowed ranges.

use crate::error::{FieldPath, Problem, ProblemKind, SourceMap};

/// Largest coordinate a position may have [m].
pub(super) const BIG: f64 = 1e6;

/// Collects problems with their locations.
pub struct Validator<'a> {
    pub(super) sm: &'a SourceMap<'a>,
    /// Problems found so far.
    pub problems: Vec<Problem>,
}

/// An end of an allowed range.
#[derive(Clone, Copy)]
pub(super) enum End {
    Open(f64),
    Closed(f64),
    None,
}

impl Validator<'_> {
    pub(super) fn push(&mut self, kind: ProblemKind, path: &FieldPath, message: String) {
        self.problems.push(Problem {
            kind,
            field: Some(path.clone()),
            line_col: self.sm.locate(path),
            message,
        });
    }

    /// Checks `lo ⋚ x ⋚ hi`; returns whether it passed.
    pub(super) fn num(&mut self, path: &FieldPath, x: f64, lo: End, hi: End, unit: &str) -> bool {
        let name = path.last_key().unwrap_or("value");
        let ok_lo = match lo {
            End::Open(a) => x > a,
            End::Closed(a) => x >= a,
            End::None => true,
        };
        let ok_hi = match hi {
            End::Open(b) => x < b,
            End::Closed(b) => x <= b,
            End::None => true,
        };
        if x.is_finite() && ok_lo && ok_hi {
            return true;
        }
        let mut allowed = String::new();
        match lo {
            End::Open(a) => allowed.push_str(&format!("{a} < ")),
            End::Closed(a) => allowed.push_str(&format!("{a} ≤ ")),
            End::None => {}
        }
        allowed.push_str(name);
        match hi {
            End::Open(b) => allowed.push_str(&format!(" < {b}")),
            End::Closed(b) => allowed.push_str(&format!(" ≤ {b}")),
            End::None => {}
        }
        let what = if x.is_finite() {
            format!("{x} is out of range")
        } else {
            format!("{x} is not a finite number")
        };
        self.push(
            ProblemKind::Range,
            path,
            format!("{what}; allowed: {allowed} {unit}")
                .trim_end()
                .to_string(),
        );
        false
    }

    /// `0 < x ≤ max` for the field `key` of `p`.
    pub(super) fn pos(&mut self, p: &FieldPath, key: &str, x: f64, max: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Open(0.0), End::Closed(max), unit)
    }

    /// `0 ≤ x ≤ max` for the field `key` of `p`.
    pub(super) fn nonneg(&mut self, p: &FieldPath, key: &str, x: f64, max: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Closed(0.0), End::Closed(max), unit)
    }

    /// `lo ≤ x ≤ hi` for the field `key` of `p`.
    pub(super) fn within(&mut self, p: &FieldPath, key: &str, x: f64, lo: f64, hi: f64, unit: &str) -> bool {
        self.num(&p.key(key), x, End::Closed(lo), End::Closed(hi), unit)
    }

    /// `lo ≤ xᵢ ≤ hi` for every element of the field `key` of `p`.
    pub(super) fn within_all(
        &mut self,
        p: &FieldPath,
        key: &str,
        xs: &[f64],
        lo: f64,
        hi: f64,
        unit: &str,
    ) -> bool {
        self.vec(&p.key(key), xs, End::Closed(lo), End::Closed(hi), unit)
    }

    pub(super) fn vec(&mut self, path: &FieldPath, xs: &[f64], lo: End, hi: End, unit: &str) -> bool {
        let mut ok = true;
        for (i, x) in xs.iter().enumerate() {
            ok &= self.num(&path.index(i), *x, lo, hi, unit);
        }
        ok
    }
}

pub(super) fn axis(v: &mut Validator<'_>, path: &FieldPath, a: &[f64; 3]) {
    if v.vec(path, a, End::Closed(-1e3), End::Closed(1e3), "")
        && (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() < 1e-9
    {
        v.push(
            ProblemKind::Range,
            path,
            "must be a non-zero vector (it is normalised on load)".into(),
        );
    }
}
