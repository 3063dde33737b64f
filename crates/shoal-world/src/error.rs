//! Errors of world and vehicle files. Every problem names the file, the line and column (when
//! the field is written in the file), the field path (e.g. `vehicles[0].model.body.mass`) and,
//! for numbers, the allowed range with its unit.

use std::fmt;
use std::path::PathBuf;

/// One segment of a field path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Seg {
    /// Table key.
    Key(String),
    /// Array index.
    Index(usize),
}

/// Path of a field inside a file, e.g. `vehicles[2].mission[0].depth`.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct FieldPath(pub Vec<Seg>);

impl FieldPath {
    /// The empty path (the whole file).
    pub fn root() -> Self {
        Self(Vec::new())
    }
    /// This path extended by a key.
    pub fn key(&self, k: &str) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_string()));
        p
    }
    /// This path extended by an index.
    pub fn index(&self, i: usize) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }
    /// This path followed by another.
    pub fn join(&self, other: &FieldPath) -> Self {
        let mut p = self.clone();
        p.0.extend(other.0.iter().cloned());
        p
    }
    /// Parses a serde_path_to_error path (`a.b[3].c`).
    pub fn parse(s: &str) -> Self {
        let mut out = Vec::new();
        for part in s.split('.') {
            if part.is_empty() || part == "?" {
                continue;
            }
            let mut rest = part;
            if let Some(i) = rest.find('[') {
                if i > 0 {
                    out.push(Seg::Key(rest[..i].to_string()));
                }
                rest = &rest[i..];
                while let Some(stripped) = rest.strip_prefix('[') {
                    let end = stripped.find(']').unwrap_or(stripped.len());
                    if let Ok(n) = stripped[..end].parse() {
                        out.push(Seg::Index(n));
                    }
                    rest = stripped.get(end + 1..).unwrap_or("");
                }
            } else {
                out.push(Seg::Key(rest.to_string()));
            }
        }
        Self(out)
    }
    /// The last key of the path, if any.
    pub fn last_key(&self) -> Option<&str> {
        self.0.iter().rev().find_map(|s| match s {
            Seg::Key(k) => Some(k.as_str()),
            Seg::Index(_) => None,
        })
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for s in &self.0 {
            match s {
                Seg::Key(k) => {
                    if !first {
                        f.write_str(".")?;
                    }
                    f.write_str(k)?;
                }
                Seg::Index(i) => write!(f, "[{i}]")?,
            }
            first = false;
        }
        Ok(())
    }
}

/// What kind of problem a file has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProblemKind {
    /// The file could not be read.
    Io,
    /// Not valid TOML.
    Syntax,
    /// A field the schema does not know.
    UnknownField,
    /// A required field is missing.
    MissingField,
    /// A value of the wrong type (e.g. text where a number in metres is expected).
    Type,
    /// A number outside its allowed range.
    Range,
    /// A name that refers to nothing (preset, thruster, tilt).
    Reference,
    /// Vehicles overlapping each other or obstacles.
    Overlap,
    /// A vehicle or obstacle outside the pool.
    Outside,
    /// Anything else that makes the world inconsistent.
    Invalid,
}

/// One problem in a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Kind.
    pub kind: ProblemKind,
    /// The field, if the problem belongs to one.
    pub field: Option<FieldPath>,
    /// 1-based line and column in the file, when the field is written there.
    pub line_col: Option<(usize, usize)>,
    /// Human-readable explanation including the allowed range.
    pub message: String,
}

/// A world or vehicle file that cannot be used, with every problem found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct WorldError {
    /// The file (or `<embedded default world>`).
    pub file: PathBuf,
    /// The problems, in file order where known.
    pub problems: Vec<Problem>,
}

