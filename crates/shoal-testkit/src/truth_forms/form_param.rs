//! One parameter of a truth form and how its value is drawn.

use shoal_output::words::with_unit;

/// How a parameter's value is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Draw {
    /// A magnitude: uniform within the part of `lo … hi` that the magnitude band selects.
    Magnitude,
    /// A magnitude as above, with a random sign.
    Signed,
    /// A magnitude whose effect grows as the value falls (a factor below one, a time
    /// constant's inverse): the band's weak end is `hi`, its strong end `lo`.
    Deficit,
    /// A shape parameter (phase, direction, …): uniform over all of `lo … hi`, whatever the
    /// band.
    Shape,
}

/// One parameter of a truth form.
#[derive(Clone, Debug, PartialEq)]
pub struct FormParam {
    /// Name with its unit as a suffix where it has one (e.g. `omega_rad_s`).
    pub name: &'static str,
    /// Unit in words (e.g. `rad/s`, `-`).
    pub unit: &'static str,
    /// Smallest value (magnitude for [`Draw::Signed`]; the strong end for [`Draw::Deficit`]),
    /// in [`FormParam::unit`].
    pub lo: f64,
    /// Largest value (magnitude for [`Draw::Signed`]; the weak end for [`Draw::Deficit`]), in
    /// [`FormParam::unit`].
    pub hi: f64,
    /// How it is drawn.
    pub draw: Draw,
    /// What it means.
    pub doc: &'static str,
}

impl FormParam {
    /// A magnitude in `lo … hi` [`unit`](FormParam::unit).
    pub const fn magnitude(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            lo,
            hi,
            draw: Draw::Magnitude,
            doc,
        }
    }

    /// A magnitude in `lo … hi` [`unit`](FormParam::unit) with a random sign.
    pub const fn signed(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Signed,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// A magnitude in `lo … hi` [`unit`](FormParam::unit) whose effect is the stronger the
    /// smaller it is.
    pub const fn deficit(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Deficit,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// A shape parameter uniform in `lo … hi` [`unit`](FormParam::unit).
    pub const fn shape(
        name: &'static str,
        unit: &'static str,
        lo: f64,
        hi: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            draw: Draw::Shape,
            ..Self::magnitude(name, unit, lo, hi, doc)
        }
    }

    /// The range as text, e.g. `±0.01 … 0.03 m` or `2.5 … 5 rad/s`.
    pub fn range_text(&self) -> String {
        let sign = if self.draw == Draw::Signed { "±" } else { "" };
        with_unit(&format!("{sign}{} … {}", self.lo, self.hi), self.unit)
    }
}
