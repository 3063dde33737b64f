//! `vehicles.csv`: one row per vehicle (its summary and, with optical traffic, its
//! communication counters), numbers written as [`super::numbers`] says.

use super::numbers::format_num;
use super::summary::VehicleSummary;
use crate::comm_report::VehicleComm;
use shoal_output::files::{CsvFile, FileError};
use std::path::{Path, PathBuf};

/// `vehicles.csv`: one row per vehicle with its [`VehicleSummary`] and, when the world has
/// optical traffic, its communication counters (units in the column names), so that
/// summary.json stays small whatever the vehicle count.
pub(super) fn write_vehicles_csv(
    path: &Path,
    rows: &[VehicleSummary],
    comm: Option<&[VehicleComm]>,
) -> Result<PathBuf, FileError> {
    const COMM: [&str; 8] = [
        "frames_sent",
        "queue_overflow",
        "rx_attempts",
        "rx_delivered",
        "rx_lost_range",
        "rx_lost_occlusion",
        "rx_lost_collision",
        "rx_lost_half_duplex",
    ];
    let mut w = CsvFile::create(path)?;
    let mut header: Vec<&str> = vec![
        "name",
        "group",
        "mode",
        "final_x_m",
        "final_y_m",
        "final_z_m",
        "final_yaw_deg",
        "final_depth_reading_m",
        "depth_error_m",
        "yaw_error_deg",
        "distance_m",
        "max_depth_m",
        "max_speed_m_s",
        "impacts",
        "steps_in_contact",
        "ballast_ml",
    ];
    if comm.is_some() {
        header.extend(COMM);
    }
    w.write_record(header)?;
    for (i, v) in rows.iter().enumerate() {
        let [x, y, z] = v.final_position_m;
        let mut row = vec![
            v.name.clone(),
            v.group.clone(),
            v.mode.clone(),
            format_num(x),
            format_num(y),
            format_num(z),
            format_num(v.final_yaw_deg),
            format_num(v.final_depth_reading_m),
            format_num(v.depth_error_m),
            format_num(v.yaw_error_deg),
            format_num(v.distance_m),
            format_num(v.max_depth_m),
            format_num(v.max_speed_m_s),
            v.impacts.to_string(),
            v.steps_in_contact.to_string(),
            format_num(v.ballast_ml),
        ];
        if let Some(c) = comm.and_then(|c| c.get(i)) {
            let r = &c.rx;
            row.extend(
                [
                    c.sent,
                    c.queue_overflow,
                    r.attempts,
                    r.delivered,
                    r.lost_range,
                    r.lost_occlusion,
                    r.lost_collision,
                    r.lost_half_duplex,
                ]
                .map(|x| x.to_string()),
            );
        }
        w.write_record(row)?;
    }
    w.commit()
}
