//! `thruster_deadband`: no thrust for |command| < d₀.
//!
//! An ESC needs a minimum duty cycle before the motor overcomes its static friction and
//! cogging; Blue Robotics' T200 bench data show a dead band of ±30–40 µs around 1500 µs.
//! Small commands — the ones a controller near its setpoint gives all the time — then do
//! nothing.
//!
//! Modelled by remapping the command before the thrust curve so that the curve's range is
//! kept: `n' = sign(n) · n_max · max(|n| − d₀, 0) / (n_max − d₀)`. Full command still gives
//! full thrust, the map is continuous in n and in d₀, and d₀ = 0 is the baseline.

use super::{Effect, ParamInfo};
use crate::thruster::ThrusterParams;
use crate::vehicle::VehicleParams;

/// See the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct ThrusterDeadband;

impl Effect for ThrusterDeadband {
    fn name(&self) -> &'static str {
        "thruster_deadband"
    }
    fn summary(&self) -> &'static str {
        "no thrust for |command| < d₀"
    }
    fn explanation(&self) -> &'static str {
        "ESC and motor static friction: commands below d₀ produce no thrust; above it the \
         thrust curve is stretched over the remaining command range."
    }
    fn params(&self, _vehicle: &VehicleParams) -> Vec<ParamInfo> {
        vec![ParamInfo {
            name: "d0_pct",
            unit: "%",
            lo: 0.0,
            hi: 40.0,
            null: 0.0,
            typical: 8.0,
            doc: "dead band half-width in command percent",
        }]
    }
    fn command(&self, p: &[f64], thruster: &ThrusterParams, n: f64) -> f64 {
        let d0 = p[0];
        let max = thruster.max_command;
        if d0 <= 0.0 || max <= d0 {
            return n;
        }
        n.signum() * max * (n.abs() - d0).max(0.0) / (max - d0)
    }
}
