//! The buoyancy tank: a gaiter filled and emptied by a peristaltic pump. Water taken in adds
//! weight, not volume (the gaiter sits inside the displaced hull volume), so filling makes the
//! vehicle heavier and moves its centre of gravity towards the tank.

use crate::math::Vec3;

/// Pump command.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum Pump {
    /// Pump water out of the tank (vehicle becomes lighter).
    Empty,
    /// Pump stopped.
    #[default]
    Off,
    /// Pump water into the tank (vehicle becomes heavier).
    Fill,
}

impl Pump {
    /// −1, 0 or +1.
    pub fn sign(self) -> f64 {
        match self {
            Pump::Empty => -1.0,
            Pump::Off => 0.0,
            Pump::Fill => 1.0,
        }
    }

    /// The pump command of its wire code in both agent transports (the iceoryx2 `Command` and
    /// the ROS 2 `Actuators` message): −1 empty, 0 off, +1 fill; any other value is `None`.
    pub fn from_wire(code: i64) -> Option<Pump> {
        match code {
            -1 => Some(Pump::Empty),
            0 => Some(Pump::Off),
            1 => Some(Pump::Fill),
            _ => None,
        }
    }

    /// The pump command nearest to a signed value (< −0.5 empty, > 0.5 fill, else off).
    pub fn from_sign(v: f64) -> Pump {
        if v > 0.5 {
            Pump::Fill
        } else if v < -0.5 {
            Pump::Empty
        } else {
            Pump::Off
        }
    }
}

/// Buoyancy-tank parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct BallastParams {
    /// Tank capacity \[m³\].
    pub capacity: f64,
    /// Pump volume flow [m³/s] (same both ways).
    pub flow: f64,
    /// Centre of the tank water in the body frame \[m\].
    pub position: Vec3,
    /// Water in the tank at the start of a run \[m³\].
    pub initial_volume: f64,
}

impl BallastParams {
    /// New water volume \[m³\] after running the pump for `dt` \[s\] from `volume` \[m³\].
    #[inline]
    pub fn advance(&self, volume: f64, pump: Pump, dt: f64) -> f64 {
        (volume + pump.sign() * self.flow * dt).clamp(0.0, self.capacity)
    }

    /// The tank's full switch: true when the tank holds its capacity (within 0.1 %).
    #[inline]
    pub fn is_full(&self, volume: f64) -> bool {
        volume >= self.capacity * 0.999
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pump_wire_codes_are_the_signs_and_nothing_else() {
        // The agent wire code is the pump's sign: −1 empty, 0 off, +1 fill.
        for p in [Pump::Empty, Pump::Off, Pump::Fill] {
            assert_eq!(Pump::from_wire(p.sign() as i64), Some(p));
        }
        assert_eq!(Pump::from_wire(-1), Some(Pump::Empty));
        assert_eq!(Pump::from_wire(1), Some(Pump::Fill));
        for bad in [2, -2, 127, -128, i64::MAX] {
            assert_eq!(Pump::from_wire(bad), None, "{bad}");
        }
    }

    #[test]
    fn pump_fills_at_flow_and_stops_at_capacity() {
        let b = BallastParams {
            capacity: 20e-6,
            flow: 0.05e-6,
            position: Vec3::zeros(),
            initial_volume: 0.0,
        };
        let mut v = 0.0;
        for _ in 0..1000 {
            v = b.advance(v, Pump::Fill, 0.01);
        }
        assert!((v - 0.5e-6).abs() < 1e-15);
        assert!(!b.is_full(v));
        for _ in 0..100_000 {
            v = b.advance(v, Pump::Fill, 0.01);
        }
        assert_eq!(v, 20e-6);
        assert!(b.is_full(v));
        assert_eq!(b.advance(0.0, Pump::Empty, 1.0), 0.0);
    }
}
