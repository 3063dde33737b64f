//! Maps of a world: a plot of the pool seen from above, east to the right and north up, its
//! walls and obstacles under the data, zoomed to where the vehicles are, with one scale on
//! both axes (the region shown: [`map_view`]).

use shoal_output::plot::{Outline, Plot, Series, map_view};

/// A map of `geometry` seen from above (east to the right, north up, one scale on both axes):
/// the pool's walls and its obstacles (filled) as outlines under `series`, zoomed to `focus`
/// ((east, north) points \[m\], [`map_view`]), `height` px high.
pub fn map_plot(
    title: String,
    geometry: &shoal_world::geometry::Geometry,
    series: Vec<Series>,
    focus: impl IntoIterator<Item = (f64, f64)>,
    height: u32,
) -> Plot {
    let pool = geometry.pool;
    let mut outlines = vec![Outline {
        points: vec![(0.0, 0.0), (pool.y, 0.0), (pool.y, pool.x), (0.0, pool.x)],
        filled: false,
    }];
    outlines.extend(geometry.obstacles.iter().map(|ob| {
        Outline {
            points: ob
                .top_outline(48)
                .into_iter()
                .map(|(x, y)| (y, x))
                .collect(),
            filled: true,
        }
    }));
    let (east, north, size) = map_view((pool.x, pool.y), focus, height);
    Plot {
        title,
        x_label: "east y [m]".into(),
        y_label: "north x [m]".into(),
        series,
        outlines,
        x_range: Some(east),
        y_range: Some(north),
        size,
        equal_aspect: true,
        ..Default::default()
    }
}
