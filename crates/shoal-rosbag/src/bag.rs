//! Reading a rosbag2: its MCAP file(s), the mapped topics' messages decoded by their own
//! schemas into time series, one per mapping entry.
//!
//! A bag is a `.mcap` file or a rosbag2 folder (`metadata.yaml` and its `.mcap` files, read in
//! name order, as `ros2 bag record` splits them). Messages are read with Foxglove's `mcap`
//! crate (chunks compressed with zstd or lz4 included); every channel of a mapped topic must
//! carry a `ros2msg` schema and `cdr` messages. Topics the mapping does not name are passed
//! over without decoding.
//!
//! Times: each topic's clock (`header` stamps or the bag's `log` times, see
//! `crate::mapping`) in nanoseconds. A topic's messages are put in time order (a bag stores
//! them as received); two messages of one topic at the same time are one sample if they agree
//! and an error if they do not.

use crate::decode::decode;
use crate::mapping::{Clock, Entry, Feeds, Frame, Mapping};
use crate::schema::Schema;
use crate::select::{Plan, Target};
use nalgebra::Quaternion;
use shoal_model::frames;
use shoal_model::math::Quat;
use shoal_sysid::log::run::ChannelKind;
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// A problem with a bag, naming the file and, where it is in one, the topic, the message and
/// the field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}: {}{message}", file.display(), place.as_ref().map(|p| format!("{p}: ")).unwrap_or_default())]
pub struct BagError {
    /// The bag file (or folder).
    pub file: PathBuf,
    /// Where in it: topic, message number, field, mapping entry.
    pub place: Option<String>,
    /// What is wrong and what to do.
    pub message: String,
}

impl BagError {
    pub(crate) fn new(file: &Path, place: Option<String>, message: String) -> BagError {
        BagError {
            file: file.to_path_buf(),
            place,
            message,
        }
    }
}

/// One mapping entry's samples: times \[ns, on the topic's clock\] and values in shoal's unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// The entry.
    pub entry: Entry,
    /// Sample times, strictly increasing \[ns\].
    pub t: Vec<i64>,
    /// One value per time.
    pub v: Vec<f64>,
}

/// What reading found, for the report line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BagSummary {
    /// MCAP files read.
    pub files: usize,
    /// Messages of mapped topics decoded.
    pub decoded: usize,
    /// Messages of other topics passed over.
    pub passed_over: usize,
    /// Each mapped topic: its message type and clock.
    pub topics: Vec<(String, String, Clock)>,
}

/// The MCAP files of a bag: the file itself, or a folder's `.mcap` files in name order.
pub fn bag_files(path: &Path) -> Result<Vec<PathBuf>, BagError> {
    let fail = |m: String| BagError::new(path, None, m);
    if path.is_dir() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| fail(format!("cannot read the folder: {e}")))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "mcap"))
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(fail(
                "no .mcap file in this folder: shoal reads rosbag2 with the MCAP storage \
                 (a sqlite3 bag, .db3, converts with `ros2 bag convert`)"
                    .into(),
            ));
        }
        return Ok(files);
    }
    if path.extension().is_some_and(|x| x == "db3") {
        return Err(fail(
            "a sqlite3 bag: shoal reads rosbag2 with the MCAP storage (convert with \
             `ros2 bag convert`, or record with `--storage mcap`, the default since Iron)"
                .into(),
        ));
    }
    Ok(vec![path.to_path_buf()])
}

/// The longest record read \[bytes\]: a corrupt length (or a chunk's) beyond it is an error
/// rather than an allocation of that size. Real bags' records are a few MiB at most (an image).
pub const RECORD_LIMIT: usize = 256 << 20;

