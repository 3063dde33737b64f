//! What a run's outputs gather of each vehicle while its trajectory rows stream past
//! ([`VehicleAcc`]: distance, greatest depth and speed, whether it was steered, and the samples
//! kept for the plots, [`PlotPoint`]): the summary and the plots are drawn from it.

use shoal_model::prelude::*;
use shoal_sim::recorder::{col, mode_of_code};

/// What the outputs keep of one vehicle from its trajectory rows.
#[derive(Clone, Debug, Default)]
pub(super) struct VehicleAcc {
    /// Rows seen.
    pub(super) rows: u64,
    /// Position of the last row \[m\].
    pub(super) last: Option<[f64; 3]>,
    /// Distance travelled \[m\].
    pub(super) distance: f64,
    /// Greatest depth of the body origin \[m\].
    pub(super) max_depth: f64,
    /// Greatest speed, |(u, v, w)| of the recorded body velocity \[m/s\].
    pub(super) max_speed: f64,
    /// Points for the plots (only for the vehicles drawn).
    pub(super) plot: Vec<PlotPoint>,
    /// Whether the vehicle was ever in a mode that controls its heading.
    pub(super) steered: bool,
}

/// One kept sample of a vehicle for the plots.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PlotPoint {
    /// Time \[s\].
    pub(super) t: f64,
    /// North \[m\].
    pub(super) x: f64,
    /// East \[m\].
    pub(super) y: f64,
    /// Depth reading \[m\].
    pub(super) depth: f64,
    /// Depth setpoint \[m\]; NaN where the vehicle's mode holds no depth ([`Mode::holds_depth`]: a
    /// vehicle off, turning, drifting or under raw commands records 0, which is no setpoint).
    pub(super) depth_sp: f64,
    /// Heading \[rad\].
    pub(super) yaw: f64,
    /// Heading setpoint \[rad\].
    pub(super) yaw_sp: f64,
}

impl VehicleAcc {
    /// Adds one trajectory row (the columns of [`shoal_sim::recorder::col`]), keeping it for the
    /// plots when `keep`.
    pub(super) fn add_row(&mut self, row: &[f64], keep: bool) {
        let a = self;
        let here = [row[col::X], row[col::Y], row[col::Z]];
        if let Some(last) = a.last {
            let d = ((here[0] - last[0]).powi(2)
                + (here[1] - last[1]).powi(2)
                + (here[2] - last[2]).powi(2))
            .sqrt();
            a.distance += d;
        }
        a.max_depth = a.max_depth.max(row[col::Z]);
        let speed = (row[col::U].powi(2) + row[col::U + 1].powi(2) + row[col::W].powi(2)).sqrt();
        a.max_speed = a.max_speed.max(speed);
        let mode = mode_of_code(row[col::MODE]);
        if keep {
            a.plot.push(PlotPoint {
                t: row[col::T],
                x: row[col::X],
                y: row[col::Y],
                depth: row[col::DEPTH_READING],
                depth_sp: if mode.holds_depth() {
                    row[col::DEPTH_SP]
                } else {
                    f64::NAN
                },
                yaw: row[col::YAW],
                yaw_sp: row[col::YAW_SP],
            });
        }
        a.steered |= matches!(mode, Mode::Turning | Mode::Drift | Mode::Auto);
        a.rows += 1;
        a.last = Some(here);
    }
}
