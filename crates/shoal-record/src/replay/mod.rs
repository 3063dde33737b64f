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

/// Puts the page's colour key into `meta` where it is missing (in a replay as gathered, or
/// in a page written before the key or its entry for acknowledgements travelled in the
/// header): the outcomes ([`outcome_key`]) and the legend entry of acknowledgement frames
/// ([`crate::link_key::ACK_LABEL`]).
pub fn fill_key(meta: &mut Meta) {
    if meta.outcomes.is_empty() {
        meta.outcomes = outcome_key();
    }
    if meta.ack_label.is_empty() {
        meta.ack_label = crate::link_key::ACK_LABEL.to_string();
    }
}

/// The synthetic replay of the tests (a test kit, compiled only for them).
#[cfg(test)]
#[path = "../../tests/support/demo.rs"]
#[allow(
    dead_code,
    reason = "the unit tests use the demo itself, not every constant"
)]
pub(crate) mod demo;
