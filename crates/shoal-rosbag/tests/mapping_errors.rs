//! What a new user is told when a mapping and a bag do not fit, on the kit's bag
//! (`common/bagkit.rs`): a missing topic lists the bag's topics, a misspelt channel gets a
//! "did you mean" and so does a misspelt reference, a mode reference that is not a mode's code
//! names its message, an index past an array's end names index, length and field, a bag cut short
//! says what happened and what to do (no tool that is not installed); and the bag reader
//! behind the validation's log seam reads a bag by its content, whatever its name.

mod common;

use common::bagkit;
use shoal_rosbag::{Mapping, read_bag, readers};
use shoal_sysid::log::format::ReadOptions;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shoal-mapping-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The kit's bag (2 s) written to `name`.
fn kit_bag(name: &str) -> PathBuf {
    let path = scratch(name);
    std::fs::write(&path, bagkit::bag(2)).unwrap();
    path
}

/// The kit's mapping with `from` replaced by `to`.
fn mapping_with(from: &str, to: &str) -> Mapping {
    assert!(bagkit::MAPPING.contains(from), "{from}");
    Mapping::parse(&bagkit::MAPPING.replace(from, to), Path::new("m.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_missing_topic_lists_the_bags_topics() {
    let bag = kit_bag("missing_topic.mcap");
    let m = mapping_with(r#"topic = "pressure""#, r#"topic = "depth""#);
    let e = read_bag(&bag, &m).unwrap_err().to_string();
    assert!(
        e.contains("topic `/auv/depth` has no messages in the bag"),
        "{e}"
    );
    // Every topic the kit writes, mapped or not, in name order.
    assert!(
        e.contains(
            "its topics: `/auv/camera_info`, `/auv/imu`, `/auv/pressure`, `/auv/pump`, \
             `/auv/thrusters`, `/auv/tilts`"
        ),
        "{e}"
    );
}

#[test]
fn a_misspelt_channel_gets_a_did_you_mean() {
    let text = bagkit::MAPPING.replace(r#""y.depth""#, r#""y.dpth""#);
    let e = Mapping::parse(&text, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`y.dpth`: not a channel — did you mean `y.depth`?"),
        "{e}"
    );
    // Nothing near: no guess, the list only.
    let text = bagkit::MAPPING.replace(r#""y.depth""#, r#""y.salinity""#);
    let e = Mapping::parse(&text, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(!e.contains("did you mean"), "{e}");
    assert!(e.contains("allowed: y.depth"), "{e}");
}

#[test]
fn an_unknown_reference_gets_a_did_you_mean_and_the_allowed_names() {
    let text = format!(
        "{}[references]\n\"r.dpth\" = {{ topic = \"tilts\", field = \"data[0]\" }}\n",
        bagkit::MAPPING
    );
    let e = Mapping::parse(&text, Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "m.toml: [references] `r.dpth`: not a reference — did you mean `r.depth`? (allowed: \
         r.depth, r.yaw, r.surge, r.sway, r.mode)"
    );
    // A channel's name is not a reference; unknown fields of an entry are refused.
    let e = Mapping::parse(&text.replace("r.dpth", "y.depth"), Path::new("m.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`y.depth`: not a reference"), "{e}");
    let e = Mapping::parse(
        &text.replace("r.dpth", "r.depth").replace("field", "feld"),
        Path::new("m.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("unknown field `feld`"), "{e}");
}

#[test]
fn a_mode_reference_that_is_not_a_code_names_its_message() {
    let bag = kit_bag("mode_not_a_code.mcap");
    // The port command is 16 … 20 %: no mode's code.
    let text = format!(
        "{}[references]\n\"r.mode\" = {{ topic = \"thrusters\", field = \"data[1]\" }}\n",
        bagkit::MAPPING
    );
    let m = Mapping::parse(&text, Path::new("m.toml")).unwrap();
    let e = read_bag(&bag, &m).unwrap_err().to_string();
    assert!(
        e.contains(
            "topic `/auv/thrusters`, message 1, field `data[1]`: 20 is not a value of `r.mode`"
        ),
        "{e}"
    );
    assert!(e.contains("auto (5), raw (6)"), "{e}");
    assert!(e.contains("(entry `r.mode`)"), "{e}");
}

#[test]
fn an_index_past_an_arrays_end_names_index_length_and_field() {
    let bag = kit_bag("past_end.mcap");
    // The pump's array holds one value.
    let m = mapping_with(
        r#"topic = "pump", field = "data[0]""#,
        r#"topic = "pump", field = "data[3]""#,
    );
    let e = read_bag(&bag, &m).unwrap_err().to_string();
    assert!(e.contains("topic `/auv/pump`, message 1"), "{e}");
    assert!(
        e.contains("`data[3]` is past the end of `data`: index 3, but this message's `data` has 1 element(s)"),
        "{e}"
    );
    assert!(!e.contains("NaN"), "{e}");
}

#[test]
fn a_bag_cut_short_says_what_happened_and_what_to_do() {
    let whole = bagkit::bag(2);
    let path = scratch("cut.mcap");
    std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
    let m = Mapping::parse(bagkit::MAPPING, Path::new("m.toml")).unwrap();
    let e = read_bag(&path, &m).unwrap_err().to_string();
    assert!(e.contains("the file breaks off after"), "{e}");
    assert!(e.contains("record the run again"), "{e}");
    assert!(!e.contains("mcap recover"), "{e}");
}

#[test]
fn the_seams_bag_reader_reads_a_bag_by_content_whatever_its_name() {
    let bag = kit_bag("kit_bag.dat");
    let mapping = scratch("kit.toml");
    std::fs::write(&mapping, bagkit::MAPPING).unwrap();
    let m = Mapping::read(&mapping).unwrap();
    let direct = read_bag(&bag, &m).unwrap();
    let through = readers(Some(&mapping))
        .unwrap()
        .read(&bag, &ReadOptions::default())
        .unwrap();
    assert_eq!(through.t, direct.t);
    assert_eq!(through.channels, direct.channels);
    assert!(direct.t.len() > 100, "{} rows", direct.t.len());
    // Without a mapping the same file is refused, saying what is missing.
    let e = readers(None)
        .unwrap()
        .read(&bag, &ReadOptions::default())
        .unwrap_err();
    assert!(e.message.contains("needs a mapping file"), "{e}");
}
