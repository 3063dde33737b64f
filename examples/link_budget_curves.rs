//! Draws the delivery probability of a 32-byte frame against distance for the default μAUV²
//! modem, on axis, in every named water type (and in pool water near the surface in
//! daylight): the figure of the README's link-model section.
//!
//! ```text
//! cargo run --release --example link_budget_curves -- [OUT_STEM]   # default: docs/img/link_budget
//! ```

use shoal::model::optics::{Ambient, LinkGeometry, budget};
use shoal::model::presets::uauv2_modem;
use shoal::output::plot::{Plot, Series};
use shoal::world::spec::WATER_TYPES;

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/img/link_budget".into());
    let m = uauv2_modem();
    let indoor = Ambient {
        surface_irradiance: 0.5,
        diffuse_attenuation: 0.1,
    };
    let daylight = Ambient {
        surface_irradiance: 50.0,
        diffuse_attenuation: 0.1,
    };
    let curve = |c: f64, ambient: &Ambient, depth: f64| -> Vec<(f64, f64)> {
        (1..=400)
            .map(|k| {
                let d = k as f64 * 0.01;
                (
                    d,
                    1.0 - budget(
                        &m.led,
                        &m.rx,
                        &LinkGeometry::on_axis(d),
                        c,
                        ambient,
                        depth,
                        0.0,
                        320,
                    )
                    .fer,
                )
            })
            .collect()
    };
    let mut series: Vec<Series> = WATER_TYPES
        .iter()
        .enumerate()
        .map(|(i, (name, c))| Series {
            label: Some(format!("{name} (c = {c} 1/m)")),
            points: curve(*c, &indoor, 1.0),
            color: i,
            ..Default::default()
        })
        .collect();
    series.push(Series {
        label: Some("pool, 0.3 m deep in daylight (50 W/m²)".into()),
        points: curve(0.07, &daylight, 0.3),
        color: 7,
        dashed: true,
        ..Default::default()
    });
    let files = Plot {
        title: "μAUV² modem: 32-byte frame delivered, on axis".into(),
        x_label: "distance [m]".into(),
        y_label: "probability of delivery".into(),
        series,
        x_range: Some((0.0, 4.0)),
        y_range: Some((0.0, 1.05)),
        ..Default::default()
    }
    .write(std::path::Path::new(&out))
    .expect("write the figure");
    for f in files {
        println!("wrote {}", f.display());
    }
}
