//! Names that become parts of shared-memory service names (agent prefixes and agent names).

/// Whether `s` can be part of a service name: 1–64 of `[A-Za-z0-9_.-]`.
pub fn valid_service_word(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// `name` made into a valid service word (other characters become `_`, at most 64).
pub fn service_word(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    if s.is_empty() { "world".into() } else { s }
}
