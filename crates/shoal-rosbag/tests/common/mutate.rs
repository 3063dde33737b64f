//! Seeded mutations of valid inputs for the fuzz tests: message bodies with a few bytes
//! changed, a count altered, cut short or with bytes appended ([`Mutation`]); `.msg` schema
//! texts with a token or a line deleted, duplicated or swapped ([`Edit`]). A seeded generator
//! ([`Rng`], SplitMix64) makes each case reproducible from its seed; [`cases`] is the number
//! of cases a fuzz loop runs (`PROPTEST_CASES` raises it for a long campaign).

#![allow(dead_code)]

use super::cdr::{Body, Kind};

/// The cases of a fuzz loop: `default`, or `PROPTEST_CASES` if larger.
pub fn cases(default: usize) -> usize {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .map_or(default, |n: usize| n.max(default))
}

/// SplitMix64: a small seeded generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5DEE_CE66_D1CE_4E5B)
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A whole number in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// A byte other than 0.
    pub fn nonzero_byte(&mut self) -> u8 {
        1 + (self.next() % 255) as u8
    }
}

/// A change to a valid message body.
#[derive(Clone, Debug, PartialEq)]
pub enum Mutation {
    /// These bytes (position, xor mask ≠ 0) changed.
    Bytes(Vec<(usize, u8)>),
    /// The `uint32` count (a string's or a sequence's) at this leaf set to this value.
    Count(usize, u32),
    /// The body cut to this many bytes.
    Truncate(usize),
    /// These bytes appended.
    Extend(Vec<u8>),
}

impl Mutation {
    /// A random mutation of `body`, each kind as likely.
    pub fn random(rng: &mut Rng, body: &Body) -> Mutation {
        let n = body.bytes.len();
        match rng.below(4) {
            0 => {
                let flips = 1 + rng.below(3);
                Mutation::Bytes(
                    (0..flips)
                        .map(|_| (rng.below(n), rng.nonzero_byte()))
                        .collect(),
                )
            }
            1 => {
                let counts: Vec<usize> = (0..body.leaves.len())
                    .filter(|&i| body.leaves[i].kind == Kind::Count)
                    .collect();
                let leaf = counts[rng.below(counts.len())];
                let was = body.leaves[leaf].value as u32;
                let to = match rng.below(5) {
                    0 => was + 1,
                    1 => was.saturating_sub(1),
                    2 => was + 2 + rng.below(6) as u32,
                    3 => 0,
                    _ => (rng.next() as u32) | 0x1000_0000,
                };
                Mutation::Count(leaf, if to == was { was + 1 } else { to })
            }
            2 => Mutation::Truncate(rng.below(n)),
            _ => Mutation::Extend((0..1 + rng.below(16)).map(|_| rng.next() as u8).collect()),
        }
    }

    /// The mutated bytes.
    pub fn apply(&self, body: &Body) -> Vec<u8> {
        let mut b = body.bytes.clone();
        match self {
            Mutation::Bytes(list) => {
                for &(at, mask) in list {
                    b[at] ^= mask;
                }
            }
            Mutation::Count(leaf, v) => {
                let at = body.leaves[*leaf].at;
                b[at..at + 4].copy_from_slice(&v.to_le_bytes());
            }
            Mutation::Truncate(n) => b.truncate(*n),
            Mutation::Extend(more) => b.extend_from_slice(more),
        }
        b
    }

    /// The first byte of the body that may read differently: values wholly before it are
    /// read as they were written.
    pub fn first_changed(&self, body: &Body) -> usize {
        match self {
            Mutation::Bytes(list) => list.iter().map(|&(at, _)| at).min().unwrap_or(0),
            Mutation::Count(leaf, _) => body.leaves[*leaf].at,
            Mutation::Truncate(n) => *n,
            Mutation::Extend(_) => body.bytes.len(),
        }
    }

    /// Whether every changed byte lies inside a number (the layout of the body unchanged).
    pub fn numbers_only(&self, body: &Body) -> bool {
        match self {
            Mutation::Bytes(list) => list.iter().all(|&(at, _)| {
                body.leaves
                    .iter()
                    .any(|l| l.kind.is_number() && (l.at..l.at + l.size).contains(&at))
            }),
            Mutation::Extend(_) => true,
            _ => false,
        }
    }
}

/// A change to a `.msg` schema text, at a line (0-based) and, for tokens, a token of it
/// (tokens: the line split at whitespace).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edit {
    DeleteToken(usize, usize),
    DuplicateToken(usize, usize),
    /// Token j and j + 1 of the line swapped.
    SwapTokens(usize, usize),
    DeleteLine(usize),
    DuplicateLine(usize),
    /// Line l and l + 1 swapped.
    SwapLines(usize),
}

impl Edit {
    /// A random edit of `text` (lines with tokens only, for token edits).
    pub fn random(rng: &mut Rng, text: &str) -> Edit {
        let lines: Vec<&str> = text.lines().collect();
        let l = rng.below(lines.len());
        let with_tokens: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].split_whitespace().count() > 0)
            .collect();
        let t = with_tokens[rng.below(with_tokens.len())];
        let n = lines[t].split_whitespace().count();
        match rng.below(6) {
            0 => Edit::DeleteToken(t, rng.below(n)),
            1 => Edit::DuplicateToken(t, rng.below(n)),
            2 if n > 1 => Edit::SwapTokens(t, rng.below(n - 1)),
            2 | 3 => Edit::DeleteLine(l),
            4 => Edit::DuplicateLine(l),
            _ => Edit::SwapLines(l.min(lines.len().saturating_sub(2))),
        }
    }

    /// The line a token edit changes (`None` for line edits).
    pub fn token_line(self) -> Option<usize> {
        match self {
            Edit::DeleteToken(l, _) | Edit::DuplicateToken(l, _) | Edit::SwapTokens(l, _) => {
                Some(l)
            }
            _ => None,
        }
    }

    /// The lines the edit changes, moves or removes.
    pub fn lines(self) -> Vec<usize> {
        match self {
            Edit::DeleteToken(l, _)
            | Edit::DuplicateToken(l, _)
            | Edit::SwapTokens(l, _)
            | Edit::DeleteLine(l)
            | Edit::DuplicateLine(l) => vec![l],
            Edit::SwapLines(l) => vec![l, l + 1],
        }
    }

    /// The edited text (a token-edited line rejoined with single spaces).
    pub fn apply(self, text: &str) -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        let tokens =
            |s: &str| -> Vec<String> { s.split_whitespace().map(str::to_string).collect() };
        match self {
            Edit::DeleteToken(l, j) => {
                let mut t = tokens(&lines[l]);
                t.remove(j);
                lines[l] = t.join(" ");
            }
            Edit::DuplicateToken(l, j) => {
                let mut t = tokens(&lines[l]);
                t.insert(j, t[j].clone());
                lines[l] = t.join(" ");
            }
            Edit::SwapTokens(l, j) => {
                let mut t = tokens(&lines[l]);
                t.swap(j, j + 1);
                lines[l] = t.join(" ");
            }
            Edit::DeleteLine(l) => {
                lines.remove(l);
            }
            Edit::DuplicateLine(l) => {
                let copy = lines[l].clone();
                lines.insert(l, copy);
            }
            Edit::SwapLines(l) => {
                if l + 1 < lines.len() {
                    lines.swap(l, l + 1);
                }
            }
        }
        let mut out = lines.join("\n");
        out.push('\n');
        out
    }
}
