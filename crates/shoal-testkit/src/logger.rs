//! How an ordinary data logger writes a run: every column on every row, each number with six
//! significant digits as C's `printf("%g")` prints it. A tilt held at its mechanical limit
//! β = −π/2 therefore reads `-1.5708`, a time stamp `119.98`, a small rate `-0.0035994`.
//!
//! [`shoal_sysid::log::run::MeasuredRun::to_csv`] writes full precision and leaves held inputs empty —
//! right for files the tool writes itself, too kind for a test of what it reads. The depth's
//! 1.8 mm steps, the 50 Hz sampling and the sensor noise come from the simulation
//! ([`crate::synth`]); this module only prints.

use shoal_sysid::log::run::MeasuredRun;

/// Significant digits of C's `%g`.
pub const PRINTF_G_DIGITS: usize = 6;

/// `x` as C's `printf("%.{digits}g", x)` prints it: `digits` significant digits, trailing zeros
/// and a trailing point removed, scientific notation (`1.5e-05`, at least two exponent digits)
/// when the decimal exponent is below −4 or at least `digits`. `digits` ≥ 1.
pub fn format_g(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if x == 0.0 {
        return if x.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".to_string()
        } else if x > 0.0 {
            "inf".to_string()
        } else {
            "-inf".to_string()
        };
    }
    // Rust's `{:e}` rounds the mantissa correctly (including a carry into the exponent).
    let sci = format!("{:.*e}", digits - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("`{:e}` has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` exponent is an integer");
    if exp < -4 || exp >= digits as i32 {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim_zeros(mantissa), exp.abs())
    } else {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        trim_zeros(&format!("{x:.decimals$}")).to_string()
    }
}

/// Removes trailing zeros after a decimal point, and the point if nothing follows it.
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// The run as a logger writes it: header `t,u.…,y.…,r.…`, then one row per time stamp with
/// every input (the value in force), every channel (empty where not sampled) and every
/// reference (the value in force; `r.mode` as the mode's code), each number printed
/// by [`format_g`] with [`PRINTF_G_DIGITS`].
pub fn logger_csv(run: &MeasuredRun) -> String {
    let g = |x: f64| format_g(x, PRINTF_G_DIGITS);
    let mut out = String::from("t");
    for i in &run.inputs {
        out.push_str(",u.");
        out.push_str(&i.name);
    }
    for c in &run.channels {
        out.push(',');
        out.push_str(&c.label());
    }
    for r in &run.references {
        out.push_str(",r.");
        out.push_str(&r.name);
    }
    out.push('\n');
    let mut cursor = vec![0usize; run.channels.len()];
    for (row, &t) in run.t.iter().enumerate() {
        out.push_str(&g(t));
        for i in &run.inputs {
            out.push(',');
            out.push_str(&g(i.values[row]));
        }
        for (k, c) in run.channels.iter().enumerate() {
            out.push(',');
            if c.rows.get(cursor[k]) == Some(&row) {
                out.push_str(&g(c.values[cursor[k]]));
                cursor[k] += 1;
            }
        }
        for r in &run.references {
            out.push(',');
            out.push_str(&g(r.values[row]));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prints_like_printf_g() {
        let cases: [(f64, &str); 16] = [
            (-std::f64::consts::FRAC_PI_2, "-1.5708"),
            (0.0, "0"),
            (0.02, "0.02"),
            (119.98, "119.98"),
            (0.298428123, "0.298428"),
            (-0.00359940001, "-0.0035994"),
            (0.00012345678, "0.000123457"),
            (0.000012345678, "1.23457e-05"),
            (123456.7, "123457"),
            (1234567.0, "1.23457e+06"),
            (9.9999996, "10"),
            (999999.7, "1e+06"),
            (86.50754, "86.5075"),
            (-100.0, "-100"),
            (1.0e-300, "1e-300"),
            (0.7992000000001, "0.7992"),
        ];
        for (x, want) in cases {
            assert_eq!(format_g(x, 6), want, "{x}");
        }
        assert_eq!(format_g(2.0f64.sqrt(), 3), "1.41");
    }

    #[test]
    fn writes_every_cell_and_reads_back_within_six_digits() {
        use shoal_sysid::log::run::{Channel, ChannelKind, InputColumn};
        let run = MeasuredRun {
            path: "x.csv".into(),
            name: "x".into(),
            t: vec![0.0, 0.02, 0.04],
            inputs: vec![InputColumn {
                name: "beta".into(),
                column: 2,
                values: vec![-std::f64::consts::FRAC_PI_2; 3],
                precision: Vec::new(),
                first_set: 0,
            }],
            channels: vec![Channel {
                kind: ChannelKind::Depth,
                column: 3,
                rows: vec![0, 2],
                values: vec![0.7992, 1.0 / 3.0],
            }],
            references: Vec::new(),
            extra: Vec::new(),
            header_line: 0,
            lines: Vec::new(),
            ingest: Default::default(),
        };
        assert_eq!(
            logger_csv(&run),
            "t,u.beta,y.depth\n0,-1.5708,0.7992\n0.02,-1.5708,\n0.04,-1.5708,0.333333\n"
        );
    }
}
