//! # shoal-output
//!
//! What every shoal crate needs to write its outputs, without the simulated world: files
//! written whole or not at all ([`files`]).

pub mod files;
