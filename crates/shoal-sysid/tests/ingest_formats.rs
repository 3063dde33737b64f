//! Measured runs as real loggers write them: every accepted form (separators, trailing
//! separators, comments anywhere, CRLF, time in milliseconds) and every error, each with its
//! exact line and column; the controller's references (`r.` columns) held like inputs, with
//! modes by name or code.

use shoal_sysid::log::format::{ReadOptions, Separator, TimeUnit};
use shoal_sysid::log::run::{MeasuredRun, ReferenceKind, RunError};
use std::path::Path;

fn parse(s: &str) -> Result<MeasuredRun, RunError> {
    MeasuredRun::parse(s, Path::new("run.csv"))
}

fn parse_ms(s: &str) -> Result<MeasuredRun, RunError> {
    MeasuredRun::parse_with(
        s,
        Path::new("run.csv"),
        &ReadOptions {
            time_unit: Some(TimeUnit::Milliseconds),
        },
    )
}

fn at(e: &RunError) -> (usize, Option<usize>) {
    (e.line, e.column.as_ref().map(|c| c.0))
}

#[test]
fn separators_are_found_in_the_header() {
    for (sep, text) in [
        (Separator::Comma, "t,u.port,y.depth\n0,10,1\n0.1,,1.1\n"),
        (Separator::Semicolon, "t;u.port;y.depth\n0;10;1\n0.1;;1.1\n"),
        (Separator::Tab, "t\tu.port\ty.depth\n0\t10\t1\n0.1\t\t1.1\n"),
        (
            Separator::Semicolon,
            "t ; u.port ; y.depth\n0 ; 10 ; 1\n0.1;;1.1\n",
        ),
    ] {
        let r = parse(text).unwrap();
        assert_eq!(r.ingest.separator, sep, "{text:?}");
        assert_eq!(r.t, vec![0.0, 0.1]);
        assert_eq!(r.inputs[0].values, vec![10.0, 10.0]);
        assert_eq!(r.channels[0].values, vec![1.0, 1.1]);
    }
    let e = parse("t;u.port,y.depth\n0;1,2\n").unwrap_err();
    assert_eq!(at(&e), (1, None));
    assert!(
        e.message.contains("mixes the separators `,` and `;`"),
        "{e}"
    );
    let e = parse("# c\nt u.port y.depth\n0 1 2\n").unwrap_err();
    assert_eq!(at(&e), (2, None));
    assert!(e.message.contains("no column separator"), "{e}");
    // A semicolon file with decimal commas says why the cell is not read.
    let e = parse("t;u.port;y.depth\n0;1;2\n0,1;1;2\n").unwrap_err();
    assert_eq!(at(&e), (3, Some(1)));
    assert!(e.message.contains("decimal commas"), "{e}");
}

#[test]
fn trailing_separators_are_accepted() {
    for text in [
        "t,u.port,y.depth,\n0,10,1,\n0.1,,1.1,\n",
        "t,u.port,y.depth\n0,10,1,\n0.1,,1.1\n",
        "t,u.port,y.depth,\n0,10,1\n0.1,,1.1\n",
        "t;u.port;y.depth;\n0;10;1;\n0.1;;1.1;\n",
        "t\tu.port\ty.depth\t\n0\t10\t1\t\n0.1\t\t1.1\t\n",
    ] {
        let r = parse(text).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert!(r.ingest.trailing_separator, "{text:?}");
        assert_eq!(r.t.len(), 2);
        assert_eq!(r.channels[0].values, vec![1.0, 1.1], "{text:?}");
    }
    // Two extra fields are one too many; a non-empty extra field has no column.
    let e = parse("t,u.port,y.depth\n0,10,1,,\n").unwrap_err();
    assert_eq!(at(&e), (2, None));
    assert!(e.message.contains("5 fields, but the header has 3"), "{e}");
    let e = parse("t,u.port,y.depth\n0,10,1\n0.1,10,1,7\n").unwrap_err();
    assert_eq!(at(&e), (3, None));
    assert!(e.message.contains("field 4 (`7`) has no column"), "{e}");
}

#[test]
fn comments_anywhere_keep_line_numbers() {
    let text = "  # logger v2\n# another\n\nt,u.port,y.depth\n   # indented\n0,10,1\n\t# tab\n\
                \n0.1,,1.1\n    #\n0.2,abc,1.2\n";
    let e = parse(text).unwrap_err();
    assert_eq!(at(&e), (11, Some(2)), "{e}");
    let ok = text.replace("abc", "20");
    let r = parse(&ok).unwrap();
    assert_eq!(r.header_line, 4);
    assert_eq!(r.lines, vec![6, 9, 11]);
    assert_eq!(r.ingest.comment_lines, 5);
    assert_eq!(r.ingest.blank_lines, 2);
    // A `#` after data is not a comment.
    let e = parse("t,u.port,y.depth\n0,10,1 # note\n").unwrap_err();
    assert_eq!(at(&e), (2, Some(3)));
    assert!(e.message.contains("own line"), "{e}");
}

