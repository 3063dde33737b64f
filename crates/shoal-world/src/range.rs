//! The allowed range of one number of a world file ([`FieldRange`], with its ends [`End`]):
//! the type of every row of the ranges table (`load::ranges`) and of the rows each medium-access
//! protocol declares for its own fields (`access`), and how a range reads in messages and docs.

/// One end of an allowed range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum End {
    /// Excluded value.
    Open(f64),
    /// Included value.
    Closed(f64),
    /// Included value given by another field or setting (named here, for messages and docs).
    Field(&'static str),
    /// Excluded value given by another field (named here).
    OpenField(&'static str),
    /// No limit.
    None,
}

/// The allowed range of one field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldRange {
    /// Field path pattern (see the module doc).
    pub field: &'static str,
    /// Lower end.
    pub lo: End,
    /// Upper end.
    pub hi: End,
    /// Values in `(0, zero_or)` are refused: the field is either 0 (off) or at least this
    /// (`0.0`: no such rule) [the field's unit].
    pub zero_or: f64,
    /// Unit as written in messages and docs.
    pub unit: &'static str,
    /// Why these limits.
    pub why: &'static str,
}

/// A field within the range `lo` … `hi`.
pub const fn r(
    field: &'static str,
    lo: End,
    hi: End,
    unit: &'static str,
    why: &'static str,
) -> FieldRange {
    FieldRange {
        field,
        lo,
        hi,
        zero_or: 0.0,
        unit,
        why,
    }
}

/// A field that is 0 (off) or within `[min, hi]`.
pub const fn z(
    field: &'static str,
    min: f64,
    hi: f64,
    unit: &'static str,
    why: &'static str,
) -> FieldRange {
    FieldRange {
        field,
        lo: End::Closed(0.0),
        hi: End::Closed(hi),
        zero_or: min,
        unit,
        why,
    }
}

/// A number for messages and docs: plain when readable, else `1e-9`.
pub fn fmt_num(x: f64) -> String {
    if x != 0.0 && (x.abs() >= 1e4 || x.abs() < 1e-3) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl FieldRange {
    /// Whether the finite number `x` lies in the range, `lo`/`hi` being the values of
    /// [`End::Field`] ends where known (an end of unknown value does not limit).
    pub fn admits(&self, x: f64, lo: Option<f64>, hi: Option<f64>) -> bool {
        let value = |e: End, v: Option<f64>| match e {
            End::Open(a) | End::Closed(a) => Some(a),
            End::Field(_) | End::OpenField(_) => v,
            End::None => None,
        };
        let ok_lo = match (self.lo, value(self.lo, lo)) {
            (End::Open(_) | End::OpenField(_), Some(a)) => x > a,
            (_, Some(a)) => x >= a,
            (_, None) => true,
        };
        let ok_hi = match (self.hi, value(self.hi, hi)) {
            (End::Open(_) | End::OpenField(_), Some(b)) => x < b,
            (_, Some(b)) => x <= b,
            (_, None) => true,
        };
        x.is_finite() && ok_lo && ok_hi
    }

    /// The allowed range as text, e.g. `1e-3 ≤ mass ≤ 1e5`; `lo`/`hi` are the values of
    /// [`End::Field`] ends where known.
    pub fn allowed(&self, name: &str, lo: Option<f64>, hi: Option<f64>) -> String {
        let end = |e: End, v: Option<f64>| -> Option<(String, &str)> {
            let field =
                |f: &str| v.map_or_else(|| f.to_string(), |v| format!("{} ({f})", fmt_num(v)));
            Some(match e {
                End::Open(x) => (fmt_num(x), "<"),
                End::Closed(x) => (fmt_num(x), "≤"),
                End::Field(f) => (field(f), "≤"),
                End::OpenField(f) => (field(f), "<"),
                End::None => return None,
            })
        };
        // A field that may be 0 (off) is otherwise at least `zero_or`.
        let low = if self.zero_or > 0.0 {
            Some((fmt_num(self.zero_or), "≤"))
        } else {
            end(self.lo, lo)
        };
        let mut s = match low {
            Some((x, op)) => format!("{x} {op} {name}"),
            None => name.to_string(),
        };
        if let Some((x, op)) = end(self.hi, hi) {
            s.push_str(&format!(" {op} {x}"));
        }
        if self.zero_or > 0.0 {
            s = format!("{name} = 0 or {s}");
        }
        s
    }
}
