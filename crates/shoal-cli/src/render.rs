//! `shoal render`: an animated GIF of a finished run, drawn from its `replay.html` without a
//! browser (see `shoal_record::replay::gif`).

use crate::exit::Failure;
use shoal_record::replay::gif::{self, GifOptions, View};
use shoal_record::replay::html;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Swarms above this many vehicles get the top view only by default (the side view of a
/// large swarm is a crowd).
const BOTH_VIEWS_UP_TO: usize = 200;

/// Arguments of `shoal render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// A run's output folder (holding `replay.html`), or a replay page itself.
    pub run: PathBuf,
    /// The GIF to write [default: `replay.gif` beside the replay].
    #[arg(long, value_name = "FILE")]
    pub gif: Option<PathBuf>,
    /// Views: `top` (map from above), `side` (from the east, depth down) or `both`
    /// [default: both up to 200 vehicles, else top].
    #[arg(long, value_parser = ["top", "side", "both"])]
    pub view: Option<String>,
    /// Image width [px] (240 … 4096).
    #[arg(long, default_value_t = 800, value_name = "PX")]
    pub width: u32,
    /// GIF frames per second of playback (above 0, at most 50).
    #[arg(long, default_value_t = 10.0)]
    pub fps: f64,
    /// Playback speed [simulated seconds per second of GIF].
    #[arg(long, default_value_t = 4.0)]
    pub speed: f64,
    /// Trail behind each vehicle [simulated s] (0: none).
    #[arg(long, default_value_t = 5.0, value_name = "SECONDS")]
    pub trail: f64,
    /// Most GIF frames; beyond it the frames are spread over the run.
    #[arg(long, default_value_t = 600)]
    pub max_frames: usize,
    /// Do not draw the link attempts.
    #[arg(long)]
    pub no_links: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The replay page `run` names: the file itself, or `replay.html` in the folder.
fn replay_page(run: &Path) -> PathBuf {
    if run.is_dir() {
        run.join("replay.html")
    } else {
        run.to_path_buf()
    }
}

/// Draws the GIF; bad options and unreadable replays are input errors (exit 2) that name the
/// option or the file.
pub fn render(args: &RenderArgs) -> Result<ExitCode, Failure> {
    let page = replay_page(&args.run);
    if !page.exists() {
        return Err(Failure::Input(format!(
            "{} does not exist: `shoal render` reads the replay.html of a run (written by \
             `shoal run` unless --no-replay or `[output] replay = false`)",
            page.display()
        )));
    }
    let start = Instant::now();
    let data = html::read(&page).map_err(|e| Failure::Input(e.to_string()))?;
    let view = match args.view.as_deref() {
        Some("top") => View::Top,
        Some("side") => View::Side,
        Some(_) => View::Both,
        None if data.meta.vehicles > BOTH_VIEWS_UP_TO => View::Top,
        None => View::Both,
    };
    let out = args
        .gif
        .clone()
        .unwrap_or_else(|| page.with_extension("gif"));
    let opts = GifOptions {
        view,
        width_px: args.width,
        fps: args.fps,
        speed: args.speed,
        max_frames: args.max_frames,
        trail_s: args.trail,
        links: !args.no_links,
    };
    let written = gif::render(&data, &out, &opts).map_err(|e| match e {
        gif::RenderError::File(_) | gif::RenderError::Draw { .. } => Failure::Other(e.into()),
        _ => Failure::Input(e.to_string()),
    })?;
    if !args.quiet {
        let bytes = std::fs::metadata(&written).map(|m| m.len()).unwrap_or(0);
        println!(
            "wrote {} ({:.1} MB): `{}`, {} vehicles, {:.1} s at {}× in {:.1} s",
            written.display(),
            bytes as f64 / 1e6,
            data.meta.world,
            data.meta.vehicles,
            data.meta.duration_s,
            args.speed,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}