#[test]
fn crlf_and_cr_line_ends() {
    for text in [
        "# c\r\nt,u.port,y.depth\r\n0,10,1\r\n  # c\r\n0.1,,1.1\r\n0.2,x,1\r\n",
        "# c\rt,u.port,y.depth\r0,10,1\r  # c\r0.1,,1.1\r0.2,x,1\r",
        "\u{feff}# c\nt,u.port,y.depth\n0,10,1\n  # c\n0.1,,1.1\n0.2,x,1",
    ] {
        let e = parse(text).unwrap_err();
        assert_eq!(at(&e), (6, Some(2)), "{text:?}: {e}");
        let r = parse(&text.replace(",x,", ",20,")).unwrap();
        assert_eq!(r.lines, vec![3, 5, 6], "{text:?}");
        assert_eq!(r.inputs[0].values, vec![10.0, 10.0, 20.0]);
    }
}

#[test]
fn time_in_milliseconds() {
    for (text, ms_flag) in [
        ("t_ms,u.port,y.depth\n0,10,1\n20,,1.1\n", false),
        ("t[ms],u.port,y.depth\n0,10,1\n20,,1.1\n", false),
        ("t,u.port,y.depth\n0,10,1\n20,,1.1\n", true),
        ("t_ms,u.port,y.depth\n0,10,1\n20,,1.1\n", true),
    ] {
        let r = if ms_flag { parse_ms(text) } else { parse(text) }.unwrap();
        assert_eq!(r.t, vec![0.0, 0.02], "{text}");
        assert_eq!(r.ingest.time_unit, TimeUnit::Milliseconds);
    }
    for text in [
        "t_s,u.port,y.depth\n0,10,1\n0.02,,1.1\n",
        "t[s],u.port,y.depth\n0,10,1\n0.02,,1.1\n",
    ] {
        let r = parse(text).unwrap();
        assert_eq!(r.t, vec![0.0, 0.02]);
        assert_eq!(r.ingest.time_unit, TimeUnit::Seconds);
    }
    // A header that declares seconds contradicts a millisecond option.
    let e = parse_ms("x.a,t_s,u.port,y.depth\n,0,10,1\n,0.02,,1.1\n").unwrap_err();
    assert_eq!(at(&e), (1, Some(2)));
    assert!(e.message.contains("declares the time in s"), "{e}");
    let e = parse("t,t_ms,y.depth\n0,0,1\n").unwrap_err();
    assert_eq!(at(&e), (1, Some(2)));
    assert!(e.message.contains("second time column"), "{e}");
    let e = parse_ms("t,u.port,y.depth\n0,1,2\n20,1,2\n20,1,2\n").unwrap_err();
    assert_eq!(at(&e), (4, Some(1)));
    assert!(
        e.message
            .contains("time 20 ms does not increase (line 3: 20 ms)"),
        "{e}"
    );
}

#[test]
fn every_error_is_located() {
    type Case<'a> = (&'a str, (usize, Option<usize>), &'a str);
    let cases: &[Case] = &[
        ("", (0, None), "no header row"),
        ("# only\n\n  # comments\n", (0, None), "no header row"),
        ("t,u.port,y.depth\n", (1, None), "followed by no data row"),
        (
            "# c\nt,u.port,y.depth\n0,1,2\n",
            (2, None),
            "only 1 data row",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n0.1,1\n",
            (3, Some(3)),
            "2 field(s)",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n0.1,1,2,3,4\n",
            (3, None),
            "5 fields",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n0.1,1,inf\n",
            (3, Some(3)),
            "not a finite number",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n0.1,1,NaN\n",
            (3, Some(3)),
            "not a finite number",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n0.1,1,1e400\n",
            (3, Some(3)),
            "not a finite number",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n,1,2\n",
            (3, Some(1)),
            "time is missing",
        ),
        (
            "t,u.port,y.depth\n5,1,2\n5,1,2\n",
            (3, Some(1)),
            "does not increase",
        ),
        (
            "t,u.port,y.depth\n0,1,2\n-1,1,2\n",
            (3, Some(1)),
            "does not increase",
        ),
        (
            "t,u.port,u.port,y.depth\n0,1,1,2\n",
            (1, Some(3)),
            "appears twice",
        ),
        ("t,u.,y.depth\n0,1,2\n", (1, Some(2)), "actuator name"),
        ("u.port,y.depth\n0,1\n", (1, None), "no time column"),
        ("t,u.port\n0,1\n0.1,1\n", (1, None), "no measurement column"),
        ("t,,y.depth\n0,1,2\n", (1, Some(2)), "unknown column ``"),
        (
            "t,u.port,y.depth\n0,,2\n0.1,,3\n",
            (1, Some(2)),
            "never set",
        ),
        (
            "t,u.port,y.depth\n0,1,\n0.1,1,\n",
            (1, Some(3)),
            "no samples",
        ),
    ];
    for (text, want, msg) in cases {
        let e = parse(text).unwrap_err();
        assert_eq!(at(&e), *want, "{text:?}: {e}");
        assert!(e.message.contains(msg), "{text:?}: {e}");
    }
    // Invalid UTF-8 names its line and column.
    let bytes = b"t,u.port,y.depth,x.note\n0,1,2,a\n0.1,1,2,\xff\xfe\n";
    let e = MeasuredRun::from_reader(&bytes[..], Path::new("r.csv"), &ReadOptions::default())
        .unwrap_err();
    assert_eq!(at(&e), (3, Some(4)));
    assert!(e.message.contains("UTF-8"), "{e}");
    let bytes = b"t,u.port,y.d\xffepth\n0,1,2\n";
    let e = MeasuredRun::from_reader(&bytes[..], Path::new("r.csv"), &ReadOptions::default())
        .unwrap_err();
    assert_eq!(at(&e), (1, None));
    assert!(e.message.contains("UTF-8"), "{e}");
}

