//! Numbers in messages: short, exact enough to find the value in the file.

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
}
