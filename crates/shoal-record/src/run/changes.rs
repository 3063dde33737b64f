//! A run's own options as changes of its world file ([`Changes`]), and the world they make
//! ([`load_world`]). Each option is a dotted-path override of the world file
//! ([`shoal_world::overrides`]), so the world loader checks it exactly as it checks the file:
//! `--seed -1` is refused with the file's own range, not a range of the command line's. The
//! one exception is the duration: it is checked against the file's range for `duration`
//! (1e-3 … 1e7 s, at most 1e10 steps) but set after loading, so that a run may stop before
//! the end of its missions (`shoal run world.toml --duration 5` runs their first 5 s; steps
//! after the end never come), where a world file must not name a step after its own end.

use shoal_world::cancel::{Cancel, Interrupted};
use shoal_world::desc::WorldDesc;
use shoal_world::error::WorldError;
use shoal_world::load::{DEFAULT_WORLD, EMBEDDED_NAME, ranges, read_text, too_many_steps};
use shoal_world::overrides::{ChangedError, Override, OverrideError, load_until};
use std::path::Path;

/// What a run may change of its world besides the file itself: the options of `shoal run` and
/// the keywords of Python's `shoal.run`. `None` keeps the world's value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Changes {
    /// The world's seed (`seed`).
    pub seed: Option<u64>,
    /// Simulated time \[s\] (`duration`).
    pub duration: Option<f64>,
    /// Draw the plots (`[output] plots`).
    pub plots: Option<bool>,
    /// Write `replay.html` (`[output] replay`).
    pub replay: Option<bool>,
    /// Write `run.mcap` (`[output] mcap`).
    pub mcap: Option<bool>,
    /// External agents: `lockstep` or `free` (`[agents] timing`).
    pub timing: Option<String>,
    /// External agents: the service-name prefix (`[agents] prefix`).
    pub prefix: Option<String>,
    /// External agents: how long to wait for them to attach \[s, wall time\]
    /// (`[agents] attach_timeout`).
    pub wait_agents: Option<f64>,
}

/// Which of a run's options ([`Changes`]' fields), for messages in the caller's own words
/// (a flag of `shoal run`, a keyword of Python's `shoal.run`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunOption {
    /// [`Changes::seed`].
    Seed,
    /// [`Changes::duration`].
    Duration,
    /// [`Changes::plots`].
    Plots,
    /// [`Changes::replay`].
    Replay,
    /// [`Changes::mcap`].
    Mcap,
    /// [`Changes::timing`].
    Timing,
    /// [`Changes::prefix`].
    Prefix,
    /// [`Changes::wait_agents`].
    WaitAgents,
}

impl RunOption {
    /// Its [`Changes`] field name (Python's keyword).
    pub fn name(self) -> &'static str {
        match self {
            RunOption::Seed => "seed",
            RunOption::Duration => "duration",
            RunOption::Plots => "plots",
            RunOption::Replay => "replay",
            RunOption::Mcap => "mcap",
            RunOption::Timing => "timing",
            RunOption::Prefix => "prefix",
            RunOption::WaitAgents => "wait_agents",
        }
    }
}

/// One change: which option, the world-file path it sets, the value.
struct Change {
    option: RunOption,
    path: &'static str,
    value: toml::Value,
}

impl Changes {
    /// Whether nothing is changed.
    pub fn is_empty(&self) -> bool {
        self.changes().is_empty()
    }

    fn changes(&self) -> Vec<Change> {
        let mut out = Vec::new();
        let mut push = |option, path, value: Option<toml::Value>| {
            if let Some(value) = value {
                out.push(Change {
                    option,
                    path,
                    value,
                });
            }
        };
        // (A seed above i64::MAX is refused by `load_world`: TOML cannot hold it.)
        push(
            RunOption::Seed,
            "seed",
            self.seed
                .and_then(|s| i64::try_from(s).ok())
                .map(toml::Value::Integer),
        );
        push(
            RunOption::Duration,
            "duration",
            self.duration.map(toml::Value::Float),
        );
        push(
            RunOption::Plots,
            "output.plots",
            self.plots.map(toml::Value::Boolean),
        );
        push(
            RunOption::Replay,
            "output.replay",
            self.replay.map(toml::Value::Boolean),
        );
        push(
            RunOption::Mcap,
            "output.mcap",
            self.mcap.map(toml::Value::Boolean),
        );
        push(
            RunOption::Timing,
            "agents.timing",
            self.timing.clone().map(toml::Value::String),
        );
        push(
            RunOption::Prefix,
            "agents.prefix",
            self.prefix.clone().map(toml::Value::String),
        );
        push(
            RunOption::WaitAgents,
            "agents.attach_timeout",
            self.wait_agents.map(toml::Value::Float),
        );
        out
    }
}

