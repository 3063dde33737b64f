//! Output files that appear whole or not at all. Every output of a run (summary, tables,
//! plots) is written through [`AtomicFile`]: to a hidden temporary name in the file's own
//! folder (`.<name>.tmp`), then flushed, synced to disk and renamed to its real name only
//! when complete ([`AtomicFile::commit`]). A file dropped before it is committed (a write
//! error, an early return) removes its temporary.
//!
//! So a reader never finds a truncated file under an output's name: after a full disk or a
//! file-size limit the file is simply absent (and the error names it with the OS reason, see
//! [`FileError`]); a process killed outright (SIGKILL, power loss) leaves at most a
//! `.<name>.tmp` behind, which the next run into the same folder overwrites.

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// An output file that could not be written: its (final) name and the OS reason.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {reason}", path.display())]
pub struct FileError {
    /// The file's final name.
    pub path: PathBuf,
    /// What the operating system said (e.g. "No space left on device", "File too large");
    /// part of the message, so it is not also a `source` (it would be printed twice).
    pub reason: io::Error,
}

/// The temporary name of the output `path`: `.<name>.tmp` in the same folder (a rename
/// within one folder is atomic).
pub fn temp_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.tmp"))
}

/// A file being written under its temporary name; see the module documentation.
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    /// `None` once committed.
    file: Option<File>,
}

impl AtomicFile {
    /// Creates (or truncates) the temporary of `path`.
    pub fn create(path: &Path) -> Result<Self, FileError> {
        let tmp = temp_name(path);
        let file = File::create(&tmp).map_err(|reason| FileError {
            path: path.to_path_buf(),
            reason,
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            file: Some(file),
        })
    }

    /// The final name.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `reason` as an error of this file.
    pub fn error(&self, reason: io::Error) -> FileError {
        FileError {
            path: self.path.clone(),
            reason,
        }
    }

    /// Syncs the temporary to disk and renames it to the final name; returns that name.
    pub fn commit(mut self) -> Result<PathBuf, FileError> {
        if let Some(f) = self.file.take() {
            let done = f.sync_all().and_then(|()| {
                drop(f);
                std::fs::rename(&self.tmp, &self.path)
            });
            if let Err(reason) = done {
                let _ = std::fs::remove_file(&self.tmp);
                return Err(self.error(reason));
            }
        }
        Ok(self.path.clone())
    }

    fn file(&mut self) -> io::Result<&mut File> {
        self.file
            .as_mut()
            .ok_or_else(|| io::Error::other("the file is already committed"))
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file()?.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file()?.flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes `bytes` as the whole file `path` (through its temporary); returns `path`.
pub fn write_whole(path: &Path, bytes: &[u8]) -> Result<PathBuf, FileError> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes).map_err(|e| f.error(e))?;
    f.commit()
}

/// A CSV table written through an [`AtomicFile`]: rows are whole by construction, the file
/// appears under its name at [`CsvFile::commit`], and errors name the file.
pub struct CsvFile {
    w: csv::Writer<AtomicFile>,
    path: PathBuf,
}

impl CsvFile {
    /// Starts the table `path` (its temporary).
    pub fn create(path: &Path) -> Result<Self, FileError> {
        let f = AtomicFile::create(path)?;
        Ok(Self {
            w: csv::WriterBuilder::new()
                .buffer_capacity(1 << 16)
                .from_writer(f),
            path: path.to_path_buf(),
        })
    }

    /// The final name.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends one row.
    pub fn write_record<I, T>(&mut self, record: I) -> Result<(), FileError>
    where
        I: IntoIterator<Item = T>,
        T: AsRef<[u8]>,
    {
        self.w
            .write_record(record)
            .map_err(|e| csv_error(&self.path, e))
    }

    /// Writes the rows still buffered and commits the file; returns its name.
    pub fn commit(mut self) -> Result<PathBuf, FileError> {
        self.w.flush().map_err(|reason| FileError {
            path: self.path.clone(),
            reason,
        })?;
        match self.w.into_inner() {
            Ok(f) => f.commit(),
            Err(e) => Err(FileError {
                path: self.path,
                reason: e.into_error(),
            }),
        }
    }
}

/// A CSV error of the table `path` as a [`FileError`] (writing records of strings can only
/// fail in the file system).
fn csv_error(path: &Path, e: csv::Error) -> FileError {
    let reason = match e.into_kind() {
        csv::ErrorKind::Io(io) => io,
        other => io::Error::other(format!("{other:?}")),
    };
    FileError {
        path: path.to_path_buf(),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shoal-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A file started and written in the fresh folder `name`; it is not committed yet, so
    /// only its temporary is there.
    fn started(name: &str, file: &str, text: &str) -> (PathBuf, PathBuf, AtomicFile) {
        let d = dir(name);
        let p = d.join(file);
        let mut f = AtomicFile::create(&p).unwrap();
        f.write_all(text.as_bytes()).unwrap();
        assert!(!p.exists());
        assert!(d.join(format!(".{file}.tmp")).exists());
        (d, p, f)
    }

    #[test]
    fn a_file_appears_only_when_committed() {
        let (d, p, f) = started("commit", "a.csv", "x,y\n1,2\n");
        assert_eq!(f.commit().unwrap(), p);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "x,y\n1,2\n");
        assert!(!d.join(".a.csv.tmp").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_dropped_file_leaves_nothing() {
        let (d, _, f) = started("drop", "b.json", "{");
        drop(f);
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn errors_name_the_final_file() {
        let d = dir("err");
        let p = d.join("missing-folder").join("c.png");
        let e = write_whole(&p, b"png").unwrap_err();
        assert_eq!(e.path, p);
        assert!(e.to_string().starts_with("cannot write "), "{e}");
        assert!(e.to_string().contains("c.png"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
