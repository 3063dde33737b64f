//! What the caller chooses of a GIF ([`GifOptions`]: the views, [`View`], size, frame rate,
//! speed, trails, links) and the fixed limits and sizes of the drawing (the link window, the
//! smallest body, the end hold, the most frames and frames per second).

/// What a GIF frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// The map from above: east (y) to the right, north (x) up.
    Top,
    /// The side view from the east: north (x) to the right, depth (z) down.
    Side,
    /// The map from above with the side view below it.
    #[default]
    Both,
}

/// How to draw the GIF.
#[derive(Clone, Debug)]
pub struct GifOptions {
    /// Which views.
    pub view: View,
    /// Image width \[px\] (240 to 4096); the height follows from the views' aspect ratios.
    pub width_px: u32,
    /// GIF frame rate \[frames per second of playback\] (above 0, at most 50: browsers play
    /// faster GIFs at 10 fps).
    pub fps: f64,
    /// Playback speed \[simulated seconds per second of GIF\]: 4 turns a 100-s run into a
    /// 25-s GIF.
    pub speed: f64,
    /// Most GIF frames (1 to [`MAX_GIF_FRAMES`]); beyond it, frames are spread over the run
    /// and each is shown longer.
    pub max_frames: usize,
    /// Length of the trail behind each vehicle \[s of simulated time\] (0: none).
    pub trail_s: f64,
    /// Draw the link attempts of the last moments as lines.
    pub links: bool,
}

impl Default for GifOptions {
    fn default() -> Self {
        Self {
            view: View::Both,
            width_px: 800,
            fps: 10.0,
            speed: 4.0,
            max_frames: 600,
            trail_s: 5.0,
            links: true,
        }
    }
}

/// Link attempts of the last this many simulated seconds are drawn (or of the time between two
/// GIF frames, when longer, so that every attempt is seen once) \[s\].
pub const LINK_WINDOW_S: f64 = 0.3;
/// Smallest drawn length of a vehicle's body \[px\]: smaller hulls are drawn enlarged.
pub const MIN_BODY_PX: f64 = 9.0;
/// In a crowded map the least drawn length is this fraction of the side of each vehicle's
/// share of the panel (`√(panel area / vehicles)`), at least 2 px: 10,000 vehicles on a
/// 560-px map are drawn ≈ 3 px long instead of merging at [`MIN_BODY_PX`].
pub const CROWDED_BODY_SHARE: f64 = 0.6;
/// The last frame is held this much longer before the GIF loops \[s\].
pub const END_HOLD_S: f64 = 2.0;
/// Most GIF frame rate \[1/s\]: delays below 2/100 s are played as 1/10 s by browsers.
pub const MAX_GIF_FPS: f64 = 50.0;
/// Largest [`GifOptions::max_frames`].
pub const MAX_GIF_FRAMES: usize = 20_000;
