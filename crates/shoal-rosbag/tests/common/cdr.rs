//! Message bodies written by hand, byte by byte, with a record of where each value lies: the
//! kit's message types (sensor_msgs `Imu` and `FluidPressure`, std_msgs `Float64MultiArray`)
//! and a vendor type (MAVROS's `mavros_msgs/msg/RCOut`: a header and `uint16[] channels`), in
//! plain little-endian CDR as rclcpp writes them (encapsulation header `00 01 00 00`, then
//! each value aligned to its size counted from after that header; strings and sequences a
//! `uint32` count first). The fuzz tests mutate these bodies and use the layout to know which
//! values a mutation cannot have changed.

#![allow(dead_code)]

/// What a stretch of a body holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    F64,
    I32,
    U32,
    U16,
    /// The `uint32` count of a string (bytes with the NUL) or a sequence (elements).
    Count,
    /// A string's bytes and NUL.
    Text,
}

impl Kind {
    /// A number a mapping can select.
    pub fn is_number(self) -> bool {
        matches!(self, Kind::F64 | Kind::I32 | Kind::U32 | Kind::U16)
    }
}

/// One value of a body: its field path (as a mapping writes it), where it lies, what it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    pub path: String,
    pub at: usize,
    pub size: usize,
    pub kind: Kind,
    /// The number written (a count's count; 0 for text).
    pub value: f64,
}

impl Leaf {
    /// The number these bytes of `data` hold at this leaf's place, read little-endian.
    pub fn read(&self, data: &[u8]) -> f64 {
        let b = &data[self.at..self.at + self.size];
        match self.kind {
            Kind::F64 => f64::from_le_bytes(b.try_into().unwrap()),
            Kind::I32 => i32::from_le_bytes(b.try_into().unwrap()) as f64,
            Kind::U32 | Kind::Count => u32::from_le_bytes(b.try_into().unwrap()) as f64,
            Kind::U16 => u16::from_le_bytes(b.try_into().unwrap()) as f64,
            Kind::Text => 0.0,
        }
    }
}

/// A message body and where its values lie.
#[derive(Clone, Debug)]
pub struct Body {
    /// The type's name, as the bag's schema names it.
    pub type_name: &'static str,
    pub bytes: Vec<u8>,
    pub leaves: Vec<Leaf>,
}

impl Body {
    /// The selectable numbers.
    pub fn numbers(&self) -> impl Iterator<Item = &Leaf> {
        self.leaves.iter().filter(|l| l.kind.is_number())
    }
}

struct W {
    b: Vec<u8>,
    leaves: Vec<Leaf>,
}

impl W {
    fn new() -> W {
        W {
            b: vec![0x00, 0x01, 0x00, 0x00],
            leaves: Vec::new(),
        }
    }

    fn put(&mut self, path: &str, kind: Kind, bytes: &[u8], value: f64) {
        while !(self.b.len() - 4).is_multiple_of(bytes.len().min(8)) {
            self.b.push(0);
        }
        self.leaves.push(Leaf {
            path: path.to_string(),
            at: self.b.len(),
            size: bytes.len(),
            kind,
            value,
        });
        self.b.extend_from_slice(bytes);
    }

