//! The one colour key of link outcomes: how delivered, collided, occluded, out-of-budget and
//! half-duplex receptions look wherever they are drawn. [`LINK_KEY`] is the only place these
//! colours are written; every consumer takes them from it:
//!
//! * the PNG/SVG plots that colour outcomes (`links_over_time`, [`crate::comm_report`]);
//! * the GIF of `shoal render` (its lines, legend and palette, [`crate::replay::gif`]);
//! * `replay.html`: the colours travel in the page's JSON header
//!   ([`crate::replay::Meta::outcomes`], [`crate::replay::outcome_key`]), from which the
//!   viewer colours its lines, legend and timeline.
//!
//! Acknowledgement frames (the link layer's answers to unicast frames) are drawn apart from
//! the frames behaviours and agents send: dashed, in the colour of their outcome, in the GIF,
//! in `replay.html` and in `run.mcap`'s `/links` alike; each legend gives them one entry,
//! [`ACK_LABEL`] (the page gets it in its header, [`crate::replay::Meta::ack_label`]). The
//! docs say it as [`ACK_PROSE`].
//!
//! The outcomes themselves, and their codes in the replay's `links` array, are the medium's
//! ([`shoal_sim::comm::Outcome`], the one list); this file only says how each looks, so that
//! the replay, the GIF and the plots all build on it and it builds on nothing of theirs.
//!
//! The colours read on white (plots), on the GIF's pale water and on the replay's dark water,
//! and keep apart from the first group colours (tab10 blue, orange, green) that the vehicles
//! wear in the GIF and the replay. The losses that matter least for a swarm (out of the link
//! budget: too far, wrong angle, bit errors) are grey. Docs name the colours by
//! [`OutcomeStyle::colour_name`] ([`prose`]; a test keeps README.md and docs/replay.md in step).

pub use shoal_sim::comm::Outcome;

/// How one link outcome is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutcomeStyle {
    /// The outcome.
    pub outcome: Outcome,
    /// Short legend label.
    pub label: &'static str,
    /// What it means, for legends with room (plots); empty when the label says it all.
    pub detail: &'static str,
    /// The colour's name in prose (docs).
    pub colour_name: &'static str,
    /// The colour (sRGB: red, green, blue).
    pub rgb: (u8, u8, u8),
}

/// The key, in outcome-code order ([`Outcome::code`]).
pub const LINK_KEY: [OutcomeStyle; 5] = [
    OutcomeStyle {
        outcome: Outcome::Delivered,
        label: "delivered",
        detail: "",
        colour_name: "teal",
        rgb: (0, 150, 130),
    },
    OutcomeStyle {
        outcome: Outcome::Collided,
        label: "collided",
        detail: "overlapping frames",
        colour_name: "magenta",
        rgb: (220, 0, 200),
    },
    OutcomeStyle {
        outcome: Outcome::Occluded,
        label: "occluded",
        detail: "line of sight blocked",
        colour_name: "amber",
        rgb: (225, 165, 0),
    },
    OutcomeStyle {
        outcome: Outcome::OutOfBudget,
        label: "out of budget",
        detail: "range, angle, bit errors",
        colour_name: "grey",
        rgb: (140, 140, 140),
    },
    OutcomeStyle {
        outcome: Outcome::HalfDuplex,
        label: "half-duplex",
        detail: "receiver transmitting",
        colour_name: "violet",
        rgb: (130, 80, 230),
    },
];

/// The legend entry of acknowledgement frames, which are drawn dashed in their outcome's
/// colour (GIF and `replay.html`).
pub const ACK_LABEL: &str = "acknowledgement (dashed)";

/// How acknowledgement frames are drawn, in the words of the docs (README.md and
/// docs/replay.md give it as it is: a test checks).
pub const ACK_PROSE: &str = "acknowledgement frames are dashed, in their outcome's colour";

/// The style of outcome `o`.
pub fn style(o: Outcome) -> &'static OutcomeStyle {
    &LINK_KEY[o.code() as usize]
}

/// The colour of outcome `o` as `#rrggbb`.
pub fn hex(o: Outcome) -> String {
    let (r, g, b) = style(o).rgb;
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The key in words, as the docs give it: "delivered (teal), collided (magenta), …".
pub fn prose() -> String {
    LINK_KEY
        .iter()
        .map(|s| format!("{} ({})", s.label, s.colour_name))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_key_is_in_code_order_with_distinct_colours() {
        for (i, s) in LINK_KEY.iter().enumerate() {
            assert_eq!(s.outcome.code() as usize, i, "{s:?}");
            assert_eq!(style(s.outcome), s);
        }
        for (i, a) in LINK_KEY.iter().enumerate() {
            for b in &LINK_KEY[i + 1..] {
                let d: u32 = [
                    a.rgb.0.abs_diff(b.rgb.0),
                    a.rgb.1.abs_diff(b.rgb.1),
                    a.rgb.2.abs_diff(b.rgb.2),
                ]
                .iter()
                .map(|&x| u32::from(x))
                .sum();
                assert!(d > 120, "{} and {} look alike", a.label, b.label);
            }
        }
        assert_eq!(hex(Outcome::Delivered), "#009682");
        assert!(prose().starts_with("delivered (teal), collided (magenta)"));
    }

    /// README.md and docs/replay.md say how acknowledgement frames are drawn, in the words
    /// of the key.
    #[test]
    fn the_docs_say_how_acknowledgements_are_drawn() {
        let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        for f in ["README.md", "docs/replay.md"] {
            let text = std::fs::read_to_string(repo.join(f)).unwrap();
            let folded = text.split_whitespace().collect::<Vec<_>>().join(" ");
            assert!(folded.contains(ACK_PROSE), "{f} does not say: {ACK_PROSE}");
        }
    }
}