impl WorldError {
    /// An error with one problem.
    pub fn single(file: impl Into<PathBuf>, problem: Problem) -> Self {
        Self {
            file: file.into(),
            problems: vec![problem],
        }
    }
    /// Whether any problem is of this kind.
    pub fn has(&self, kind: ProblemKind) -> bool {
        self.problems.iter().any(|p| p.kind == kind)
    }
    /// The first problem.
    pub fn first(&self) -> &Problem {
        &self.problems[0]
    }
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, p) in self.problems.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{}", self.file.display())?;
            if let Some((l, c)) = p.line_col {
                write!(f, ":{l}:{c}")?;
            }
            f.write_str(": ")?;
            if let Some(field) = &p.field {
                if p.kind == ProblemKind::UnknownField {
                    // The message names the unknown key; say where it is.
                    let parent = FieldPath(field.0[..field.0.len().saturating_sub(1)].to_vec());
                    if !parent.0.is_empty() {
                        write!(f, "in `{parent}`: ")?;
                    }
                } else if !field.0.is_empty() {
                    write!(f, "`{field}`: ")?;
                }
            }
            f.write_str(&p.message)?;
        }
        Ok(())
    }
}

/// Positions of the keys of a TOML document, for turning field paths into lines.
pub struct SourceMap<'a> {
    text: &'a str,
    doc: Option<toml::Spanned<toml::de::DeTable<'a>>>,
}

impl<'a> SourceMap<'a> {
    /// Indexes `text` (a document that fails to parse yields no positions).
    pub fn new(text: &'a str) -> Self {
        Self {
            text,
            doc: toml::de::DeTable::parse(text).ok(),
        }
    }

    /// 1-based (line, column) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let col = before.rfind('\n').map_or(offset, |nl| offset - nl - 1) + 1;
        (line, col)
    }

    /// Position of the deepest part of `path` that is written in the file: the key of the
    /// field itself when present, otherwise of its nearest written ancestor.
    pub fn locate(&self, path: &FieldPath) -> Option<(usize, usize)> {
        use toml::de::DeValue;
        let doc = self.doc.as_ref()?;
        let mut best: Option<usize> = None;
        let mut table = Some(doc.get_ref());
        let mut value: Option<&toml::Spanned<DeValue<'a>>> = None;
        for seg in &path.0 {
            match seg {
                Seg::Key(k) => {
                    let t = match (table, value) {
                        (Some(t), _) => t,
                        (None, Some(v)) => match v.get_ref() {
                            DeValue::Table(t) => t,
                            _ => break,
                        },
                        _ => break,
                    };
                    let Some((key, v)) = t.get_key_value(k.as_str()) else {
                        break;
                    };
                    best = Some(key.span().start);
                    value = Some(v);
                    table = None;
                }
                Seg::Index(i) => {
                    let Some(v) = value else { break };
                    let DeValue::Array(a) = v.get_ref() else {
                        break;
                    };
                    let Some(item) = a.get(*i) else { break };
                    best = Some(item.span().start);
                    value = Some(item);
                    table = None;
                }
            }
        }
        best.map(|o| self.line_col(o))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_parse_and_print() {
        let p = FieldPath::parse("vehicles[2].model.thrusters[0].curve.ct_pos");
        assert_eq!(p.to_string(), "vehicles[2].model.thrusters[0].curve.ct_pos");
        assert_eq!(p.last_key(), Some("ct_pos"));
    }

    #[test]
    fn locate_finds_keys_in_arrays_of_tables() {
        let text = "seed = 1\n[[vehicles]]\nname = \"a\"\n[[vehicles]]\nname = \"b\"\ncount = 3\n[vehicles.model.body]\nmass = -1\n";
        let sm = SourceMap::new(text);
        assert_eq!(
            sm.locate(&FieldPath::parse("vehicles[1].count")),
            Some((6, 1))
        );
        assert_eq!(
            sm.locate(&FieldPath::parse("vehicles[1].model.body.mass")),
            Some((8, 1))
        );
        // Not written: nearest written ancestor.
        assert_eq!(
            sm.locate(&FieldPath::parse("vehicles[1].model.body.volume"))
                .map(|p| p.0),
            Some(7)
        );
        assert_eq!(sm.locate(&FieldPath::parse("seed")), Some((1, 1)));
    }
}
