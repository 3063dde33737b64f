//! The memory estimate: a vehicle count this machine cannot hold is refused while the file is
//! checked — before a single vehicle is placed or allocated — with the estimate and what the
//! machine has, instead of the run failing somewhere in the middle.

use super::validator::Validator;
use crate::error::{FieldPath, ProblemKind};
use crate::spec::WorldFile;

/// Memory a running vehicle takes, all of it: its description, its simulation state, the
/// per-vehicle output accumulators and its share of the end-of-run tables \[bytes\].
/// Measured as peak RSS / vehicles of `shoal run` on quiet μAUV² swarms (3.2 KB at 10⁵,
/// 2.9 KB at 10⁶ vehicles); the estimate errs on the large side.
pub const DEFAULT_BYTES_PER_VEHICLE: u64 = 4 * 1024;

/// Extra memory of a vehicle in a group that transmits (a behaviour or an agent): the
/// receivers in its range keep reception statistics per sender \[bytes\]. Measured with
/// 1 Hz beacons on a 1.5 m grid (≈ 40 senders heard per vehicle): 10.4 KB per vehicle in
/// all at 10⁵ vehicles.
pub const DEFAULT_EXTRA_BYTES_PER_SENDER: u64 = 8 * 1024;

/// What a world may use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    /// Memory available to the run \[bytes\].
    pub available_bytes: u64,
    /// Estimated memory per vehicle \[bytes\].
    pub bytes_per_vehicle: u64,
    /// Estimated extra memory per vehicle of a group that transmits \[bytes\].
    pub extra_bytes_per_sender: u64,
}

impl MemoryBudget {
    /// This machine's available memory (`MemAvailable` of `/proc/meminfo`, or the cgroup's
    /// limit when lower) with [`DEFAULT_BYTES_PER_VEHICLE`]; `None` where neither is known.
    pub fn this_machine() -> Option<Self> {
        let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
        let avail = meminfo.as_deref().and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
                .map(|kb| kb * 1024)
        });
        let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max")
            .ok()
            .and_then(|s| s.trim().parse::<u64>().ok());
        let available_bytes = match (avail, cgroup) {
            (Some(a), Some(c)) => a.min(c),
            (a, c) => a.or(c)?,
        };
        Some(Self {
            available_bytes,
            bytes_per_vehicle: DEFAULT_BYTES_PER_VEHICLE,
            extra_bytes_per_sender: DEFAULT_EXTRA_BYTES_PER_SENDER,
        })
    }

    /// Estimated memory of `n` vehicles of which `senders` transmit \[bytes\].
    pub fn estimate(&self, n: u64, senders: u64) -> u64 {
        n.saturating_mul(self.bytes_per_vehicle)
            .saturating_add(senders.saturating_mul(self.extra_bytes_per_sender))
    }
}

fn gb(b: u64) -> String {
    format!("{:.1} GB", b as f64 / 1e9)
}

/// Refuses the world when its vehicles would not fit; the problem is placed at the largest
/// group's `count`.
pub(super) fn check(wf: &WorldFile, budget: Option<&MemoryBudget>, v: &mut Validator<'_>) {
    let Some(b) = budget else {
        return;
    };
    let total: u64 = wf.vehicles.iter().map(|g| g.count as u64).sum();
    let senders: u64 = wf
        .vehicles
        .iter()
        .filter(|g| g.behaviour.is_some() || g.agent.is_some())
        .map(|g| g.count as u64)
        .sum();
    let need = b.estimate(total, senders);
    if need <= b.available_bytes {
        return;
    }
    let Some((gi, g)) = wf
        .vehicles
        .iter()
        .enumerate()
        .max_by_key(|(i, g)| (g.count, std::cmp::Reverse(*i)))
    else {
        return;
    };
    // Vehicles that fit with this world's share of senders.
    let each = need / total.max(1);
    let fits = b.available_bytes / each.max(1);
    v.push(
        ProblemKind::Range,
        &FieldPath::root().key("vehicles").index(gi).key("count"),
        format!(
            "{total} vehicles need about {} (≈ {:.1} KB each, estimated), but this machine has {} \
             available: at most about {fits} vehicles fit{}",
            gb(need),
            each as f64 / 1024.0,
            gb(b.available_bytes),
            if wf.vehicles.len() > 1 {
                format!(" (this group has {})", g.count)
            } else {
                String::new()
            }
        ),
    );
}
