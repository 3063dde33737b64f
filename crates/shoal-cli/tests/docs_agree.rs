//! What a newcomer reads agrees with the code: README.md and the docs are checked against the
//! binary and the libraries.
//!
//! * README's Status section names every command the binary has and the parts that exist
//!   (the fused step, the Python package), and calls none of them "next";
//! * memory per vehicle is stated once, in README's *Large worlds* paragraph (between the
//!   `memory-per-vehicle` markers); no other sentence about vehicles gives an amount of memory;
//! * every `cargo install` in the docs and scripts is `--locked` (without it cargo resolves the
//!   dependencies again, to versions nobody tested);
//! * the docs name the link outcomes' colours as the one key (`shoal_record::link_key`) does.

mod common;

use common::repo;
use std::path::PathBuf;
use std::process::Command;

/// The Markdown files a user reads: README.md, ARCHITECTURE.md, docs/, python/, examples/ and
/// the crates' READMEs.
fn markdown_files() -> Vec<PathBuf> {
    let root = repo();
    let mut out = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    let mut dirs = vec![
        root.join("docs"),
        root.join("python"),
        root.join("examples"),
        root.join("crates"),
    ];
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            if p.is_dir() {
                if !name.starts_with('.') && name != "target" && name != "node_modules" {
                    dirs.push(p);
                }
            } else if name.ends_with(".md") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn read(p: &PathBuf) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// `text` with its line breaks and indentation folded into single spaces.
fn folded(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The section of README.md under `## {title}`, up to the next `## `.
fn readme_section(title: &str) -> String {
    let readme = read(&repo().join("README.md"));
    let head = format!("\n## {title}\n");
    let at = readme
        .find(&head)
        .unwrap_or_else(|| panic!("README.md has no section {title:?}"));
    let rest = &readme[at + head.len()..];
    rest[..rest.find("\n## ").unwrap_or(rest.len())].to_string()
}

/// The binary's commands, as `shoal --help` lists them.
fn commands() -> Vec<String> {
    let o = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&o.stdout).to_string();
    let list = &help[help.find("Commands:").expect("a command list")..];
    list.lines()
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect()
}

#[test]
fn the_status_section_is_true_of_the_code() {
    let status = folded(&readme_section("Status"));
    let cmds = commands();
    assert!(cmds.len() >= 8, "{cmds:?}");
    let mut exists: Vec<String> = cmds.iter().map(|c| format!("`{c}`")).collect();
    exists.extend(["Python package".to_string(), "fused".to_string()]);
    for thing in &exists {
        assert!(
            status.contains(thing.as_str()),
            "README's Status does not list {thing}, which exists:\n{status}"
        );
    }
    // Whatever it calls next (or planned, to do) must not be something that exists.
    for word in ["Next", "next", "Planned", "planned", "To do", "to do"] {
        for (i, _) in status.match_indices(word) {
            let rest = &status[i..];
            let sentence = &rest[..rest.find(". ").unwrap_or(rest.len())];
            for thing in &exists {
                assert!(
                    !sentence.contains(thing.as_str()),
                    "README's Status calls {thing} {word:?}, but it exists: {sentence}"
                );
            }
        }
    }
}

/// Whether `sentence` states an amount of memory on the scale of a vehicle or a large world:
/// a number right before `KB`, `kB` or `GB` (MB are the sizes of pages and files).
fn states_memory(sentence: &str) -> bool {
    let chars: Vec<char> = sentence.chars().collect();
    (0..chars.len().saturating_sub(1)).any(|i| {
        let unit = [chars[i], chars[i + 1]];
        let is_unit = matches!(unit, ['K', 'B'] | ['k', 'B'] | ['G', 'B']);
        let after_ok = chars.get(i + 2).is_none_or(|c| !c.is_alphanumeric());
        let mut j = i;
        while j > 0 && chars[j - 1] == ' ' {
            j -= 1;
        }
        is_unit && after_ok && j > 0 && chars[j - 1].is_ascii_digit()
    })
}

/// The sentences of a Markdown text outside code blocks and tables.
fn prose_sentences(text: &str) -> Vec<String> {
    let mut prose = String::new();
    let mut code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            code = !code;
            continue;
        }
        if !code && !line.trim_start().starts_with('|') {
            prose.push_str(line);
            prose.push('\n');
        }
    }
    prose
        .split("\n\n")
        .flat_map(|para| {
            folded(para)
                .split(". ")
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}

const MEMORY_START: &str = "<!-- memory-per-vehicle:start -->";
const MEMORY_END: &str = "<!-- memory-per-vehicle:end -->";

#[test]
fn memory_per_vehicle_is_stated_once() {
    let mut found = Vec::new();
    for f in markdown_files() {
        let mut text = read(&f);
        if f.ends_with("README.md") && f.parent() == Some(repo().as_path()) {
            let (Some(a), Some(b)) = (text.find(MEMORY_START), text.find(MEMORY_END)) else {
                panic!("README.md has no {MEMORY_START} … {MEMORY_END} paragraph");
            };
            let figure = &text[a..b];
            assert_eq!(
                figure.matches(" KB per vehicle").count(),
                1,
                "README's memory paragraph states one figure per vehicle:\n{figure}"
            );
            text.replace_range(a..b, "");
        }
        for s in prose_sentences(&text) {
            let about_vehicles = s.contains("vehicle") || s.contains("10⁶");
            if about_vehicles && states_memory(&s) {
                found.push(format!(
                    "{}: {s}",
                    f.strip_prefix(repo()).unwrap_or(&f).display()
                ));
            }
        }
    }
    assert!(
        found.is_empty(),
        "memory per vehicle is stated outside README's memory paragraph (refer to it instead):\n{}",
        found.join("\n")
    );
}

#[test]
fn cargo_install_is_locked_everywhere() {
    let mut files = markdown_files();
    files.extend(
        std::fs::read_dir(repo().join("scripts"))
            .unwrap()
            .flatten()
            .map(|e| e.path()),
    );
    let mut unlocked = Vec::new();
    for f in files {
        let Ok(text) = std::fs::read_to_string(&f) else {
            continue;
        };
        for (n, line) in text.lines().enumerate() {
            if line.contains("cargo install") && !line.contains("--locked") {
                unlocked.push(format!("{}:{}: {line}", f.display(), n + 1));
            }
        }
    }
    assert!(
        unlocked.is_empty(),
        "`cargo install` without `--locked` resolves the dependencies again:\n{}",
        unlocked.join("\n")
    );
}

#[test]
fn the_docs_name_the_link_colours_of_the_one_key() {
    use shoal_record::link_key::{LINK_KEY, prose};
    let key = prose();
    for f in ["README.md", "docs/replay.md"] {
        let text = folded(&read(&repo().join(f)));
        assert!(
            text.contains(&key),
            "{f} does not give the colour key as it is: {key}"
        );
    }
    // Nowhere is an outcome given another colour of the key.
    for f in markdown_files() {
        let text = folded(&read(&f));
        for k in &LINK_KEY {
            for other in LINK_KEY.iter().filter(|o| o.colour_name != k.colour_name) {
                let wrong = format!("{} ({})", k.label, other.colour_name);
                assert!(
                    !text.contains(&wrong),
                    "{}: {wrong:?}, but {} is {}",
                    f.display(),
                    k.label,
                    k.colour_name
                );
            }
        }
    }
}
