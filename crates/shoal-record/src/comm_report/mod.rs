//! Run outputs of the optical medium: the communication section of `summary.json`, the tables
//! `links.csv` (per second: reception attempts by outcome), `connectivity.csv` (per second:
//! components, largest component, mean degree of the communication graph) and
//! `link_pairs.csv` (per sender → receiver), and plots (`plots`: delivery ratio against
//! distance with the link-budget curve, link outcomes and connectivity over time, the
//! communication graph, and — when the world floods a value — how many vehicles knew it over
//! time).
//!
//! `summary` builds the communication section of `summary.json`, `tables` writes the tables,
//! `envelope` computes the link budget's best case against distance, `plots` draws from
//! them; this file only gathers them.

mod envelope;
mod plots;
mod summary;
mod tables;

pub use envelope::{Envelope, delivery_envelope};
pub use plots::{DELIVERY_MARKER_PX, connectivity_plot, delivery_plot, links_plot, plots, wilson};
pub use summary::{
    CommSummary, DistanceBin, FLOWS_IN_SUMMARY, FlowSummary, GossipSummary, VehicleComm,
    flow_summaries, summarize,
};
pub use tables::{
    PAIRS_MAX_VEHICLES, table_names, write_connectivity_csv, write_link_pairs_csv, write_links_csv,
    write_tables,
};
