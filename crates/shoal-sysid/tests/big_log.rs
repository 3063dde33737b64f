//! A 10⁶-row log with one broken cell near its end, read from a file: the error names exactly
//! that line and column (line numbers are counted incrementally, comment lines included).

use shoal_sysid::log::run::MeasuredRun;
use std::io::{BufWriter, Write};

#[test]
fn a_million_rows_with_one_broken_cell_near_the_end() {
    const ROWS: usize = 1_000_000;
    const BROKEN: usize = ROWS - 37;
    let dir = std::env::temp_dir().join(format!("shoal-sysid-big-log-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.csv");
    let mut w = BufWriter::new(std::fs::File::create(&path).unwrap());
    writeln!(w, "# a long diving log\r").unwrap();
    writeln!(
        w,
        "t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth,y.yaw\r"
    )
    .unwrap();
    let mut line = 2;
    let mut broken_line = 0;
    for i in 0..ROWS {
        if i % 100_000 == 50 {
            writeln!(w, "   # checkpoint {i}").unwrap();
            line += 1;
        }
        line += 1;
        let beta = if i == BROKEN {
            broken_line = line;
            "-1.57O8"
        } else {
            "-1.5708"
        };
        let cmd = (i / 150) % 200;
        let yaw = if i % 5 == 0 { "0.301" } else { "" };
        writeln!(
            w,
            "{}.{:02},0,{cmd},{cmd},0,{beta},0,{:.4},{yaw}\r",
            i / 50,
            (i % 50) * 2,
            0.8 + (i % 1000) as f64 * 1e-4
        )
        .unwrap();
    }
    drop(w);
    let e = MeasuredRun::read(&path).unwrap_err();
    let _ = std::fs::remove_dir_all(&dir);
    // Two header lines, the rows before it and ten checkpoint comments.
    assert_eq!(broken_line, 2 + (BROKEN + 1) + 10);
    assert_eq!(
        (e.line, e.column.clone()),
        (broken_line, Some((6, "u.beta".to_string()))),
        "{e}"
    );
    assert!(e.message.contains("`-1.57O8` is not a number"), "{e}");
}
