//! ROS 2 message definitions in rosbag2's `ros2msg` form: a type's `.msg` text followed by
//! that of every type it uses — depth first, each dependency once, after a line of 80 `=` and
//! a line `MSG: <package>/<Type>` — as `ros2 bag record` stores them as MCAP schemas. The
//! tables of definitions live beside their types ([`super::ros2`], [`super::foxglove`],
//! [`super::plain`]); [`definition`] assembles one from all of them.

use super::msgdef::MsgDef;
use super::{foxglove, plain, ros2};

/// The line before each dependency's definition: 80 `=`.
const RULE: &str =
    "================================================================================";

/// Every definition `run.mcap` and the ROS 2 bridge write.
fn tables() -> [&'static [MsgDef]; 3] {
    [ros2::DEFS, foxglove::DEFS, plain::DEFS]
}

/// The complete definition of `name` (e.g. `sensor_msgs/msg/Imu`) in rosbag2's `ros2msg`
/// form, or `None` for a type not written here.
pub fn definition(name: &str) -> Option<String> {
    fn find(name: &str) -> Option<&'static MsgDef> {
        tables().into_iter().flatten().find(|d| d.name == name)
    }
    fn add(name: &str, seen: &mut Vec<&'static str>, out: &mut String) -> Option<()> {
        let d = find(name)?;
        out.push_str(d.text);
        for &dep in d.uses {
            if seen.contains(&dep) {
                continue;
            }
            seen.push(dep);
            out.push_str(&format!("\n{RULE}\nMSG: {dep}\n"));
            add(dep, seen, out)?;
        }
        Some(())
    }
    let mut out = String::new();
    add(name, &mut Vec::new(), &mut out)?;
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn definitions_append_each_dependency_once_depth_first() {
        let imu = definition("sensor_msgs/msg/Imu").unwrap();
        let rule = "=".repeat(80);
        let heads: Vec<&str> = imu
            .lines()
            .filter_map(|l| l.strip_prefix("MSG: "))
            .collect();
        assert_eq!(
            heads,
            [
                "geometry_msgs/Quaternion",
                "geometry_msgs/Vector3",
                "std_msgs/Header",
                "builtin_interfaces/Time"
            ]
        );
        assert!(imu.starts_with("# An inertial measurement."));
        assert!(imu.contains(&format!("\n\n{rule}\nMSG: std_msgs/Header\n")));
        assert_eq!(imu.matches(&rule).count(), 4);
        let arr = definition("std_msgs/msg/Float64MultiArray").unwrap();
        assert!(
            arr.ends_with("uint32 stride # elements per step of it, times the inner dimensions\n")
        );
        assert!(definition("nav_msgs/msg/Odometry").is_none());
    }

    /// Every type a definition uses is defined, and every complex field's type is among the
    /// uses (so no reader meets an unknown type).
    #[test]
    fn every_used_type_is_defined_and_declared() {
        let primitives = [
            "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64",
            "uint64", "float32", "float64", "string",
        ];
        for d in tables().into_iter().flatten() {
            let pkg = d.name.split('/').next().unwrap();
            for &u in d.uses {
                assert!(
                    tables().into_iter().flatten().any(|e| e.name == u),
                    "{}: uses {u}, not defined",
                    d.name
                );
            }
            for line in d.text.lines() {
                let line = line.split('#').next().unwrap().trim();
                let Some(ty) = line.split_whitespace().next() else {
                    continue;
                };
                if line.contains('=') && !line.contains(' ') {
                    continue;
                }
                let base = ty.split('[').next().unwrap();
                if primitives.contains(&base) {
                    continue;
                }
                let full = if base.contains('/') {
                    base.to_string()
                } else {
                    format!("{pkg}/{base}")
                };
                assert!(
                    d.uses.contains(&full.as_str()),
                    "{}: {full} not in uses",
                    d.name
                );
            }
        }
    }
}
