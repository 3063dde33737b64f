//! Numbers as written and in messages: how far a written number may have been rounded
//! ([`half_ulp`]), and numbers short, exact enough to find the value in the file ([`short`]).

/// A number for messages: at most 7 significant digits, no trailing zeros.
pub(crate) fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if !(1e-4..1e7).contains(&a) {
        let s = format!("{x:.6e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.')
        } else {
            m
        };
        return format!("{m}e{e}");
    }
    let decimals = (6 - a.log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Half a unit of the last written digit of a decimal number — the rounding the writer may
/// have applied: `-1.5708` → 5·10⁻⁵, `100` → 0.5, `2.50e-3` → 5·10⁻⁶. Saturates at the
/// ends of the `f32` range (0 for cells that are not numbers).
pub fn half_ulp(cell: &str) -> f32 {
    let s = cell.as_bytes();
    let mut i = usize::from(matches!(s.first(), Some(b'+' | b'-')));
    let mut decimals: i64 = 0;
    let mut dot = false;
    let mut digits = false;
    while let Some(&b) = s.get(i) {
        match b {
            b'0'..=b'9' => {
                digits = true;
                if dot {
                    decimals = decimals.saturating_add(1);
                }
            }
            b'.' if !dot => dot = true,
            _ => break,
        }
        i += 1;
    }
    if !digits {
        return 0.0;
    }
    let mut exp: i64 = 0;
    if matches!(s.get(i), Some(b'e' | b'E')) {
        i += 1;
        let neg = s.get(i) == Some(&b'-');
        if matches!(s.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        while let Some(&b) = s.get(i) {
            if !b.is_ascii_digit() {
                break;
            }
            exp = (exp * 10 + i64::from(b - b'0')).min(100_000);
            i += 1;
        }
        if neg {
            exp = -exp;
        }
    }
    let p = exp.saturating_sub(decimals).clamp(-400, 400) as i32;
    (0.5 * 10f64.powi(p)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers() {
        assert_eq!(short(-std::f64::consts::FRAC_PI_2), "-1.570796");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(5e-5), "5e-5");
        assert_eq!(short(0.02), "0.02");
        assert_eq!(short(1e9), "1e9");
    }

    #[test]
    fn half_ulp_of_written_numbers() {
        let cases = [
            ("-1.5708", 5e-5),
            ("1.5708", 5e-5),
            ("100", 0.5),
            ("0", 0.5),
            ("2.50e-3", 5e-6),
            ("1e9", 5e8),
            ("1E+2", 50.0),
            (".5", 0.05),
            ("5.", 0.5),
            ("+0.001", 5e-4),
        ];
        for (cell, want) in cases {
            let h = f64::from(half_ulp(cell));
            assert!((h - want).abs() <= 1e-6 * want, "{cell}: {h}");
        }
        assert_eq!(half_ulp("1e-999"), 0.0);
        assert_eq!(half_ulp("1e999"), f32::INFINITY);
        assert_eq!(half_ulp("abc"), 0.0);
    }
}
