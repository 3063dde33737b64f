//! Measured runs as real loggers write them: every accepted form (separators, trailing
//! separators, comments anywhere, CRLF, time in milliseconds) and every error, each with its
//! exact line and column.

use shoal_sysid::log::format::{ReadOptions, Separator, TimeUnit};
use shoal_sysid::log::run::{MeasuredRun, RunError};
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
