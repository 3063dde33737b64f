//! Why a GIF could not be rendered ([`RenderError`]); every message names the file.

use shoal_output::files::FileError;
use std::path::PathBuf;

/// Why a GIF could not be rendered; every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The replay holds nothing to draw.
    #[error(
        "cannot render {}: the replay is empty ({frames} frames, {vehicles} vehicles)",
        path.display()
    )]
    Empty {
        /// The GIF asked for.
        path: PathBuf,
        /// Frames in the replay.
        frames: usize,
        /// Vehicles in the replay.
        vehicles: usize,
    },
    /// The replay's arrays or header do not fit together.
    #[error("cannot render {}: inconsistent replay: {message}", path.display())]
    Data {
        /// The GIF asked for.
        path: PathBuf,
        /// What does not fit.
        message: String,
    },
    /// An option is out of its range.
    #[error("cannot render {}: {message}", path.display())]
    Options {
        /// The GIF asked for.
        path: PathBuf,
        /// Which option, its value and the allowed range.
        message: String,
    },
    /// Drawing or encoding failed.
    #[error("cannot draw {}: {message}", path.display())]
    Draw {
        /// The GIF being drawn.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
}
