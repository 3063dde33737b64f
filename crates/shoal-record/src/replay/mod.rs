//! The replay page of a run and its GIF: the data gathered while the world ran
//! ([`shoal_record::replay`], re-exported here) written as one self-contained `replay.html`
//! ([`html`]), drawn as an animated GIF without a browser ([`gif`]), and a synthetic replay
//! for tests, size measurements and the viewer's development ([`demo`]). See docs/replay.md.

pub use shoal_sim::replay::*;

pub mod demo;
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
