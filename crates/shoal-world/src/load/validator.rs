//! The [`Validator`]: collects located problems and checks numbers against the allowed ranges
//! of [`super::ranges`].

use super::ranges::{self, End, FieldRange, fmt_num};
use crate::error::{FieldPath, Problem, ProblemKind, SourceMap};

/// Collects problems with their locations.
pub struct Validator<'a> {
    pub(super) sm: &'a SourceMap<'a>,
    /// Problems found so far.
    pub problems: Vec<Problem>,
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

    /// Moves the problems found since the `from`-th to the fields `to` gives (located
    /// anew), dropping those that then repeat one already there.
    pub(super) fn move_problems(
        &mut self,
        from: usize,
        to: impl Fn(&FieldPath) -> Option<FieldPath>,
    ) {
        let moved: Vec<Problem> = self.problems.drain(from..).collect();
        for mut p in moved {
            if let Some(f) = p.field.as_ref().and_then(&to) {
                p.line_col = self.sm.locate(&f);
                p.field = Some(f);
            }
            if !self.problems[from..].contains(&p) {
                self.problems.push(p);
            }
        }
    }

    /// Checks the number at `path` against its range in [`ranges::RANGES`]; returns whether it
    /// passed.
    pub(super) fn field(&mut self, path: &FieldPath, x: f64) -> bool {
        self.field_with(path, x, None, None)
    }

    /// [`Self::field`] where an end of the range is another field's value (`lo`, `hi`: the
    /// values of the range's [`End::Field`] ends).
    pub(super) fn field_with(
        &mut self,
        path: &FieldPath,
        x: f64,
        lo: Option<f64>,
        hi: Option<f64>,
    ) -> bool {
        self.range_of(path)
            .is_some_and(|r| self.check(path, x, r, lo, hi))
    }

    /// Checks the number at `path` against the range of the field `range_of`.
    pub(super) fn field_by(&mut self, path: &FieldPath, range_of: &FieldPath, x: f64) -> bool {
        self.range_of(range_of)
            .is_some_and(|r| self.check(path, x, r, None, None))
    }

    /// Checks every element of the vector field at `path` against the field's range.
    pub(super) fn fields(&mut self, path: &FieldPath, xs: &[f64]) -> bool {
        let Some(r) = self.range_of(path) else {
            return false;
        };
        let mut ok = true;
        for (i, x) in xs.iter().enumerate() {
            ok &= self.check(&path.index(i), *x, r, None, None);
        }
        ok
    }

    /// The table's range of the field at `path`; a field missing from the table is a bug,
    /// reported as a problem at that field rather than a panic.
    fn range_of(&mut self, path: &FieldPath) -> Option<&'static FieldRange> {
        let r = ranges::lookup(&path.to_string());
        if r.is_none() {
            self.push(
                ProblemKind::Invalid,
                path,
                "no allowed range is defined for this field (a bug in shoal: please report it)"
                    .into(),
            );
        }
        r
    }

    /// Checks `lo ⋚ x ⋚ hi` for a number whose range is not in the table (an effect's
    /// parameter, whose range its effect declares).
    pub(super) fn num(
        &mut self,
        path: &FieldPath,
        x: f64,
        lo: End,
        hi: End,
        unit: &'static str,
    ) -> bool {
        let r = FieldRange {
            field: "",
            lo,
            hi,
            zero_or: 0.0,
            unit,
            why: "",
        };
        self.check(path, x, &r, None, None)
    }

    fn check(
        &mut self,
        path: &FieldPath,
        x: f64,
        r: &FieldRange,
        lo: Option<f64>,
        hi: Option<f64>,
    ) -> bool {
        let name = path.last_key().unwrap_or("value");
        let subnormal = x != 0.0 && x.abs() < f64::MIN_POSITIVE;
        let too_small = r.zero_or > 0.0 && x > 0.0 && x < r.zero_or;
        if r.admits(x, lo, hi) && !subnormal && !too_small {
            return true;
        }
        let what = if !x.is_finite() {
            format!("{x} is not a finite number")
        } else if subnormal {
            format!("{x:e} is a subnormal number, too small to mean anything")
        } else if too_small {
            format!(
                "{} is too small to be physical (0 switches it off)",
                fmt_num(x)
            )
        } else {
            format!("{} is out of range", fmt_num(x))
        };
        let mut message = format!("{what}; allowed: {}", r.allowed(name, lo, hi));
        for (sep, part) in [(" ", r.unit), (" — ", r.why)] {
            if !part.is_empty() {
                message.push_str(sep);
                message.push_str(part);
            }
        }
        self.push(ProblemKind::Range, path, message);
        false
    }
}

pub(super) fn axis(v: &mut Validator<'_>, path: &FieldPath, a: &[f64; 3]) {
    if v.fields(path, a) && (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt() < 1e-9 {
        v.push(
            ProblemKind::Range,
            path,
            "must be a non-zero vector (it is normalised on load)".into(),
        );
    }
}
