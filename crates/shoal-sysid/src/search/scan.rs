//! Where a fit starts: a line from the null values towards the far bounds and a space-filling
//! Halton design over the box of the new parameters ([`scan_points`]). A threshold law has no
//! gradient where it does not bind and an output-error cost has valleys far from the null
//! values; the best of these points start the Levenberg–Marquardt runs (`fit.rs`).

use shoal_model::effects::ParamInfo;

/// Bases of the Halton sequence, one per scanned dimension (a form has at most a few
/// parameters; further dimensions repeat them).
const HALTON_BASES: [u32; 8] = [2, 3, 5, 7, 11, 13, 17, 19];

/// The `i`-th element (from 1) of the van der Corput sequence in `base`, in (0, 1).
fn van_der_corput(mut i: u32, base: u32) -> f64 {
    let mut f = 1.0;
    let mut r = 0.0;
    while i > 0 {
        f /= base as f64;
        r += f * (i % base) as f64;
        i /= base;
    }
    r
}

/// Starting points of a fit for the excited parameters from index `from` on (the others as in
/// `base`): six points from the null values towards the far bounds (all of them together,
/// shape parameters at their defaults), and a Halton design of 8 + 8·d points over the whole
/// box of those d parameters, shape parameters included. A threshold law (a cap, a dead band)
/// has no gradient where it does not bind and an output-error cost has valleys far from the
/// null values, so a fit from the null and typical values alone can stop in the wrong one;
/// the best of these points starts the Levenberg–Marquardt runs. Deterministic.
pub(super) fn scan_points(
    infos: &[ParamInfo],
    excited: &[bool],
    base: &[f64],
    from: usize,
) -> Vec<Vec<f64>> {
    let dims: Vec<usize> = (from..infos.len()).filter(|&j| excited[j]).collect();
    let mut out = Vec::new();
    for step in 1..=6 {
        let a = step as f64 / 7.0;
        let mut x = base.to_vec();
        for j in from..infos.len() {
            let p = &infos[j];
            x[j] = if !excited[j] || p.shape {
                p.null
            } else {
                let far = if (p.hi - p.null).abs() >= (p.null - p.lo).abs() {
                    p.hi
                } else {
                    p.lo
                };
                p.null + a * (far - p.null)
            };
        }
        out.push(x);
    }
    let n = 8 + 8 * dims.len();
    for i in 1..=n {
        let mut x = base.to_vec();
        for j in from..infos.len() {
            if !excited[j] {
                x[j] = infos[j].null;
            }
        }
        for (d, &j) in dims.iter().enumerate() {
            let u = van_der_corput(i as u32, HALTON_BASES[d % HALTON_BASES.len()]);
            x[j] = infos[j].lo + u * (infos[j].hi - infos[j].lo);
        }
        out.push(x);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn param(lo: f64, hi: f64, null: f64, shape: bool) -> ParamInfo {
        ParamInfo {
            name: "x",
            unit: "-",
            lo,
            hi,
            null,
            typical: 0.5 * (null + hi),
            doc: "",
            shape,
        }
    }

    /// The scan keeps the parameters before `from` and the unexcited ones, stays in the box,
    /// reaches both sides of a signed parameter and the whole range of a shape parameter, and
    /// is the same every time.
    #[test]
    fn scan_points_fill_the_box_of_the_new_parameters_only() {
        let infos = vec![
            param(0.0, 2.0, 1.0, false),   // held (before `from`)
            param(-1.0, 1.0, 0.0, false),  // signed, excited
            param(5.0, 500.0, 60.0, true), // shape, excited
            param(0.0, 1.0, 0.0, false),   // not excited
        ];
        let excited = [true, true, true, false];
        let base = vec![1.7, 0.0, 60.0, 0.0];
        let pts = scan_points(&infos, &excited, &base, 1);
        assert_eq!(pts.len(), 6 + 8 + 8 * 2);
        assert_eq!(pts, scan_points(&infos, &excited, &base, 1));
        for x in &pts {
            assert_eq!(x[0], 1.7);
            assert_eq!(x[3], 0.0);
            for (j, p) in infos.iter().enumerate() {
                assert!(p.lo <= x[j] && x[j] <= p.hi, "{x:?}");
            }
        }
        let signed: Vec<f64> = pts.iter().map(|x| x[1]).collect();
        assert!(signed.iter().any(|&v| v < -0.5) && signed.iter().any(|&v| v > 0.5));
        let shape: Vec<f64> = pts.iter().map(|x| x[2]).collect();
        assert!(shape.iter().any(|&v| v < 60.0) && shape.iter().any(|&v| v > 400.0));
    }
}
