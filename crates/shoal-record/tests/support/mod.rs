//! Helpers shared by the integration tests (each test binary uses some of them).
#![allow(dead_code)]

pub mod browser;
pub mod demo;
pub mod plots;
// The same scenes as shoal-sim's own tests build.
#[path = "../../../shoal-sim/tests/support/world.rs"]
pub mod world;
