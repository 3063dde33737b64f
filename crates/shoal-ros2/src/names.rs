//! Vehicles by name: a vehicle's name made a ROS 2 name ([`ros_name`]) is the name of its
//! topics (`/<namespace>/<name>/…`), and the name by which frames are addressed on
//! `modem/tx` (`to`) and by which `modem/rx` and `modem/outcome` name the sender and the
//! destination. [`Names`] holds it for every vehicle of the world, bridged or not (a ROS 2
//! node may address any vehicle with a modem), and refuses a world where two come out the same.

use crate::error::Ros2Error;
use std::collections::HashMap;

/// A vehicle's name as a ROS 2 name: every character but ASCII letters and digits as `_`,
/// runs of `_` as one, no `_` at the end, and a `v` before a leading digit (`school-0` →
/// `school_0`, `x--y` → `x_y`, `3d` → `v3d`). A ROS name comes out as itself.
pub fn ros_name(vehicle: &str) -> String {
    let mut s = String::with_capacity(vehicle.len() + 1);
    for c in vehicle.chars() {
        let c = if c.is_ascii_alphanumeric() { c } else { '_' };
        if !(c == '_' && (s.is_empty() || s.ends_with('_'))) {
            s.push(c);
        }
    }
    while s.ends_with('_') {
        s.pop();
    }
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit()) {
        s.insert(0, 'v');
    }
    s
}

/// Every vehicle of a world by its ROS 2 name, and back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Names {
    /// ROS name by vehicle id.
    by_id: Vec<String>,
    /// Vehicle id by ROS name.
    ids: HashMap<String, u32>,
}

impl Names {
    /// The ROS names of the vehicles `names` (their names in id order, as in
    /// `trajectories.csv`); two vehicles whose ROS names are the same are refused, naming
    /// both (topics under `/<namespace>/…`).
    pub fn new<'a>(
        names: impl IntoIterator<Item = &'a str>,
        namespace: &str,
    ) -> Result<Names, Ros2Error> {
        let mut out = Names::default();
        let mut world = Vec::new();
        for (id, name) in names.into_iter().enumerate() {
            let ros = ros_name(name);
            let id = u32::try_from(id)
                .map_err(|_| Ros2Error::Name(format!("more than {} vehicles", u32::MAX)))?;
            if let Some(&other) = out.ids.get(&ros) {
                return Err(Ros2Error::Name(format!(
                    "vehicles `{}` and `{name}` would share the ROS name `{ros}` (topics \
                     /{namespace}/{ros}/…, frames' `sender` and `to`): rename one (ROS names \
                     hold letters, digits and single `_`)",
                    world[other as usize]
                )));
            }
            out.ids.insert(ros.clone(), id);
            out.by_id.push(ros);
            world.push(name);
        }
        Ok(out)
    }

    /// The ROS name of vehicle `id` (`""` for an id that is not a vehicle's).
    pub fn name(&self, id: u32) -> &str {
        self.by_id.get(id as usize).map_or("", String::as_str)
    }

    /// The vehicle whose ROS name is exactly `name`, if any.
    pub fn id(&self, name: &str) -> Option<u32> {
        self.ids.get(name).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vehicle_names_become_ros_names() {
        // The same cases as python/shoal_ros2/swarm.py's `ros_name`.
        for (name, ros) in [
            ("school-0", "school_0"),
            ("x--y", "x_y"),
            ("3d", "v3d"),
            ("auv_", "auv"),
            ("_a", "a"),
            ("", "v"),
            ("ü-boot", "boot"),
        ] {
            assert_eq!(ros_name(name), ros, "{name}");
            assert_eq!(ros_name(ros), ros, "a ROS name is itself");
        }
    }

    #[test]
    fn names_resolve_both_ways_exactly_and_clashes_are_refused() {
        let n = Names::new(["auv-0", "auv-1", "3d"], "pool").unwrap();
        assert_eq!((n.name(0), n.name(1), n.name(2)), ("auv_0", "auv_1", "v3d"));
        assert_eq!((n.id("auv_1"), n.id("v3d")), (Some(1), Some(2)));
        // Only the ROS name itself: not the world's spelling, not another that maps to it.
        assert_eq!(
            (n.id("auv-1"), n.id("auv__1"), n.id(""), n.id("nobody")),
            (None, None, None, None)
        );
        assert_eq!(n.name(3), "");
        let e = Names::new(["a-b", "c", "a_b"], "pool").unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("`a-b` and `a_b`") && text.contains("/pool/a_b/"),
            "{text}"
        );
    }
}
