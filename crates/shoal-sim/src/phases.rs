//! Where a step's time goes: the wall time of each phase of the step ([`Phase`]), summed over
//! the steps since timing was switched on ([`crate::sim::Sim::time_phases`]).
//!
//! A timed world runs the same systems in the same order, with a marker system after each
//! phase that reads the clock (the schedule of [`crate::systems::build_schedule`] with
//! `time_phases`); an untimed world has no markers at all. The markers cost a few clock reads
//! per step, nothing per vehicle.

use bevy_ecs::prelude::*;
use serde::Serialize;
use std::time::Instant;

/// The phases of a step, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Missions, behaviours (beacons, gossip, …) and clearing of unread inboxes.
    Ingest,
    /// The fused vehicle pass: control, actuation, dynamics, collisions, sensors.
    Vehicles,
    /// The medium's snapshot: poses, spatial grid, pruning of old transmissions.
    MediumSnapshot,
    /// The medium's transmit phase: queues, access, carrier sense.
    MediumTransmit,
    /// The medium's delivery phase: every reception decided at its receiver.
    MediumDelivery,
    /// The recorder, the connectivity graph and the replay capture.
    Recorder,
}

impl Phase {
    /// Every phase, in step order.
    pub const ALL: [Phase; 6] = [
        Phase::Ingest,
        Phase::Vehicles,
        Phase::MediumSnapshot,
        Phase::MediumTransmit,
        Phase::MediumDelivery,
        Phase::Recorder,
    ];

    /// Its name in tables and JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Phase::Ingest => "ingest",
            Phase::Vehicles => "vehicles",
            Phase::MediumSnapshot => "medium_snapshot",
            Phase::MediumTransmit => "medium_transmit",
            Phase::MediumDelivery => "medium_delivery",
            Phase::Recorder => "recorder",
        }
    }
}

/// The clock of a timed world: when the last phase ended and the time of each phase so far.
#[derive(Resource, Debug, Default)]
pub struct PhaseClock {
    last: Option<Instant>,
    seconds: [f64; 6],
}

impl PhaseClock {
    /// The time spent in each phase so far.
    pub fn times(&self) -> PhaseTimes {
        PhaseTimes {
            seconds: self.seconds,
        }
    }
}

/// Wall time spent in each phase of the step \[s\], in the order of [`Phase::ALL`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PhaseTimes {
    /// Seconds per phase \[s\].
    pub seconds: [f64; 6],
}

impl PhaseTimes {
    /// The time of one phase \[s\].
    pub fn of(&self, p: Phase) -> f64 {
        self.seconds[p as usize]
    }

    /// The time of all phases \[s\].
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }

    /// The medium's three phases together \[s\].
    pub fn medium(&self) -> f64 {
        self.of(Phase::MediumSnapshot)
            + self.of(Phase::MediumTransmit)
            + self.of(Phase::MediumDelivery)
    }

    /// The time since `earlier` (a reading of the same world) \[s\].
    pub fn since(&self, earlier: &PhaseTimes) -> PhaseTimes {
        PhaseTimes {
            seconds: std::array::from_fn(|k| self.seconds[k] - earlier.seconds[k]),
        }
    }

    /// Each phase's share of the total (0 … 1; all zero when nothing was timed).
    pub fn shares(&self) -> [f64; 6] {
        let total = self.total();
        std::array::from_fn(|k| {
            if total > 0.0 {
                self.seconds[k] / total
            } else {
                0.0
            }
        })
    }
}

/// One value per phase of the step, in the order of [`Phase::ALL`]; written (serde) as an
/// object keyed by [`Phase::name`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ByPhase(pub [f64; 6]);

impl Serialize for ByPhase {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (p, v) in Phase::ALL.iter().zip(&self.0) {
            m.serialize_entry(p.name(), v)?;
        }
        m.end()
    }
}

/// Where a run's wall time went \[s\]: each phase of its steps (keyed by [`Phase::name`]; zero
/// when the world was not timed) and the writing of recorded rows while it ran.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct RunPhases {
    /// Wall time of each phase of the steps \[s\].
    #[serde(flatten)]
    pub steps: ByPhase,
    /// Draining the recorded rows and writing them to the trajectory file during the run
    /// (not the end-of-run files) \[s\].
    pub outputs: f64,
}

/// Starts the clock of a step (the first system of a timed schedule).
pub fn phase_start(mut clock: ResMut<PhaseClock>) {
    clock.last = Some(Instant::now());
}

/// Ends phase `P` (an index of [`Phase::ALL`]): adds the time since the previous marker.
pub fn phase_end<const P: usize>(mut clock: ResMut<PhaseClock>) {
    let now = Instant::now();
    if let Some(last) = clock.last {
        clock.seconds[P] += now.duration_since(last).as_secs_f64();
    }
    clock.last = Some(now);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_add_each_phase_to_its_own_total() {
        let mut world = World::new();
        world.insert_resource(PhaseClock::default());
        let mut s = Schedule::default();
        let sleep = |ms: u64| move || std::thread::sleep(std::time::Duration::from_millis(ms));
        s.add_systems(
            (
                phase_start,
                sleep(2),
                phase_end::<{ Phase::Vehicles as usize }>,
                sleep(6),
                phase_end::<{ Phase::MediumDelivery as usize }>,
            )
                .chain(),
        );
        s.run(&mut world);
        s.run(&mut world);
        let t = world.resource::<PhaseClock>().times();
        // Sleeping lasts at least as long as asked; each phase holds only its own sleeps.
        assert!(t.of(Phase::Vehicles) >= 0.004, "{t:?}");
        assert!(t.of(Phase::MediumDelivery) >= 0.012, "{t:?}");
        assert_eq!(t.of(Phase::Ingest), 0.0);
        assert_eq!(t.medium(), t.of(Phase::MediumDelivery));
        let shares = t.shares();
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let none = t.since(&t);
        assert_eq!(none.shares(), [0.0; 6]);
    }
}
