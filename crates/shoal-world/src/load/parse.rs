//! The serde stage: TOML text → [`WorldFile`] with located problems. A misspelt key does not
//! hide the next one: each unknown key is reported, taken out, and the file read again, so
//! one error names every unknown key (and, once the rest reads, the later stages add every
//! out-of-range number).

use super::messages::toml_problem;
use crate::error::{FieldPath, Problem, ProblemKind, SourceMap, WorldError};
use crate::spec::WorldFile;
use serde_path_to_error::Segment;
use std::path::Path;

/// At most this many unknown keys are collected before the rest are left unreported.
const MAX_UNKNOWN: usize = 200;

/// The serde stage alone: TOML → [`WorldFile`] with located errors (every unknown key).
pub fn parse_world_file(
    text: &str,
    file: &Path,
    sm: &SourceMap<'_>,
) -> Result<WorldFile, WorldError> {
    let (wf, unknown) = parse_collecting(text, file, sm)?;
    if unknown.is_empty() {
        Ok(wf)
    } else {
        Err(WorldError {
            file: file.to_path_buf(),
            problems: unknown,
        })
    }
}

/// The file read with its unknown keys left out, and a problem for each of those keys (none:
/// the file as it is). A syntax error or any other problem the file cannot be read past is
/// an error, with the unknown keys found before it.
pub(super) fn parse_collecting(
    text: &str,
    file: &Path,
    sm: &SourceMap<'_>,
) -> Result<(WorldFile, Vec<Problem>), WorldError> {
    let de = toml::de::Deserializer::parse(text)
        .map_err(|e| WorldError::single(file, toml_problem(&e, None, sm, ProblemKind::Syntax)))?;
    let first = match serde_path_to_error::deserialize(de) {
        Ok(wf) => return Ok((wf, Vec::new())),
        Err(e) => e,
    };
    let fail = |problems: Vec<Problem>| WorldError {
        file: file.to_path_buf(),
        problems,
    };
    let mut problems = Vec::new();
    let mut e = first;
    // Again as a value tree, from which each unknown key is taken out in turn.
    let mut doc: toml::Value = match text.parse::<toml::Table>() {
        Ok(t) => toml::Value::Table(t),
        Err(_) => return Err(fail(vec![located(&e, sm)])),
    };
    loop {
        let problem = located(&e, sm);
        let unknown = problem.kind == ProblemKind::UnknownField;
        problems.push(problem);
        if !unknown || problems.len() >= MAX_UNKNOWN || !remove(&mut doc, e.path()) {
            return Err(fail(problems));
        }
        match serde_path_to_error::deserialize::<_, WorldFile>(doc.clone()) {
            Ok(wf) => return Ok((wf, problems)),
            Err(next) => e = next,
        }
    }
}

/// The problem of a serde error, located by its span or its field path.
fn located(e: &serde_path_to_error::Error<toml::de::Error>, sm: &SourceMap<'_>) -> Problem {
    let path = FieldPath::parse(&e.path().to_string());
    toml_problem(e.inner(), Some(path), sm, ProblemKind::Invalid)
}

/// Takes the key at `path` (an unknown field's) out of `doc`; whether there was one.
fn remove(doc: &mut toml::Value, path: &serde_path_to_error::Path) -> bool {
    let segments: Vec<&Segment> = path.iter().collect();
    let Some((Segment::Map { key }, parents)) = segments.split_last() else {
        return false;
    };
    let mut at = doc;
    for s in parents {
        let next = match (s, at) {
            (Segment::Map { key }, toml::Value::Table(t)) => t.get_mut(key),
            (Segment::Seq { index }, toml::Value::Array(a)) => a.get_mut(*index),
            _ => None,
        };
        match next {
            Some(v) => at = v,
            None => return false,
        }
    }
    match at {
        toml::Value::Table(t) => t.remove(key).is_some(),
        _ => false,
    }
}
