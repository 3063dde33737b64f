//! The validation's one log seam (`shoal_sysid::log::readers`): a file is read by the first
//! reader that recognises its content, whatever its name — a rosbag2 given without a mapping
//! is refused with what is missing (never read as a CSV whose header "is not valid UTF-8"),
//! a CSV is read as CSV, and a reader put first is asked first.

use shoal_sysid::log::format::ReadOptions;
use shoal_sysid::log::readers::{LogReader, MCAP_MAGIC, Readers, Sniff};
use shoal_sysid::log::run::{MeasuredRun, RunError};
use shoal_sysid::validate::{Config, Progress, RunInput, validate};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shoal-log-readers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn quiet(_: Progress<'_>) {}

const CSV: &str = "t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth\n\
                   0,0,0,0,0,0,0,0.5\n0.1,0,0,0,0,0,0,0.5\n0.2,0,0,0,0,0,0,0.5\n";

#[test]
fn an_mcap_without_a_mapping_is_refused_by_content_whatever_its_name() {
    // MCAP's magic, then bytes that are not UTF-8: the CSV reader would stop at its header.
    let mut bytes = MCAP_MAGIC.to_vec();
    bytes.extend_from_slice(&[0x01, 0xff, 0xfe, 0x00, 0x80]);
    for name in ["run.mcap", "run.csv", "run"] {
        let path = scratch(name);
        std::fs::write(&path, &bytes).unwrap();
        let e = match validate(
            &Config::default(),
            &[RunInput::File(path.clone())],
            &[],
            &quiet,
        ) {
            Ok(_) => panic!("{name}: an MCAP read without a mapping"),
            Err(e) => e.to_string(),
        };
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(e.contains("a rosbag2 (MCAP)"), "{e}");
        assert!(e.contains("--mapping MAPPING.toml"), "{e}");
        assert!(e.contains("mapping=\"MAPPING.toml\""), "{e}");
        assert!(!e.contains("UTF-8"), "{e}");
    }
}

#[test]
fn a_rosbag2_folder_without_a_mapping_is_refused_and_other_folders_say_what_they_are_not() {
    let bag = scratch("bag_dir");
    std::fs::create_dir_all(&bag).unwrap();
    std::fs::write(
        bag.join("metadata.yaml"),
        "rosbag2_bagfile_information: {}\n",
    )
    .unwrap();
    let e = Readers::default()
        .read(&bag, &ReadOptions::default())
        .unwrap_err();
    assert!(e.message.contains("needs a mapping file"), "{e}");
    let plain = scratch("plain_dir");
    std::fs::create_dir_all(&plain).unwrap();
    let e = Readers::default()
        .read(&plain, &ReadOptions::default())
        .unwrap_err();
    assert!(e.message.contains("not a rosbag2"), "{e}");
}

#[test]
fn a_csv_is_read_as_csv_whatever_its_name_but_a_bags() {
    let path = scratch("dive.log");
    std::fs::write(&path, CSV).unwrap();
    let run = Readers::default()
        .read(&path, &ReadOptions::default())
        .unwrap();
    assert_eq!(run.t, [0.0, 0.1, 0.2]);
    assert_eq!(run.channels[0].values, [0.5, 0.5, 0.5]);
    // Named as a bag, it is taken for one (a damaged bag gets the bag reader's diagnosis).
    let named = scratch("dive.mcap");
    std::fs::write(&named, CSV).unwrap();
    let e = Readers::default()
        .read(&named, &ReadOptions::default())
        .unwrap_err();
    assert!(e.message.contains("needs a mapping file"), "{e}");
}

/// A reader of files starting with `FAKE`: three rows at depth 2 m.
struct Fake;

impl LogReader for Fake {
    fn format(&self) -> &'static str {
        "fake"
    }
    fn recognises(&self, sniff: &Sniff<'_>) -> bool {
        sniff.head.starts_with(b"FAKE")
    }
    fn read(&self, path: &Path, options: &ReadOptions) -> Result<MeasuredRun, RunError> {
        MeasuredRun::parse_with(&CSV.replace("0.5\n", "2\n"), path, options)
    }
}

#[test]
fn a_reader_put_first_is_asked_first_and_only_for_what_it_recognises() {
    let readers = Readers::default().with_first(Arc::new(Fake));
    assert_eq!(readers.formats(), ["fake", "rosbag2 (no mapping)", "CSV"]);
    let fake = scratch("fake.csv");
    std::fs::write(&fake, "FAKE").unwrap();
    let run = readers.read(&fake, &ReadOptions::default()).unwrap();
    assert_eq!(run.channels[0].values, [2.0, 2.0, 2.0]);
    let csv = scratch("plain.csv");
    std::fs::write(&csv, CSV).unwrap();
    let run = readers.read(&csv, &ReadOptions::default()).unwrap();
    assert_eq!(run.channels[0].values, [0.5, 0.5, 0.5]);
}
