//! Whole-swarm access through flat arrays, one row per vehicle in id order, for bindings that
//! drive every vehicle at once without a loop per vehicle in their own language (the Python
//! package, `crates/shoal-py`):
//! - read a [`Quantity`] of every vehicle (state, sensor readings, setpoints, actuators, modem
//!   counters) into one slice ([`Sim::read_f64`], [`Sim::read_i64`], [`Sim::read_bool`]);
//! - set the setpoints ([`Sim::set_setpoints`]) or raw actuator commands
//!   ([`Sim::set_actuators`]) of all vehicles or a subset, every value checked before
//!   anything changes: a NaN or infinite number, an unknown mode or pump code, or (unless
//!   clipping was asked for) a value outside its range is a [`CommandError`] naming the
//!   vehicle, the field and the allowed range;
//! - queue frames on vehicles' modems ([`Sim::queue_frames`]) and collect the frames
//!   delivered in a step with the outcomes of acknowledged unicasts
//!   ([`Sim::collect_received`], [`Arrivals`]).
//!
//! A command written here acts like an external agent's ([`crate::agents`]): it replaces the
//! setpoints the built-in controller follows from its next control tick on, and ends the
//! agent fallback of an agent-driven vehicle. A vehicle's mission and built-in behaviour
//! still run and may replace the setpoints again. The ranges are the agents' (one source:
//! [`crate::orders`]); agents clamp values outside them, here they are errors unless the
//! caller clips.
//!
//! `quantity` holds what can be read and the reads; `commands` the commands and the
//! frames; `columns` the column types both take and `error` the error both give. This file
//! only gathers them.

mod columns;
mod commands;
mod error;
mod quantity;

pub use columns::{Column, Rows};
pub use commands::{ActuatorOrder, Arrivals, MODES, SetpointOrder, mode_code};
pub use error::CommandError;
pub use quantity::{BatchShape, Dtype, Quantity};
