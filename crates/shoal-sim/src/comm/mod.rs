//! The shared optical medium: frames take airtime, modems are half-duplex, overlapping frames
//! collide unless one is `capture_ratio` times stronger, transmit queues are bounded, access is
//! one protocol per modem (`mac`), the LED→photodiode ray can be blocked by walls,
//! obstacles and other hulls, and every reception is decided by the link budget of
//! [`shoal_model::optics`] with a draw from the *receiver's* random stream.
//!
//! One step runs three systems in order (all in [`crate::systems::StepSet::Comm`]):
//! 1. [`comm_snapshot_system`]: the spatial grid of the vehicles brought up to the poses that
//!    the vehicle pass copied into [`Medium::poses`], pruning of old transmissions;
//! 2. [`comm_transmit_system`]: frames handed to modems (from behaviours or agents) enter the
//!    bounded queues; idle modems start transmitting in time order within the step, so carrier
//!    sense sees exactly the transmissions that started before it;
//! 3. [`comm_deliver_system`]: every frame whose transmission ended in this step is evaluated
//!    at each candidate receiver — in parallel over receivers, each using only its own state
//!    and random stream — so delivery never depends on system order or thread count.
//!
//! The code is split by concern:
//! - `frames`: outboxes, inboxes and received frames, the modems' transmit queues and the
//!   vehicles' random streams for the medium;
//! - `stats`: reception counters per link and vehicle, and the distance and latency bins;
//! - `links`: outcomes of attempts, a link's counters and a receiver's links by sender;
//! - `ledger`: the reception attempts of recent steps, folded into those counters in bulk;
//! - `grid`: the dense spatial grid used for range and occlusion queries;
//! - `ending`: the frames ending in a step, their possible interferers and candidate receivers,
//!   in flat buffers, for the delivery phase;
//! - `modem_lanes`: one receiver's modems as lanes, the geometry of a transmission at all of
//!   them computed at once;
//! - `copy_lanes`: one frame's copies as lanes, the geometry of the best-case bound for all
//!   of them at once;
//! - `lanes`: what the lane kernels share — four-lane types, poses in lanes, and the run-time
//!   choice between a kernel compiled for AVX and the baseline;
//! - `mac`: the link layer — medium access, one protocol per file (ALOHA, carrier sense,
//!   slotted ALOHA, TDMA, CSMA/CA, p-persistent CSMA), and stop-and-wait ARQ;
//! - `air`: the transmissions on record by position, for carrier sensing;
//! - `countdown`: the vehicles counting idle back-off slots down, asked again only when a
//!   frame starts near them or their count runs out;
//! - `flows`: unicast traffic per sender and destination;
//! - `medium`: the [`Medium`] resource, frames on the air and the precomputed link budget;
//! - `sensing`: carrier sensing (power heard now, since when the channel is idle);
//! - `link_layer`: a vehicle's link layer around its queues (acknowledgements, retries,
//!   duplicates, addressing);
//! - `reception`: the decision of one reception at its receiver;
//! - `transmit`: the transmit phase's walk through the step — the vehicles' turns in time
//!   order, each port's decision, the frames started;
//! - `started`: what a walk started, merged from the parts walked apart and put on record;
//! - `parts`: the vehicles with a turn in independent groups, packed into parts walked on
//!   several threads;
//! - `systems`: the three step systems above.

mod air;
mod copy_lanes;
mod countdown;
mod ending;
mod flows;
mod frames;
mod grid;
mod lanes;
mod ledger;
mod link_layer;
mod links;
mod mac;
mod medium;
mod modem_lanes;
mod parts;
mod reception;
mod sensing;
mod started;
mod stats;
mod systems;
mod transmit;

pub use flows::{FlowStats, Flows};
pub use frames::{
    CommRng, FrameEvent, FrameOutcome, Inbox, Kind, ModemPort, Modems, OutFrame, Outbox, Received,
    comm_rng,
};
pub use grid::Grid;
pub use ledger::{Grouped, Ledger};
pub use links::{LinkEvent, LinkMap, LinkStats, Outcome};
pub use mac::Link;
pub use medium::{GRID_SKIN, Medium, ModemConsts, Transmission, cutoff_range, received_power};
pub use stats::{
    CommStats, DIST_BIN, DIST_BINS, Heard, LAT_BINS, latency_bin, latency_bin_centre,
    latency_percentile,
};
pub use systems::{comm_deliver_system, comm_snapshot_system, comm_transmit_system};