#[test]
#[expect(
    clippy::approx_constant,
    reason = "-1.5708 is what a logger writes for -π/2"
)]
fn input_precision_is_recorded_per_value_and_held() {
    let r = parse("t,u.beta,u.port,y.depth\n0,,10,1\n0.1,-1.5708,,1\n0.2,-1.57,5.25,1\n0.3,,,1\n")
        .unwrap();
    let beta = &r.inputs[0];
    assert_eq!(beta.values, vec![-1.5708, -1.5708, -1.57, -1.57]);
    assert_eq!(beta.first_set, 1);
    let p: Vec<f64> = beta.precision.iter().map(|&p| f64::from(p)).collect();
    assert!(
        (p[0] - 5e-5).abs() < 1e-9 && (p[1] - 5e-5).abs() < 1e-9,
        "{p:?}"
    );
    assert!(
        (p[2] - 5e-3).abs() < 1e-8 && (p[3] - 5e-3).abs() < 1e-8,
        "{p:?}"
    );
    assert_eq!(r.inputs[1].first_set, 0);
    assert_eq!(r.inputs[1].precision[2], 0.005);
}

/// A log with references, mode by name (any case) and by code, empty cells held: row by row
/// (a comment line, the header on line 2, rows on lines 3 … 8).
const REFERENCES: &str = "# mission 4\n\
    t,u.port,y.depth,r.depth,r.yaw,r.mode\n\
    0,10,0.5,,0.25,\n\
    0.1,,0.51,1.5,,Diving\n\
    0.2,,0.52,,,\n\
    0.3,,0.53,2,,5\n\
    0.4,,0.54,,-1.5,TURNING\n\
    0.5,,0.55,,,0\n";

#[test]
fn references_are_held_like_inputs_and_modes_read_by_name_or_code() {
    let r = parse(REFERENCES).unwrap_or_else(|e| panic!("{e}"));
    // Each column by hand: the value in force at each row; before the first set cell that
    // cell's value. Modes as their codes: diving 1, auto 5, turning 3, off 0.
    let want: [(ReferenceKind, usize, [f64; 6], usize); 3] = [
        (ReferenceKind::Depth, 4, [1.5, 1.5, 1.5, 2.0, 2.0, 2.0], 1),
        (
            ReferenceKind::Yaw,
            5,
            [0.25, 0.25, 0.25, 0.25, -1.5, -1.5],
            0,
        ),
        (ReferenceKind::Mode, 6, [1.0, 1.0, 1.0, 5.0, 3.0, 0.0], 1),
    ];
    assert_eq!(r.references.len(), 3);
    for (kind, column, values, first_set) in want {
        let col = r.reference(kind).unwrap();
        assert_eq!(col.name, kind.name());
        assert_eq!(col.column, column, "{kind:?}");
        assert_eq!(col.values, values, "{kind:?}");
        assert_eq!(col.first_set, first_set, "{kind:?}");
    }
    // Written precision held with the value; a mode is exact.
    let depth = r.reference(ReferenceKind::Depth).unwrap();
    assert_eq!(depth.precision[0], 0.05);
    assert_eq!(depth.precision[5], 0.5);
    assert!(
        r.reference(ReferenceKind::Mode)
            .unwrap()
            .precision
            .iter()
            .all(|&p| p == 0.0)
    );
    // The inputs and channels are not disturbed.
    assert_eq!(r.inputs[0].values, vec![10.0; 6]);
    assert_eq!(r.channels[0].values.len(), 6);
    assert!(r.reference(ReferenceKind::Surge).is_none());
    // Every mode name in any case, and every code, is read as the code.
    for (cell, code) in [
        ("off", 0.0),
        ("BUOYANCY", 2.0),
        ("Drift", 4.0),
        ("raw", 6.0),
        ("6", 6.0),
        ("3.0", 3.0),
    ] {
        let text = format!("t,y.depth,r.mode\n0,1,{cell}\n0.1,1,\n");
        let r = parse(&text).unwrap_or_else(|e| panic!("{cell}: {e}"));
        assert_eq!(r.references[0].values, vec![code, code], "{cell}");
    }
}

