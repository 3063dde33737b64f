//! Simple, dependable plots (PNG and SVG from one description) with plotters and an embedded
//! DejaVu Sans font, so plots render on machines without system fonts.
//!
//! Three rules keep a plot honest whatever the data:
//! * the axes cover every point that is drawn ([`data_range`]: all finite points of all series
//!   and outlines, with a margin), and where a range is fixed, lines are clipped at the plot
//!   area's edge ([`clip_polyline`]) — plotters itself would squash them onto the edge or draw
//!   them over the axes;
//! * a nearly constant, quantised signal does not fill the plot with its quantisation steps:
//!   [`Plot::min_y_span`] sets the smallest vertical span of an autoscaled axis;
//! * the legend never covers data: it goes into a corner that nothing drawn passes through,
//!   or below the plot when there is none ([`legend_place`]).
//!
//! Dots and markers are drawn after every line, so an interval bar or a reference curve never
//! hides a point; a map ([`Plot::equal_aspect`]) has one scale on both axes.
//!
//! One file per concept: the description ([`Plot`], [`Series`], [`Outline`]), the look shared
//! by every plot (`style`: font and [`PALETTE`]), axis ranges and clipping (`range`), the
//! layout decided before drawing (`layout`: ranges as drawn, the chart, the legend's place),
//! the legend's place and size (`legend`) and its drawing (`legend_draw`), drawing and writing
//! the files (`render`), and the region a map shows (`map`).

mod description;
mod layout;
mod legend;
mod legend_draw;
mod map;
mod range;
mod render;
mod style;

pub use description::{Outline, Plot, Series};
pub use layout::RangesDrawn;
pub use legend::{LegendPlace, legend_place, touches};
pub use map::map_view;
pub use range::{clip_polyline, data_range};
pub use render::PlotError;
pub use style::{PALETTE, color, register_font, rgb};