/// Why [`load_world`] could not make a world.
#[derive(Debug, thiserror::Error)]
pub enum LoadWorldError {
    /// The world file itself: every problem with its line, field and allowed range.
    #[error(transparent)]
    World(#[from] WorldError),
    /// An option's value is not one the world file may hold.
    #[error("{}: {message}", option.name())]
    Option {
        /// The option.
        option: RunOption,
        /// What the loader said of the field it sets, with the allowed range.
        message: String,
    },
    /// The options together make a world that cannot be (no single option causes it).
    #[error("with these options: {0}")]
    Combined(String),
    /// A stop was asked for before the world was complete.
    #[error("interrupted while loading the world")]
    Interrupted(#[from] Interrupted),
}

/// Where a run's world comes from.
#[derive(Clone, Copy, Debug)]
pub enum WorldSource<'a> {
    /// The embedded default world of `shoal run`.
    Embedded,
    /// A world file.
    File(&'a Path),
    /// The TOML text of a world, named `name` in messages (its relative paths are relative to
    /// the working folder).
    Text {
        /// The text.
        text: &'a str,
        /// Its name in messages.
        name: &'a str,
    },
}

impl<'a> From<Option<&'a Path>> for WorldSource<'a> {
    /// A file, or the embedded default world.
    fn from(p: Option<&'a Path>) -> Self {
        p.map_or(WorldSource::Embedded, WorldSource::File)
    }
}

/// The world of `source` with `changes` applied, loaded until `cancel` asks for a stop.
pub fn load_world<'a>(
    source: impl Into<WorldSource<'a>>,
    changes: &Changes,
    cancel: &Cancel,
) -> Result<WorldDesc, LoadWorldError> {
    if let Some(s) = changes.seed
        && i64::try_from(s).is_err()
    {
        return Err(LoadWorldError::Option {
            option: RunOption::Seed,
            message: format!(
                "seed = {s}: allowed 0 … {} (a world file's integers)",
                i64::MAX
            ),
        });
    }
    let (text, file) = match source.into() {
        WorldSource::File(p) => (read_text(p)?, p),
        WorldSource::Embedded => (DEFAULT_WORLD.to_string(), Path::new(EMBEDDED_NAME)),
        WorldSource::Text { text, name } => (text.to_string(), Path::new(name)),
    };
    let mut rest = changes.clone();
    let duration = rest.duration.take();
    let mut desc = load_changed(&text, file, &rest, cancel)?;
    if let Some(d) = duration {
        desc.duration = run_length(d, desc.dt)?;
    }
    Ok(desc)
}

/// `d` \[s\] if it is a run length the world file's range allows at steps of `dt` \[s\].
fn run_length(d: f64, dt: f64) -> Result<f64, LoadWorldError> {
    let option = RunOption::Duration;
    let Some(range) = ranges::lookup("duration") else {
        return Ok(d);
    };
    if !range.admits(d, None, None) {
        let message = format!(
            "{} is out of range; allowed: {} {} — {}",
            ranges::fmt_num(d),
            range.allowed("duration", None, None),
            range.unit,
            range.why
        );
        return Err(LoadWorldError::Option { option, message });
    }
    match too_many_steps(d, dt) {
        Some(message) => Err(LoadWorldError::Option { option, message }),
        None => Ok(d),
    }
}

/// The world of the text `text` (named `file`) with `changes` as overrides of its fields.
fn load_changed(
    text: &str,
    file: &Path,
    changes: &Changes,
    cancel: &Cancel,
) -> Result<WorldDesc, LoadWorldError> {
    let changes = changes.changes();
    let overrides: Vec<Override> = changes
        .iter()
        .map(|c| Override {
            path: c.path.to_string(),
            value: c.value.clone(),
        })
        .collect();
    load_until(text, file, &overrides, cancel).map_err(|e| match e {
        ChangedError::World(e) => e.into(),
        ChangedError::Interrupted(i) => i.into(),
        ChangedError::Overrides(OverrideError::Problems { paths, world }) => {
            if let Some(p) = paths.first() {
                return LoadWorldError::Option {
                    option: changes[p.index].option,
                    message: p.message.clone(),
                };
            }
            match world.iter().find_map(|l| Some((l.by?, l))) {
                Some((i, l)) => LoadWorldError::Option {
                    option: changes[i].option,
                    message: l.problem.message.clone(),
                },
                None => LoadWorldError::Combined(
                    world
                        .iter()
                        .map(|l| l.problem.message.clone())
                        .collect::<Vec<_>>()
                        .join("; "),
                ),
            }
        }
        ChangedError::Overrides(e) => LoadWorldError::Combined(e.to_string()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(changes: &Changes) -> Result<WorldDesc, LoadWorldError> {
        load_world(WorldSource::Embedded, changes, &Cancel::new())
    }

    /// The default world's missions have steps at 70 s: a 5-s run is their beginning, not an
    /// error (a world file may not name a step after its own end; a run may stop early).
    #[test]
    fn a_run_may_stop_before_its_missions_end() {
        let full = load(&Changes::default()).unwrap();
        assert_eq!(full.duration, 100.0);
        let short = load(&Changes {
            duration: Some(5.0),
            ..Changes::default()
        })
        .unwrap();
        assert_eq!(short.duration, 5.0);
        assert_eq!(short.steps(), 500);
    }

    /// The duration's range is the world file's: 0, NaN and more than 1e7 s are refused with
    /// it, and so are more than 1e10 steps.
    #[test]
    fn the_duration_is_checked_with_the_files_range() {
        for d in [0.0, 1e-4, f64::NAN, 2e7] {
            let e = load(&Changes {
                duration: Some(d),
                ..Changes::default()
            })
            .unwrap_err();
            let LoadWorldError::Option { option, message } = e else {
                panic!("{d}: {e}");
            };
            assert_eq!(option, RunOption::Duration);
            assert!(
                message.contains("allowed: 0.001 ≤ duration ≤ 1e7 s"),
                "{d}: {message}"
            );
        }
        let world = "name = \"fine\"\nduration = 1.0\ndt = 1e-6\n[pool]\nsize = [2.0, 2.0, 1.0]\n";
        let e = load_world(
            WorldSource::Text {
                text: world,
                name: "w.toml",
            },
            &Changes {
                duration: Some(1e5),
                ..Changes::default()
            },
            &Cancel::new(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("more than 1e10"), "{e}");
    }
}