    fn f64(&mut self, path: &str, v: f64) {
        self.put(path, Kind::F64, &v.to_le_bytes(), v);
    }
    fn i32(&mut self, path: &str, v: i32) {
        self.put(path, Kind::I32, &v.to_le_bytes(), v as f64);
    }
    fn u32(&mut self, path: &str, v: u32) {
        self.put(path, Kind::U32, &v.to_le_bytes(), v as f64);
    }
    fn u16(&mut self, path: &str, v: u16) {
        self.put(path, Kind::U16, &v.to_le_bytes(), v as f64);
    }
    fn count(&mut self, path: &str, n: usize) {
        self.put(path, Kind::Count, &(n as u32).to_le_bytes(), n as f64);
    }
    fn string(&mut self, path: &str, s: &str) {
        self.count(path, s.len() + 1);
        let at = self.b.len();
        self.b.extend_from_slice(s.as_bytes());
        self.b.push(0);
        self.leaves.push(Leaf {
            path: path.to_string(),
            at,
            size: s.len() + 1,
            kind: Kind::Text,
            value: 0.0,
        });
    }
    fn header(&mut self, ns: u64, frame: &str) {
        self.i32("header.stamp.sec", (ns / 1_000_000_000) as i32);
        self.u32("header.stamp.nanosec", (ns % 1_000_000_000) as u32);
        self.string("header.frame_id", frame);
    }
    fn vector(&mut self, path: &str, v: [f64; 3]) {
        for (c, x) in ["x", "y", "z"].iter().zip(v) {
            self.f64(&format!("{path}.{c}"), x);
        }
    }
    fn fixed(&mut self, path: &str, v: &[f64]) {
        for (k, x) in v.iter().enumerate() {
            self.f64(&format!("{path}[{k}]"), *x);
        }
    }
    fn done(self, type_name: &'static str) -> Body {
        Body {
            type_name,
            bytes: self.b,
            leaves: self.leaves,
        }
    }
}

/// A `sensor_msgs/msg/Imu` stamped `ns`: attitude quaternion (x, y, z, w), angular velocity,
/// linear acceleration, and `cov` as each of the three covariances.
pub fn imu(ns: u64, q: [f64; 4], rates: [f64; 3], accel: [f64; 3], cov: &[f64; 9]) -> Body {
    let mut w = W::new();
    w.header(ns, "auv");
    for (c, x) in ["x", "y", "z", "w"].iter().zip(q) {
        w.f64(&format!("orientation.{c}"), x);
    }
    w.fixed("orientation_covariance", cov);
    w.vector("angular_velocity", rates);
    w.fixed("angular_velocity_covariance", cov);
    w.vector("linear_acceleration", accel);
    w.fixed("linear_acceleration_covariance", cov);
    w.done("sensor_msgs/msg/Imu")
}

/// A `sensor_msgs/msg/FluidPressure` stamped `ns` \[Pa, Pa²\].
pub fn fluid_pressure(ns: u64, pressure: f64, variance: f64) -> Body {
    let mut w = W::new();
    w.header(ns, "auv");
    w.f64("fluid_pressure", pressure);
    w.f64("variance", variance);
    w.done("sensor_msgs/msg/FluidPressure")
}

/// A one-dimensional `std_msgs/msg/Float64MultiArray` whose dimension is called `label`.
pub fn float64_multi_array(label: &str, data: &[f64]) -> Body {
    let mut w = W::new();
    w.count("layout.dim", 1);
    w.string("layout.dim[0].label", label);
    w.u32("layout.dim[0].size", data.len() as u32);
    w.u32("layout.dim[0].stride", data.len() as u32);
    w.u32("layout.data_offset", 0);
    w.count("data", data.len());
    w.fixed("data", data);
    w.done("std_msgs/msg/Float64MultiArray")
}

/// MAVROS's servo outputs: `mavros_msgs/msg/RCOut` stamped `ns`, PWM pulse widths \[µs\].
pub fn rc_out(ns: u64, channels: &[u16]) -> Body {
    let mut w = W::new();
    w.header(ns, "base_link");
    w.count("channels", channels.len());
    for (k, v) in channels.iter().enumerate() {
        w.u16(&format!("channels[{k}]"), *v);
    }
    w.done(RC_OUT)
}

/// The vendor type's name and its `ros2msg` schema as rosbag2 stores it.
pub const RC_OUT: &str = "mavros_msgs/msg/RCOut";
pub const RC_OUT_SCHEMA: &str = "# RAW Servo out state\n\nstd_msgs/Header header\n\
    uint16[] channels\n\
    ================================================================================\n\
    MSG: std_msgs/Header\n\
    # Standard metadata for higher-level stamped data types.\n\
    builtin_interfaces/Time stamp\n\
    string frame_id\n\
    ================================================================================\n\
    MSG: builtin_interfaces/Time\n\
    int32 sec\n\
    uint32 nanosec\n";