/// The messages of the MCAP file at `file`, streamed (memory: one chunk); a record the MCAP
/// library cannot read is an error (see [`Guarded`]).
fn open_mcap(
    file: &Path,
) -> Result<impl Iterator<Item = Result<mcap::Message<'static>, String>>, BagError> {
    use std::io::{Read, Seek};
    let fail = |m: String| BagError::new(file, None, m);
    let mut f =
        std::fs::File::open(file).map_err(|e| fail(format!("cannot read the file: {e}")))?;
    let mut magic = [0u8; 8];
    let n = f
        .read(&mut magic)
        .map_err(|e| fail(format!("cannot read the file: {e}")))?;
    if magic[..n] != mcap::MAGIC[..] {
        return Err(fail(
            "not an MCAP file (it does not start with MCAP's magic bytes): shoal reads \
             rosbag2 with the MCAP storage"
                .into(),
        ));
    }
    f.rewind()
        .map_err(|e| fail(format!("cannot read the file: {e}")))?;
    let options =
        mcap::sans_io::LinearReaderOptions::default().with_record_length_limit(RECORD_LIMIT);
    Ok(Guarded {
        stream: mcap::io::MessageReader::new_with_options(
            std::io::BufReader::with_capacity(1 << 20, f),
            options,
        ),
        failed: false,
    })
}

/// An MCAP message stream whose reader's panics are errors. The MCAP library (0.26) trusts
/// some lengths in the file: a record inside an uncompressed chunk that claims to run past
/// the chunk's end overflows its arithmetic, which panics in builds with overflow checks
/// (debug builds, tests) where release builds go on to an error. Caught here, a corrupt file
/// is an error in every build; the stream ends after it.
struct Guarded<I> {
    stream: I,
    failed: bool,
}

impl<I: Iterator<Item = mcap::McapResult<mcap::Message<'static>>>> Iterator for Guarded<I> {
    type Item = Result<mcap::Message<'static>, String>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let stream = &mut self.stream;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| stream.next())) {
            Ok(next) => next.map(|m| m.map_err(|e| e.to_string())),
            Err(_) => {
                self.failed = true;
                Some(Err(
                    "a corrupt record: the MCAP reader failed on a length in it".into(),
                ))
            }
        }
    }
}

/// A mapped topic's decoding: its schema, what to keep, where each entry's values are.
struct TopicPlan {
    schema: Schema,
    plan: Plan,
    clock: Clock,
    stamp: Option<(usize, usize)>,
    targets: Vec<(usize, Target)>,
    type_name: String,
}

