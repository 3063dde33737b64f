//! What Python passes as a world (a path, world-file text, or nothing for the embedded default
//! world) and as a thread count, read the same way by `World` and `shoal.run`, and how such a
//! world is loaded ([`Source::load`]).

use crate::errors::WorldError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyString;
use shoal_record::run::{Changes, WorldSource, load_world};
use shoal_world::cancel::Cancel;
use shoal_world::desc::WorldDesc;
use std::path::PathBuf;

/// Name used in messages for world text given directly.
pub const TEXT_NAME: &str = "<world text>";

/// A world as Python named it.
#[derive(Clone, Debug)]
pub enum Source {
    /// The embedded default world of `shoal run`.
    Embedded,
    /// A world file.
    File(PathBuf),
    /// The TOML text of a world.
    Text(String),
}

impl Source {
    /// Loads this world with `seed` in place of its own, as `shoal run --seed` does: the seed
    /// is the world file's, so it draws the placement as well as the vehicles' streams.
    pub fn load(&self, py: Python<'_>, seed: Option<u64>) -> PyResult<WorldDesc> {
        let changes = Changes {
            seed,
            ..Changes::default()
        };
        py.detach(|| load_world(self.as_world(), &changes, &Cancel::new()))
            .map_err(|e| WorldError::new_err(e.to_string()))
    }

    /// A path (str or path-like) or the TOML text of a world (a str containing a newline or
    /// `=`); `None` is the embedded default world.
    pub fn of(world: Option<&Bound<'_, PyAny>>) -> PyResult<Source> {
        let Some(w) = world.filter(|w| !w.is_none()) else {
            return Ok(Source::Embedded);
        };
        if let Ok(s) = w.cast::<PyString>() {
            let s = s.to_cow()?.into_owned();
            return Ok(if s.contains('\n') || s.contains('=') {
                Source::Text(s)
            } else {
                Source::File(PathBuf::from(s))
            });
        }
        w.extract::<PathBuf>().map(Source::File).map_err(|_| {
            PyValueError::new_err("world: expected a world file's path or the TOML text of a world")
        })
    }

    /// The same for the run driver's loader.
    pub fn as_world(&self) -> WorldSource<'_> {
        match self {
            Source::Embedded => WorldSource::Embedded,
            Source::File(p) => WorldSource::File(p),
            Source::Text(t) => WorldSource::Text {
                text: t,
                name: TEXT_NAME,
            },
        }
    }
}

/// Working threads: `None` is every core (as `shoal run`), else 1 … 256.
pub fn threads(threads: Option<usize>) -> PyResult<usize> {
    match threads {
        None => Ok(shoal_sim::parallel::all_cores()),
        Some(t @ 1..=256) => Ok(t),
        Some(t) => Err(PyValueError::new_err(format!(
            "threads = {t}: allowed 1 … 256"
        ))),
    }
}