#[test]
fn an_unknown_or_repeated_reference_names_its_column_with_a_did_you_mean() {
    let e = parse("# c\nt,u.port,y.depth,r.dpth\n0,1,2,3\n0.1,1,2,3\n").unwrap_err();
    assert_eq!((e.line, e.column.clone()), (2, Some((4, "r.dpth".into()))));
    assert!(
        e.message
            .starts_with("unknown reference `r.dpth` — did you mean `r.depth`?"),
        "{e}"
    );
    assert!(
        e.message
            .contains("(allowed: r.depth, r.yaw, r.surge, r.sway, r.mode)"),
        "{e}"
    );
    // Nothing near: the list only.
    let e = parse("t,y.depth,r.speed\n0,1,2\n").unwrap_err();
    assert_eq!(at(&e), (1, Some(3)));
    assert!(!e.message.contains("did you mean"), "{e}");
    assert!(e.message.contains("allowed: r.depth"), "{e}");
    let e = parse("t,y.depth,r.mode,r.yaw,r.mode\n0,1,2,0,2\n").unwrap_err();
    assert_eq!(at(&e), (1, Some(5)));
    assert!(e.message.contains("appears twice"), "{e}");
    // The unknown-column message names the `r.` columns among the allowed ones.
    let e = parse("t,y.depth,ref_depth\n0,1,2\n").unwrap_err();
    assert!(e.message.contains("`r.<reference>`"), "{e}");
}

#[test]
fn a_bad_reference_cell_names_line_column_and_the_allowed_values() {
    let e = parse("t,y.depth,r.depth,r.mode\n0,1,1,auto\n0.1,1,,\n0.2,1,,swim\n").unwrap_err();
    assert_eq!((e.line, e.column.clone()), (4, Some((4, "r.mode".into()))));
    assert!(
        e.to_string()
            .starts_with("run.csv:4: column 4 `r.mode`: `swim` is not a mode"),
        "{e}"
    );
    assert!(
        e.message.contains(
            "off (0), diving (1), buoyancy (2), turning (3), drift (4), auto (5), raw (6)"
        ),
        "{e}"
    );
    // Codes past the table and fractions are not modes either.
    for cell in ["7", "-1", "2.5", "nan"] {
        let e = parse(&format!("t,y.depth,r.mode\n0,1,{cell}\n0.1,1,\n")).unwrap_err();
        assert_eq!(at(&e), (2, Some(3)), "{cell}: {e}");
        assert!(e.message.contains("is not a mode"), "{cell}: {e}");
    }
    // A non-finite reference: the allowed range with its unit.
    let e = parse("t,y.depth,r.depth\n0,1,1\n0.1,1,inf\n").unwrap_err();
    assert_eq!(at(&e), (3, Some(3)));
    assert!(
        e.message.contains(
            "`inf` is not a finite number (allowed for `r.depth`: a finite depth [m, positive down])"
        ),
        "{e}"
    );
    let e = parse("t,y.depth,r.yaw\n0,1,north\n").unwrap_err();
    assert!(e.message.contains("`north` is not a number"), "{e}");
    let e = parse("t,y.depth,r.surge\n0,1,\n0.1,1,\n").unwrap_err();
    assert_eq!(at(&e), (1, Some(3)));
    assert!(e.message.contains("this reference is never set"), "{e}");
}

#[test]
fn references_round_trip_through_to_csv() {
    let r = parse(REFERENCES).unwrap();
    let text = r.to_csv();
    assert!(
        text.starts_with("t,u.port,y.depth,r.depth,r.yaw,r.mode\n"),
        "{text}"
    );
    let again = parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(again.t, r.t);
    assert_eq!(again.inputs, r.inputs);
    assert_eq!(again.channels, r.channels);
    // Values, precision, columns and the row each is first set at.
    assert_eq!(again.references, r.references);
}
