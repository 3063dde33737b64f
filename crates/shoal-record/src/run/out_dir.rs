//! Where a run's outputs go when the caller names no folder: `out/<world name>` in the
//! working folder, the name made a path word (lower case, letters and digits, `-` between).

use std::path::PathBuf;

/// `out/<slug of name>`: e.g. `"Paper diving (5.2)"` → `out/paper-diving-5-2`.
pub fn default_out(world_name: &str) -> PathBuf {
    PathBuf::from("out").join(slug(world_name))
}

/// `name` as a path word; `world` when nothing of it is left.
fn slug(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let s = s
        .split('-')
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("-");
    if s.is_empty() { "world".into() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_path_words() {
        assert_eq!(
            default_out("Paper diving (5.2)"),
            PathBuf::from("out/paper-diving-5-2")
        );
        assert_eq!(
            default_out("default swarm"),
            PathBuf::from("out/default-swarm")
        );
        assert_eq!(default_out("λ!"), PathBuf::from("out/world"));
    }
}
