//! The MCAP file itself, written by Foxglove's `mcap` crate through a
//! [`shoal_output::files::AtomicFile`]: `run.mcap` is streamed to its hidden temporary
//! (`.run.mcap.tmp`) while the world runs and appears under its name only when
//! [`McapFile::finish`] has written the summary section and the run's outputs commit it. The
//! temporary cannot seek, so the writer keeps each chunk ([`CHUNK_BYTES`] of messages before
//! compression, zstd, single-threaded so the bytes do not depend on the machine) in memory
//! until it is whole. Every failure is a [`FileError`] naming the file and the reason.

use super::definitions::definition;
use mcap::records::MessageHeader;
use mcap::write::NoSeek;
use mcap::{McapError, WriteOptions, Writer};
use serde::Serialize;
use shoal_output::files::{AtomicFile, FileError};
use std::collections::BTreeMap;
use std::io::{BufWriter, Seek};
use std::path::{Path, PathBuf};

type Sink = NoSeek<BufWriter<AtomicFile>>;

/// Messages per chunk before compression \[bytes\]: the writer holds one chunk in memory, and
/// an index entry per channel and chunk until the end (≈ 50 B each: 6,000 channels of
/// [`super::MAX_VEHICLES`] vehicles in the 130 chunks of a file at its budget take ≈ 40 MB).
const CHUNK_BYTES: u64 = 4 << 20;

/// An MCAP file being written (under its temporary name).
pub struct McapFile {
    writer: Writer<Sink>,
    path: PathBuf,
    /// Messages written so far, per channel (index = channel id).
    sequence: Vec<u32>,
    /// Messages written \[count\].
    messages: u64,
    /// Their payloads \[bytes\].
    message_bytes: u64,
}

/// A finished MCAP file, still under its temporary name.
pub struct Finished {
    /// The file (commit it to give it its name).
    pub file: AtomicFile,
    /// Its length \[bytes\].
    pub bytes: u64,
    /// Messages in it \[count\].
    pub messages: u64,
    /// Their payloads, uncompressed \[bytes\].
    pub message_bytes: u64,
}

impl McapFile {
    /// Starts the file `path` (its temporary).
    pub fn create(path: &Path) -> Result<Self, FileError> {
        let file = AtomicFile::create(path)?;
        let sink = NoSeek::new(BufWriter::with_capacity(1 << 16, file));
        let writer = WriteOptions::new()
            .profile("ros2")
            .library(format!("shoal {}", env!("CARGO_PKG_VERSION")))
            .compression(Some(mcap::Compression::Zstd))
            .chunk_size(Some(CHUNK_BYTES))
            .compression_threads(0)
            .disable_seeking(true)
            .create(sink)
            .map_err(|e| error(path, e))?;
        Ok(Self {
            writer,
            path: path.to_path_buf(),
            sequence: Vec::new(),
            messages: 0,
            message_bytes: 0,
        })
    }

    /// Adds the schema `name` in `encoding`; returns its id.
    fn schema(&mut self, name: &str, encoding: &str, data: &[u8]) -> Result<u16, FileError> {
        let path = &self.path;
        self.writer
            .add_schema(name, encoding, data)
            .map_err(|e| error(path, e))
    }

    /// Adds the ROS 2 schema of type `name` (e.g. `sensor_msgs/msg/Imu`) with its complete
    /// definition ([`super::definitions::definition`]); its id.
    pub fn ros2_schema(&mut self, name: &str) -> Result<u16, FileError> {
        let text = definition(name).ok_or_else(|| FileError {
            path: self.path.clone(),
            reason: std::io::Error::other(format!("no definition of {name}")),
        })?;
        self.schema(name, "ros2msg", text.as_bytes())
    }

    /// Adds a CDR channel on `topic` with `schema` and `metadata`, and the QoS rosbag2 records
    /// (`offered_qos_profiles`: `latched` for a topic written once, which a late subscriber
    /// must still get); its id.
    pub fn channel(
        &mut self,
        schema: u16,
        topic: &str,
        latched: bool,
        metadata: &[(&str, String)],
    ) -> Result<u16, FileError> {
        let mut meta: BTreeMap<String, String> = metadata
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        meta.insert("offered_qos_profiles".into(), qos(latched));
        let path = &self.path;
        let id = self
            .writer
            .add_channel(schema, topic, "cdr", &meta)
            .map_err(|e| error(path, e))?;
        if self.sequence.len() <= usize::from(id) {
            self.sequence.resize(usize::from(id) + 1, 0);
        }
        Ok(id)
    }

    pub fn write(&mut self, channel: u16, ns: u64, data: &[u8]) -> Result<(), FileError> {
        let seq = &mut self.sequence[usize::from(channel)];
        *seq = seq.wrapping_add(1);
        let header = MessageHeader {
            channel_id: channel,
            sequence: *seq,
            log_time: ns,
            publish_time: ns,
        };
        let path = &self.path;
        self.writer
            .write_to_known_channel(&header, data)
            .map_err(|e| error(path, e))?;
        self.messages += 1;
        self.message_bytes += data.len() as u64;
        Ok(())
    }

    /// Writes the ROS 2 message `msg` in CDR ([`super::ros2::encode`]) on `channel` at `ns`
    /// nanoseconds.
    pub fn write_cdr<T: Serialize>(
        &mut self,
        channel: u16,
        ns: u64,
        msg: &T,
    ) -> Result<(), FileError> {
        let bytes = super::ros2::encode(msg).map_err(|reason| FileError {
            path: self.path.clone(),
            reason,
        })?;
        self.write(channel, ns, &bytes)
    }

    /// Writes the summary section and the footer; returns the whole file, not yet committed.
    pub fn finish(mut self) -> Result<Finished, FileError> {
        let path = self.path.clone();
        self.writer.finish().map_err(|e| error(&path, e))?;
        let mut sink = self.writer.into_inner();
        let bytes = sink.stream_position().map_err(|reason| FileError {
            path: path.clone(),
            reason,
        })?;
        let file = sink.into_inner().into_inner().map_err(|e| FileError {
            path: path.clone(),
            reason: e.into_error(),
        })?;
        Ok(Finished {
            file,
            bytes,
            messages: self.messages,
            message_bytes: self.message_bytes,
        })
    }
}

/// An error of the `mcap` crate as an error of the file `path`.
fn error(path: &Path, e: McapError) -> FileError {
    let reason = match e {
        McapError::Io(io) => io,
        other => std::io::Error::other(other.to_string()),
    };
    FileError {
        path: path.to_path_buf(),
        reason,
    }
}

/// One QoS profile in rosbag2's YAML form: reliable, volatile (or transient local when
/// `latched`), keep last 10 (1), the other policies at their defaults.
fn qos(latched: bool) -> String {
    let (durability, depth) = if latched {
        ("transient_local", 1)
    } else {
        ("volatile", 10)
    };
    let never = "\n    sec: 2147483647\n    nsec: 4294967295";
    format!(
        "- history: keep_last\n  depth: {depth}\n  reliability: reliable\n  durability: {durability}\n  deadline:{never}\n  lifespan:{never}\n  liveliness: automatic\n  liveliness_lease_duration:{never}\n  avoid_ros_namespace_conventions: false\n"
    )
}
