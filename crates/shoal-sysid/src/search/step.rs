//! What a search reports while it runs.

/// What a search reports while it runs (to [`search`](super::search)'s `progress`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step<'a> {
    /// A stage begins: what it does and, when known in advance, how many fits it makes.
    Stage {
        /// What the stage does.
        stage: &'a str,
        /// Candidate fits it makes, when known.
        fits: Option<usize>,
    },
    /// A candidate fit finished (its name).
    Fit(&'a str),
}
