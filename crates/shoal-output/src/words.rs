//! Numbers in sentences, written once for every crate that prints to people: a count with its
//! noun in the right number ([`count`]) and a ratio such as a real-time factor that keeps its
//! significant digits when it is small ([`factor`]).

/// `n` and `noun`, plural unless `n` is 1: `count(1, "vehicle")` is `1 vehicle`,
/// `count(3, "vehicle")` is `3 vehicles`. Nouns ending in s, x, ch or sh take `es`.
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {}", plural(noun))
    }
}

/// The plural of an English noun as shoal's messages use them (`channel` → `channels`,
/// `pass` → `passes`, `entry` → `entries`).
pub fn plural(noun: &str) -> String {
    if noun.ends_with(['s', 'x']) || noun.ends_with("ch") || noun.ends_with("sh") {
        return format!("{noun}es");
    }
    if let Some(stem) = noun.strip_suffix('y')
        && !stem.is_empty()
        && !stem.ends_with(['a', 'e', 'i', 'o', 'u'])
    {
        return format!("{stem}ies");
    }
    format!("{noun}s")
}

/// `value` followed by its unit, or alone where the unit says the quantity is dimensionless
/// (`-` or empty): `with_unit("0.12", "m")` is `0.12 m`, `with_unit("1.319", "-")` is `1.319`.
pub fn with_unit(value: &str, unit: &str) -> String {
    if unit.is_empty() || unit == "-" {
        value.to_string()
    } else {
        format!("{value} {unit}")
    }
}

/// A ratio `x` (e.g. simulated seconds per wall-clock second) with the digits that matter:
/// one decimal from 1 up (`12.3`), two significant digits below (`0.43`, `0.0021`), `0` for
/// zero and the value as it is when not finite.
pub fn factor(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    if x.abs() >= 1.0 {
        return format!("{x:.1}");
    }
    // Two significant digits: as many decimals as the leading zeros need, plus two.
    let decimals = (-x.abs().log10().floor()) as usize + 1;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_say_one_and_many() {
        assert_eq!(count(1, "vehicle"), "1 vehicle");
        assert_eq!(count(0, "vehicle"), "0 vehicles");
        assert_eq!(count(2, "channel"), "2 channels");
        assert_eq!(count(3, "pass"), "3 passes");
        assert_eq!(count(2, "entry"), "2 entries");
        assert_eq!(count(2, "day"), "2 days");
        assert_eq!(count(1, "thread"), "1 thread");
    }

    #[test]
    fn dimensionless_values_print_no_unit() {
        assert_eq!(with_unit("1.319", "-"), "1.319");
        assert_eq!(with_unit("1.319", ""), "1.319");
        assert_eq!(with_unit("0.12", "m"), "0.12 m");
        assert_eq!(with_unit("2", "rad/s"), "2 rad/s");
    }

    #[test]
    fn small_factors_keep_two_significant_digits() {
        assert_eq!(factor(12.34), "12.3");
        assert_eq!(factor(1.0), "1.0");
        assert_eq!(factor(0.43), "0.43");
        assert_eq!(factor(0.0432), "0.043");
        assert_eq!(factor(0.002149), "0.0021");
        assert_eq!(factor(0.0), "0");
    }
}
