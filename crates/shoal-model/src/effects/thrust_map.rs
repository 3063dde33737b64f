//! `thrust_map`: a non-parametric thrust map — every thruster's thrust scaled by a factor that
//! is piecewise linear in the command, with its own knots for each direction.
//!
//! Not a family of the catalogue and never named in a verdict: it is the model search's
//! *nuisance* model for static thrust-map shapes. When the true law of one thrust-map family
//! (a gain that changes slope, a reverse thrust that fades) has no form in the catalogue, the
//! best form leaves a residual shaped like a thrust map, and a second thrust-map family joins
//! only to soak it up. This map can take any such shape, so a thrust-map family that does not
//! fit better than the map in its place is a stand-in, not a finding (see the search's
//! `nuisance.rs`).
//!
//! Modelled as `f' = g(n)·f` with `g` linear between its values at four knots of |n|/n_max for
//! each direction of the command n, and held at the first knot's value below it (small
//! commands give little thrust; a dead band is a family's own shape) and at the last knot's
//! value above it (a map is not extrapolated beyond the commands it was fitted on). The knots
//! are fixed when the map is made (the search places them at quantiles of the commands it
//! fits the map on); all factors at 1 is the baseline.

use super::effect::{Effect, ParamInfo, ThrustContext};
use crate::vehicle_params::VehicleParams;

/// Default knots of the map as fractions of the thruster's largest command (ascending).
pub const KNOTS: [f64; 4] = [0.1, 0.25, 0.5, 1.0];

/// Parameter names: forward knots, then reverse knots (same order as [`KNOTS`]).
const NAMES: [&str; 8] = [
    "g_fwd_1", "g_fwd_2", "g_fwd_3", "g_fwd_4", "g_rev_1", "g_rev_2", "g_rev_3", "g_rev_4",
];

/// See the module documentation.
#[derive(Clone, Copy, Debug)]
pub struct ThrustMap {
    /// Knots of forward commands as fractions of the thruster's largest command (0…1,
    /// strictly ascending).
    pub forward: [f64; 4],
    /// Knots of reverse commands as fractions of the thruster's largest command (0…1,
    /// strictly ascending).
    pub reverse: [f64; 4],
}

impl Default for ThrustMap {
    fn default() -> Self {
        Self {
            forward: KNOTS,
            reverse: KNOTS,
        }
    }
}

impl ThrustMap {
    /// The factor g at the command fraction `x` = |n|/n_max (0…1) for the four values `g` at
    /// the (strictly ascending) `knots` of one direction: linear between knots, held below the
    /// first and above the last.
    pub fn factor(g: &[f64], knots: &[f64; 4], x: f64) -> f64 {
        if x <= knots[0] {
            return g[0];
        }
        for i in 1..knots.len() {
            if x <= knots[i] {
                let a = (x - knots[i - 1]) / (knots[i] - knots[i - 1]);
                return g[i - 1] + a * (g[i] - g[i - 1]);
            }
        }
        g[knots.len() - 1]
    }
}

impl Effect for ThrustMap {
    fn name(&self) -> &'static str {
        "thrust_map"
    }
    fn form(&self) -> &'static str {
        "piecewise_linear"
    }
    fn summary(&self) -> &'static str {
        "thrust scaled by a piecewise-linear factor of the command, per direction"
    }
    fn explanation(&self) -> &'static str {
        "A thrust map of no particular law: each thruster's thrust is scaled by a factor that \
         changes linearly between its values at four command knots, with its own knots and \
         values for reverse commands. Used by the model search as a nuisance model, never \
         named."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        NAMES
            .iter()
            .map(|&name| ParamInfo {
                name,
                unit: "-",
                lo: 0.0,
                hi: 3.0,
                null: 1.0,
                typical: 0.9,
                doc: "thrust factor at this knot of command and direction",
                shape: false,
            })
            .collect()
    }
    fn thrust(&self, p: &[f64], ctx: &ThrustContext<'_>, f: f64) -> f64 {
        let n_max = ctx.thruster.max_command.max(f64::MIN_POSITIVE);
        let x = (ctx.command.abs() / n_max).min(1.0);
        let (g, knots) = if ctx.command < 0.0 {
            (&p[4..8], &self.reverse)
        } else {
            (&p[0..4], &self.forward)
        };
        Self::factor(g, knots, x) * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_is_linear_between_knots_and_held_outside() {
        let g = [0.5, 1.0, 2.0, 1.5];
        assert_eq!(ThrustMap::factor(&g, &KNOTS, 0.0), 0.5);
        assert_eq!(ThrustMap::factor(&g, &KNOTS, 0.1), 0.5);
        // Halfway between 25 % and 50 %: (1 + 2)/2.
        assert!((ThrustMap::factor(&g, &KNOTS, 0.375) - 1.5).abs() < 1e-12);
        // A fifth of the way from 10 % to 25 %.
        assert!((ThrustMap::factor(&g, &KNOTS, 0.13) - 0.6).abs() < 1e-12);
        assert_eq!(ThrustMap::factor(&g, &KNOTS, 1.0), 1.5);
        // Held beyond the last knot.
        let short = [0.1, 0.2, 0.3, 0.4];
        assert_eq!(ThrustMap::factor(&g, &short, 0.9), 1.5);
    }

    #[test]
    fn each_direction_has_its_own_knots_in_fractions_of_the_largest_command() {
        let vehicle = crate::presets::uauv2();
        let thruster = &vehicle.thrusters[0];
        let n_max = thruster.max_command;
        let p = [1.0, 1.0, 0.8, 0.6, 0.5, 0.5, 0.5, 0.5];
        let map = ThrustMap::default();
        let at = |command: f64, f: f64| {
            let ctx = ThrustContext {
                t: 0.0,
                thruster,
                command,
                inflow: 0.0,
            };
            map.thrust(&p, &ctx, f)
        };
        // Forward, 75 % of the largest command: halfway from 0.8 to 0.6.
        assert!((at(0.75 * n_max, 2.0) - 1.4).abs() < 1e-12);
        // Reverse at the same magnitude: the reverse knots.
        assert!((at(-0.75 * n_max, -2.0) + 1.0).abs() < 1e-12);
        // All knots at their nulls: the baseline.
        let null: Vec<f64> = map.params(&vehicle).iter().map(|q| q.null).collect();
        let ctx = ThrustContext {
            t: 0.0,
            thruster,
            command: 0.3 * n_max,
            inflow: 0.0,
        };
        assert_eq!(map.thrust(&null, &ctx, 1.7), 1.7);
    }
}
