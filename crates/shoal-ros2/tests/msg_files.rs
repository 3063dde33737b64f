//! The `shoal_msgs` interface package and the Rust types agree: every `.msg` file in
//! `crates/shoal-ros2/shoal_msgs/msg/`, parsed as a bag's schema is (the rosbag2 reader's
//! parser), has exactly the fields of its Rust struct — names, types, order (traced with
//! serde-reflection, so the check sees what CDR writes) — and its constants the values of the
//! Rust constants; and the package's build files list every `.msg` file.

use serde_reflection::{ContainerFormat, Format, Named, Registry, Tracer, TracerConfig};
use shoal_ros2::msgs::{self, Actuators, FrameOutcome, OpticalFrame, Setpoint};
use shoal_rosbag::schema::{Count, Elem, Prim, Schema};
use std::path::{Path, PathBuf};

fn package() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("shoal_msgs")
}

fn registry() -> Registry {
    let mut t = Tracer::new(TracerConfig::default());
    t.trace_simple_type::<Setpoint>().unwrap();
    t.trace_simple_type::<Actuators>().unwrap();
    t.trace_simple_type::<OpticalFrame>().unwrap();
    t.trace_simple_type::<FrameOutcome>().unwrap();
    t.registry().unwrap()
}

/// The serde format a `.msg` field must have.
fn expected(schema: &Schema, elem: Elem, count: Count) -> Format {
    let one = match elem {
        Elem::Prim(p) => match p {
            Prim::Bool => Format::Bool,
            Prim::U8 => Format::U8,
            Prim::I8 => Format::I8,
            Prim::I16 => Format::I16,
            Prim::U16 => Format::U16,
            Prim::I32 => Format::I32,
            Prim::U32 => Format::U32,
            Prim::I64 => Format::I64,
            Prim::U64 => Format::U64,
            Prim::F32 => Format::F32,
            Prim::F64 => Format::F64,
            Prim::Str | Prim::WStr => Format::Str,
        },
        // builtin_interfaces/Time → the Rust `Time`.
        Elem::Msg(t) => Format::TypeName(schema.types[t].name.rsplit('/').next().unwrap().into()),
    };
    match count {
        Count::One => one,
        Count::Seq => Format::Seq(Box::new(one)),
        Count::Fixed(n) => Format::TupleArray {
            content: Box::new(one),
            size: n,
        },
    }
}

fn fields(reg: &Registry, name: &str) -> Vec<(String, Format)> {
    match reg.get(name) {
        Some(ContainerFormat::Struct(f)) => f
            .iter()
            .map(|Named { name, value }| (name.clone(), value.clone()))
            .collect(),
        other => panic!("{name}: {other:?}"),
    }
}

/// `TYPE NAME=VALUE` lines of a `.msg` file.
fn constants(text: &str) -> Vec<(String, i64)> {
    text.lines()
        .filter_map(|l| {
            let l = l.split('#').next()?.trim();
            let (lhs, v) = l.split_once('=')?;
            let name = lhs.split_whitespace().nth(1)?;
            Some((name.to_string(), v.trim().parse().ok()?))
        })
        .collect()
}

#[test]
fn every_msg_file_matches_its_rust_type_field_for_field() {
    let reg = registry();
    let mut files: Vec<PathBuf> = std::fs::read_dir(package().join("msg"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        ["Actuators", "FrameOutcome", "OpticalFrame", "Setpoint"]
    );
    for (file, name) in files.iter().zip(&names) {
        let text = std::fs::read_to_string(file).unwrap();
        let schema = Schema::parse(&format!("shoal_msgs/msg/{name}"), &text).unwrap();
        let msg: Vec<(String, Format)> = schema
            .root_type()
            .fields
            .iter()
            .map(|f| (f.name.clone(), expected(&schema, f.elem, f.count)))
            .collect();
        assert_eq!(
            msg,
            fields(&reg, name),
            "{name}.msg and the Rust struct differ"
        );
    }
    // The stamp is builtin_interfaces/Time: int32 sec, uint32 nanosec.
    assert_eq!(
        fields(&reg, "Time"),
        [
            ("sec".to_string(), Format::I32),
            ("nanosec".to_string(), Format::U32)
        ]
    );
}

#[test]
fn the_constants_are_the_rust_ones() {
    let setpoint = std::fs::read_to_string(package().join("msg/Setpoint.msg")).unwrap();
    let want = [
        ("MODE_KEEP", msgs::mode::KEEP),
        ("MODE_OFF", msgs::mode::OFF),
        ("MODE_DIVING", msgs::mode::DIVING),
        ("MODE_BUOYANCY", msgs::mode::BUOYANCY),
        ("MODE_TURNING", msgs::mode::TURNING),
        ("MODE_DRIFT", msgs::mode::DRIFT),
        ("MODE_AUTO", msgs::mode::AUTO),
    ];
    let got = constants(&setpoint);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for ((n, v), (wn, wv)) in got.iter().zip(want) {
        assert_eq!((n.as_str(), *v), (wn, i64::from(wv)));
    }
    let frame = std::fs::read_to_string(package().join("msg/OpticalFrame.msg")).unwrap();
    assert_eq!(
        constants(&frame),
        [("ALL_MODEMS".to_string(), i64::from(msgs::ALL_MODEMS))]
    );
}

#[test]
fn the_package_builds_every_msg_file() {
    let cmake = std::fs::read_to_string(package().join("CMakeLists.txt")).unwrap();
    for f in std::fs::read_dir(package().join("msg")).unwrap() {
        let name = f.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            cmake.contains(&format!("\"msg/{name}\"")),
            "CMakeLists.txt lacks msg/{name}"
        );
    }
    let xml = std::fs::read_to_string(package().join("package.xml")).unwrap();
    assert!(xml.contains("<name>shoal_msgs</name>") && xml.contains("rosidl_interface_packages"));
}
