//! The replay page of a run and its GIF: the data gathered while the world ran
//! ([`shoal_record::replay`], re-exported here) written as one self-contained `replay.html`
//! ([`html`]), drawn as an animated GIF without a browser ([`gif`]). A synthetic replay for tests,
//! size measurements and the viewer's development is a test kit beside the tests
//! (`tests/support/demo.rs`). See docs/replay.md.

pub use shoal_sim::replay::*;

pub mod gif;
pub mod html;

/// The colour key of link outcomes ([`crate::link_key::LINK_KEY`]) as the page's header
/// carries it ([`Meta::outcomes`]), by outcome code.
pub fn outcome_key() -> Vec<OutcomeMeta> {
    crate::link_key::LINK_KEY
        .iter()
        .map(|s| OutcomeMeta {
            name: s.label.to_string(),
            color: crate::link_key::hex(s.outcome),
        })
        .collect()
}

/// The synthetic replay of the tests (a test kit, compiled only for them).
#[cfg(test)]
#[path = "../../tests/support/demo.rs"]
#[allow(
    dead_code,
    reason = "the unit tests use the demo itself, not every constant"
)]
pub(crate) mod demo;
