//! summary.json stays small for any vehicle count: per-vehicle results go to `vehicles.csv`
//! (one whole row per vehicle, with the communication counters when there is traffic). Before,
//! 10⁶ vehicles wrote a 0.5–0.8 GB summary.json.

mod common;

use std::process::Command;

#[test]
fn summary_stays_small_and_vehicles_csv_has_a_row_per_vehicle() {
    let dir = common::tmp("scale", "summary");
    let world = dir.join("w.toml");
    // 20 000 vehicles on a grid for half a second, beacons on a quarter of them.
    std::fs::write(
        &world,
        "duration = 0.5\n[pool]\nsize = [210.0, 210.0, 3.0]\n[output]\nplots = false\n\
         [[vehicles]]\nname = \"quiet\"\ncount = 15000\n\
         grid = { origin = [1.0, 1.0, 1.0], spacing = [1.4, 1.4], columns = 150 }\n\
         [[vehicles]]\nname = \"beacon\"\ncount = 5000\n\
         grid = { origin = [1.0, 142.0, 1.0], spacing = [1.4, 1.4], columns = 150 }\n\
         behaviour = { kind = \"beacon\", period = 0.02, payload_bytes = 8 }\n\
         [vehicles.model]\nmodems = [{ name = \"front\", position = [0.1, 0.0, 0.0], direction = [1.0, 0.0, 0.0] }]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_shoal"))
        .args(["run", "--quiet"])
        .arg(&world)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let size = std::fs::metadata(out.join("summary.json")).unwrap().len();
    assert!(
        size < 100_000,
        "summary.json is {size} bytes for 20 000 vehicles"
    );
    let s = common::summary(&out);
    assert_eq!(s["vehicles"], 20_000);
    assert!(s.get("vehicle_details").is_none());
    assert!(s["comm"].get("vehicles").is_none());
    assert!(
        s["comm"]["frames_sent"].as_u64().unwrap() > 0,
        "{}",
        s["comm"]
    );
    let csv = std::fs::read_to_string(out.join("vehicles.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "name");
    assert!(header.contains(&"frames_sent") && header.contains(&"rx_delivered"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 20_000);
    assert!(rows.iter().all(|r| r.len() == header.len()));
    assert!(csv.ends_with('\n'));
    // The per-vehicle counters add up to the summary's totals.
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let total = |name: &str| -> u64 {
        rows.iter()
            .map(|r| r[col(name)].parse::<u64>().unwrap())
            .sum()
    };
    assert_eq!(
        total("frames_sent"),
        s["comm"]["frames_sent"].as_u64().unwrap()
    );
    assert_eq!(
        total("rx_delivered"),
        s["comm"]["receptions"]["delivered"].as_u64().unwrap()
    );
    assert_eq!(rows[0][0], "quiet-0");
    assert_eq!(rows[15_000][0], "beacon-0");
    std::fs::remove_dir_all(&dir).ok();
}