/// Reads every mapped entry's series from the bag at `path`.
pub fn read_series(path: &Path, mapping: &Mapping) -> Result<(Vec<Series>, BagSummary), BagError> {
    let files = bag_files(path)?;
    let topics = mapping.topics();
    let mut plans: HashMap<String, TopicPlan> = HashMap::new();
    // Per topic: (time, message number, values).
    let mut samples: HashMap<String, Vec<(i64, usize, Vec<f64>)>> = HashMap::new();
    let mut summary = BagSummary {
        files: files.len(),
        ..BagSummary::default()
    };
    // Every topic in the bag, for the message when a mapped one is not there.
    let mut seen: BTreeSet<String> = BTreeSet::new();
    for file in &files {
        let stream = open_mcap(file)?;
        for (k, message) in stream.enumerate() {
            let message = message.map_err(|e| {
                BagError::new(
                    file,
                    None,
                    format!(
                        "the file breaks off after {k} message(s) ({e}): a recording cut \
                         short, its recorder stopped before it closed the file (killed, power \
                         lost, disk full). shoal reads whole MCAP files only: record the run \
                         again, stopping `ros2 bag record` with Ctrl-C so that it closes the \
                         file"
                    ),
                )
            })?;
            let topic = &message.channel.topic;
            if !seen.contains(topic) {
                seen.insert(topic.clone());
            }
            if topics.binary_search(&topic.as_str()).is_err() {
                summary.passed_over += 1;
                continue;
            }
            if !plans.contains_key(topic) {
                let plan = topic_plan(file, &message.channel, mapping)?;
                plans.insert(topic.clone(), plan);
            }
            let tp = &plans[topic];
            let list = samples.entry(topic.clone()).or_default();
            let number = list.len() + 1;
            let place = || format!("topic `{topic}`, message {number}");
            let mut out = vec![f64::NAN; tp.plan.slots];
            decode(&tp.schema, &tp.plan.sel, &message.data, &mut out).map_err(|e| {
                BagError::new(file, Some(place()), format!("{} : {e}", tp.type_name))
            })?;
            let t = match (tp.clock, tp.stamp) {
                (Clock::Header, Some((s, n))) => (out[s] as i64) * 1_000_000_000 + out[n] as i64,
                _ => i64::try_from(message.log_time).map_err(|_| {
                    BagError::new(file, Some(place()), "log time past the year 2262".into())
                })?,
            };
            list.push((t, number, out));
            summary.decoded += 1;
        }
    }
    let mut series = Vec::new();
    for (i, e) in mapping.entries.iter().enumerate() {
        let (Some(tp), Some(list)) = (plans.get(&e.topic), samples.get_mut(&e.topic)) else {
            return Err(BagError::new(
                path,
                Some(format!("entry `{}`", e.key)),
                format!(
                    "topic `{}` has no messages in the bag; its topics: {}",
                    e.topic,
                    if seen.is_empty() {
                        "none (the bag holds no messages)".to_string()
                    } else {
                        seen.iter()
                            .map(|t| format!("`{t}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    }
                ),
            ));
        };
        list.sort_by_key(|(t, n, _)| (*t, *n));
        let Some(&(_, target)) = tp.targets.iter().find(|(k, _)| *k == i) else {
            unreachable!("the plan of a topic holds a target for each of its entries")
        };
        series.push(entry_series(path, e, target, list)?);
    }
    let mut listed: Vec<(String, String, Clock)> = plans
        .iter()
        .map(|(t, p)| (t.clone(), p.type_name.clone(), p.clock))
        .collect();
    listed.sort_by(|a, b| a.0.cmp(&b.0));
    summary.topics = listed;
    Ok((series, summary))
}

fn topic_plan(
    file: &Path,
    channel: &mcap::Channel<'_>,
    mapping: &Mapping,
) -> Result<TopicPlan, BagError> {
    let topic = &channel.topic;
    let at = |m: String| BagError::new(file, Some(format!("topic `{topic}`")), m);
    if channel.message_encoding != "cdr" {
        return Err(at(format!(
            "messages encoded as `{}`: shoal reads ROS 2's `cdr`",
            channel.message_encoding
        )));
    }
    let Some(schema) = &channel.schema else {
        return Err(at(
            "the channel has no schema, so its messages cannot be read: record the bag with a \
             ROS 2 tool that stores message definitions (ros2 bag, rosbags), or map another \
             topic"
                .into(),
        ));
    };
    if schema.encoding != "ros2msg" {
        return Err(at(format!(
            "type `{}` has a `{}` schema: shoal reads `ros2msg` definitions (the .msg text \
             ros2 bag stores); republish the data as a standard type (e.g. \
             std_msgs/msg/Float64MultiArray) or record with a tool that stores .msg text",
            schema.name, schema.encoding
        )));
    }
    let text = std::str::from_utf8(&schema.data)
        .map_err(|_| at(format!("the schema of `{}` is not UTF-8 text", schema.name)))?;
    let parsed = Schema::parse(&schema.name, text).map_err(|e| at(e.to_string()))?;
    let mut plan = Plan::new();
    let mut targets = Vec::new();
    let mut clock = None;
    for (i, e) in mapping
        .entries
        .iter()
        .enumerate()
        .filter(|(_, e)| e.topic == *topic)
    {
        let t = plan.add(&parsed, &e.field).map_err(|m| {
            at(format!(
                "entry `{}`, field `{}` of {}: {m}",
                e.key, e.field, schema.name
            ))
        })?;
        check_target(e, t)
            .map_err(|m| at(format!("entry `{}`, field `{}`: {m}", e.key, e.field)))?;
        match (clock, e.clock) {
            (Some(c), Some(d)) if c != d => {
                return Err(at(format!(
                    "entry `{}` asks for clock `{d:?}` but another entry of the topic for \
                     `{c:?}`: one clock per topic",
                    e.key
                )));
            }
            (None, c) => clock = c,
            _ => {}
        }
        targets.push((i, t));
    }
    let stamp = match (
        plan.add(&parsed, "header.stamp.sec"),
        plan.add(&parsed, "header.stamp.nanosec"),
    ) {
        (Ok(Target::Number(s)), Ok(Target::Number(n))) => Some((s, n)),
        _ => None,
    };
    let clock = match (clock, stamp) {
        (Some(Clock::Header), None) => {
            return Err(at(format!(
                "clock = \"header\" but {} has no `header.stamp`: use clock = \"log\"",
                schema.name
            )));
        }
        (Some(c), _) => c,
        (None, Some(_)) => Clock::Header,
        (None, None) => Clock::Log,
    };
    Ok(TopicPlan {
        schema: parsed,
        plan,
        clock,
        stamp,
        targets,
        type_name: schema.name.clone(),
    })
}

/// A quaternion only for an attitude channel; a number for everything else.
fn check_target(e: &Entry, t: Target) -> Result<(), String> {
    let angle = matches!(
        e.feeds,
        Feeds::Channel(ChannelKind::Roll | ChannelKind::Pitch | ChannelKind::Yaw)
    );
    match t {
        Target::Quaternion(_) if !angle => Err(format!(
            "a quaternion gives an angle: map it to `y.roll`, `y.pitch` or `y.yaw`, and `{}` \
             to a number (e.g. `{}.z`)",
            e.key, e.field
        )),
        _ => Ok(()),
    }
}

/// One entry's values from its topic's decoded messages (in time order).
fn entry_series(
    path: &Path,
    e: &Entry,
    target: Target,
    list: &[(i64, usize, Vec<f64>)],
) -> Result<Series, BagError> {
    let mut t: Vec<i64> = Vec::with_capacity(list.len());
    let mut v: Vec<f64> = Vec::with_capacity(list.len());
    let mut last_n = 0usize;
    for (time, n, out) in list {
        let place = || {
            Some(format!(
                "topic `{}`, message {n}, field `{}`",
                e.topic, e.field
            ))
        };
        let raw = match target {
            Target::Number(k) => out[k],
            Target::Quaternion(q) => angle(e, [out[q[0]], out[q[1]], out[q[2]], out[q[3]]])
                .map_err(|m| BagError::new(path, place(), m))?,
        };
        if !raw.is_finite() {
            return Err(BagError::new(
                path,
                place(),
                format!(
                    "no finite value: the sensor wrote {raw} (entry `{}`)",
                    e.key
                ),
            ));
        }
        let mut value = e.scale * raw * frame_sign(e) + e.offset;
        if let Feeds::Reference(kind) = e.feeds {
            value = kind
                .check(value)
                .map_err(|m| BagError::new(path, place(), format!("{m} (entry `{}`)", e.key)))?;
        }
        if t.last() == Some(time) {
            if v.last() != Some(&value) {
                return Err(BagError::new(
                    path,
                    place(),
                    format!(
                        "same time as message {last_n} ({:.6} s) with another value: two \
                         samples cannot be at one instant (does the driver stamp its messages? \
                         clock = \"log\" takes the bag's receive times)",
                        *time as f64 * 1e-9
                    ),
                ));
            }
            continue;
        }
        t.push(*time);
        v.push(value);
        last_n = *n;
    }
    Ok(Series {
        entry: e.clone(),
        t,
        v,
    })
}

/// −1 for body rates and velocities about or along y and z written in ROS's axes (FLU; the
/// sign of [`shoal_model::frames::body`]).
fn frame_sign(e: &Entry) -> f64 {
    use ChannelKind::*;
    let axis = match (e.frame, e.feeds) {
        (Frame::Enu, Feeds::Channel(Q | V)) => 1,
        (Frame::Enu, Feeds::Channel(R | W)) => 2,
        _ => return 1.0,
    };
    let mut unit = [0.0; 3];
    unit[axis] = 1.0;
    frames::body(unit)[axis]
}

/// The channel's angle from a quaternion (x, y, z, w), in shoal's axes \[rad\]: a NED/FRD
/// attitude as it stands, an ENU/FLU one through [`shoal_model::frames::attitude_to_ned`].
fn angle(e: &Entry, q: [f64; 4]) -> Result<f64, String> {
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if n.is_nan() || n <= 1e-6 {
        return Err(format!("quaternion {q:?} has no length: not an attitude"));
    }
    let [x, y, z, w] = q;
    let q = Quat::from_quaternion(Quaternion::new(w, x, y, z));
    let (roll, pitch, yaw) = match e.frame {
        Frame::Enu => frames::attitude_to_ned(&q),
        Frame::Ned => q.euler_angles(),
    };
    Ok(match e.feeds {
        Feeds::Channel(ChannelKind::Roll) => roll,
        Feeds::Channel(ChannelKind::Pitch) => pitch,
        Feeds::Channel(ChannelKind::Yaw) => yaw,
        _ => unreachable!("check_target lets quaternions feed attitude channels only"),
    })
}
