//! # shoal-output
//!
//! What every shoal crate needs to write its outputs, without the simulated world: files
//! written whole or not at all ([`files`]) and plots, PNG and SVG from one description, with
//! an embedded font ([`plot`]); numbers in sentences for people ([`words`]).

pub mod files;
pub mod plot;
pub mod words;
