//! How the CSV outputs write a number: rounded to 7 significant digits and printed in the
//! shortest positional form that reads back as that rounded value (whole numbers below 10¹⁵
//! exactly), e.g. `0.1234568`, `-2.5`, `1300`, `0.0000001`.
//!
//! A 10,000-vehicle run writes millions of numbers, so [`write_num`] renders the rounded
//! digits straight into a reused buffer without allocating: the 7 digits come from one
//! scaling by an exact power of ten when that settles the rounding, else from the standard
//! library's exact conversion. The digits of
//! the shortest form of the rounded value are the rounded digits without trailing zeros (an
//! f64 resolves about 16 digits, so no shorter decimal reads back as the same value), except
//! among subnormal numbers, which take the general path.

use std::fmt::Write;

/// Below this magnitude a number takes the general path (subnormals resolve fewer digits).
const TINY: f64 = 1e-300;

/// `x` written by [`write_num`], as a new string.
pub(super) fn format_num(x: f64) -> String {
    let mut s = String::new();
    write_num(x, &mut s);
    s
}

/// Replaces `out` with `x` rounded to 7 significant digits in its shortest positional form
/// (whole numbers below 10¹⁵ exactly; `NaN`, `inf`, `-inf` as Rust writes them).
pub(super) fn write_num(x: f64, out: &mut String) {
    out.clear();
    // Writing into a String cannot fail.
    if x == 0.0 {
        out.push('0');
    } else if !x.is_finite() {
        let _ = write!(out, "{x}");
    } else if x == x.trunc() && x.abs() < 1e15 {
        let _ = write!(out, "{x:.0}");
    } else if x.abs() < TINY {
        general(x, out);
    } else {
        let (digits, exp) = seven_digits(x.abs()).unwrap_or_else(|| exact_digits(x.abs()));
        let mut k = 7;
        while k > 1 && digits[k - 1] == b'0' {
            k -= 1;
        }
        if x < 0.0 {
            out.push('-');
        }
        positional(&digits[..k], exp, out);
    }
}

/// Exact powers of ten that an f64 holds.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The 7 significant digits of `a` > 0 correctly rounded, and the decimal exponent of the
/// first, by one scaling with an exact power of ten (one rounding, relative error ≤ 2⁻⁵³, so
/// at most 1.2·10⁻⁹ on the 7-digit integer); `None` when that cannot settle the rounding (the
/// scaled value within 10⁻⁶ of a tie, or a power beyond 10²²): the exact path decides then.
fn seven_digits(a: f64) -> Option<([u8; 7], i32)> {
    let mut e = decimal_exponent_guess(a);
    // The guess is the exponent or one below it: at most one correction.
    for _ in 0..3 {
        let p = e - 6;
        let scaled = match usize::try_from(p) {
            Ok(p) => a / *POW10.get(p)?,
            Err(_) => a * *POW10.get(usize::try_from(-p).ok()?)?,
        };
        if scaled < 999_999.5 {
            e -= 1;
        } else if scaled >= 9_999_999.5 {
            e += 1;
        } else {
            if (scaled - scaled.floor() - 0.5).abs() < 1e-6 {
                return None;
            }
            let mut r = scaled.round() as u32;
            let mut digits = [b'0'; 7];
            for d in digits.iter_mut().rev() {
                *d = b'0' + (r % 10) as u8;
                r /= 10;
            }
            return Some((digits, e));
        }
    }
    None
}

/// ⌊log₁₀ a⌋ or one less, for a normal `a` > 0, from its binary exponent alone: a lies in
/// [2^b, 2^(b+1)), so log₁₀ a lies in [b·log₁₀ 2, (b+1)·log₁₀ 2), an interval shorter than one;
/// ⌊b·log₁₀ 2⌋ in integers (78913 / 2¹⁸ = log₁₀ 2 to 6·10⁻⁷, exact for |b| < 1650) — no
/// logarithm per number.
fn decimal_exponent_guess(a: f64) -> i32 {
    let b = ((a.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    (b * 78_913) >> 18
}

/// [`seven_digits`] by the standard library's exact conversion (`{:.6e}`).
fn exact_digits(a: f64) -> ([u8; 7], i32) {
    let mut sci = Sci::default();
    let _ = write!(sci, "{a:.6e}");
    let s = &sci.buf[..sci.len];
    let e = s.iter().position(|&c| c == b'e').unwrap_or(s.len());
    let exp: i32 = std::str::from_utf8(&s[e + 1..])
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(0);
    let mut digits = [b'0'; 7];
    for (d, &c) in digits
        .iter_mut()
        .zip(s[..e].iter().filter(|c| c.is_ascii_digit()))
    {
        *d = c;
    }
    (digits, exp)
}

/// Writes 0.d₁d₂…dₖ × 10^(exp + 1) without an exponent.
fn positional(digits: &[u8], exp: i32, out: &mut String) {
    let d = |i: usize| char::from(digits[i]);
    if exp < 0 {
        out.push_str("0.");
        (0..-exp - 1).for_each(|_| out.push('0'));
        (0..digits.len()).for_each(|i| out.push(d(i)));
    } else {
        let int = exp as usize + 1;
        for i in 0..int {
            out.push(if i < digits.len() { d(i) } else { '0' });
        }
        if digits.len() > int {
            out.push('.');
            (int..digits.len()).for_each(|i| out.push(d(i)));
        }
    }
}

/// The definition: round through the decimal text, then the shortest form of the result.
fn general(x: f64, out: &mut String) {
    let rounded = format!("{x:.6e}").parse::<f64>().unwrap_or(x);
    let _ = write!(out, "{rounded}");
}

/// A stack buffer for one number in scientific notation.
#[derive(Default)]
struct Sci {
    buf: [u8; 32],
    len: usize,
}

impl Write for Sci {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let end = self.len + s.len();
        self.buf
            .get_mut(self.len..end)
            .ok_or(std::fmt::Error)?
            .copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The definition, written the slow way.
    fn reference(x: f64) -> String {
        if x == 0.0 {
            "0".into()
        } else if x == x.trunc() && x.abs() < 1e15 {
            format!("{x:.0}")
        } else {
            format!("{x:.6e}")
                .parse::<f64>()
                .map_or_else(|_| x.to_string(), |v| v.to_string())
        }
    }

    #[test]
    fn examples() {
        for (x, s) in [
            (0.0, "0"),
            (-0.0, "0"),
            (1300.0, "1300"),
            (-2.5, "-2.5"),
            (0.123456789, "0.1234568"),
            (1e-7, "0.0000001"),
            (9.99999996, "10"),
            (123456.75, "123456.8"),
            (1e20, "100000000000000000000"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(format_num(x), s, "{x:e}");
            assert_eq!(reference(x), s, "{x:e}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn agrees_with_the_definition_on_any_bits(bits in any::<u64>()) {
            let x = f64::from_bits(bits);
            prop_assert_eq!(format_num(x), reference(x));
        }

        #[test]
        fn agrees_with_the_definition_on_everyday_values(m in -1e7f64..1e7, e in -12i32..12) {
            let x = m * 10f64.powi(e);
            prop_assert_eq!(format_num(x), reference(x));
        }

        #[test]
        fn agrees_with_the_definition_near_ties(k in 1_000_000u32..10_000_000, e in -30i32..30) {
            // Seven digits and a half: the nearest f64 lies just above or below the tie.
            let x = (f64::from(k) + 0.5) * 10f64.powi(e);
            prop_assert_eq!(format_num(x), reference(x));
            prop_assert_eq!(format_num(-x), reference(-x));
        }
    }
}
