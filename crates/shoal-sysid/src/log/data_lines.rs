//! The line layer under the measured-run reader: a [`Read`] adapter that hands the CSV parser
//! only data lines, and maps the parser's line numbers back to the file's.
//!
//! * every line terminator (`\n`, `\r\n` or a lone `\r`) becomes `\n`;
//! * comment lines — the first character that is not a space or tab is `#` — and blank lines
//!   (nothing but spaces and tabs) are left out;
//! * a UTF-8 byte-order mark at the start of the file is dropped;
//! * a data line longer than [`MAX_LINE_BYTES`] is an error naming its line, so memory stays
//!   bounded by the rows whatever the file contains (comment lines may be of any length: they
//!   are never held).
//!
//! Why leave lines out instead of emptying them: the csv crate skips empty lines, but the
//! position it reports for a record is where it started looking — the line after the previous
//! record, before the empty lines. So the adapter drops them and keeps *marks*: the output line
//! where each run of data lines starts and its line in the file. [`LogLines::file_line`] turns
//! an output line into the file line; it is asked in increasing order and forgets the marks
//! behind it, so the marks held are only those of the bytes buffered ahead of the parser.
//!
//! One pass, constant work per byte: linear in the file size.

use std::collections::VecDeque;
use std::fmt;
use std::io::{self, BufRead, Read};

/// Longest data line accepted \[bytes\] (1 MiB).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The UTF-8 byte-order mark.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// A data line longer than [`MAX_LINE_BYTES`] (carried inside an [`io::Error`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineTooLong {
    /// 1-based line number in the file.
    pub line: usize,
}

impl fmt::Display for LineTooLong {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {} is longer than {} bytes (1 MiB), the longest line read",
            self.line, MAX_LINE_BYTES
        )
    }
}

impl std::error::Error for LineTooLong {}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// At the start of the file: checking for a byte-order mark (`n` of its bytes seen).
    Bom(usize),
    /// At the start of a line (after any leading blanks, which are held in `held`).
    LineStart,
    /// Emitting `held` (leading blanks of a data line, or a partial byte-order mark), then the
    /// rest of the line.
    Flush,
    /// Inside a data line.
    Data,
    /// Inside a comment line (discarded up to its terminator).
    Comment,
}

/// The adapter; see the module docs.
pub struct LogLines<R> {
    inner: R,
    state: State,
    /// Bytes of the current line not yet emitted (leading blanks; the line may still turn out
    /// to be a comment or blank).
    held: Vec<u8>,
    /// How many of `held` are emitted (state `Flush`).
    flushed: usize,
    /// The previous terminator was `\r`: a `\n` right after it belongs to it.
    skip_lf: bool,
    /// 1-based number of the current line in the file.
    line: usize,
    /// 1-based number of the current line in the output.
    out_line: u64,
    /// (output line, file line) where the file line minus the output line changes.
    marks: VecDeque<(u64, usize)>,
    /// Bytes of the current data line so far.
    line_len: usize,
    comment_lines: usize,
    blank_lines: usize,
}

impl<R: BufRead> LogLines<R> {
    /// Wraps a buffered reader.
    pub fn new(inner: R) -> Self {
        Self {
            inner,
            state: State::Bom(0),
            held: Vec::new(),
            flushed: 0,
            skip_lf: false,
            line: 1,
            out_line: 1,
            marks: VecDeque::new(),
            line_len: 0,
            comment_lines: 0,
            blank_lines: 0,
        }
    }

    /// Comment lines passed so far.
    pub fn comment_lines(&self) -> usize {
        self.comment_lines
    }

    /// Empty or blank (spaces and tabs only) lines passed so far.
    pub fn blank_lines(&self) -> usize {
        self.blank_lines
    }

    /// The file line of output line `out` (1-based). Ask in increasing order: marks before
    /// `out` are forgotten.
    pub fn file_line(&mut self, out: u64) -> usize {
        while self.marks.get(1).is_some_and(|m| m.0 <= out) {
            self.marks.pop_front();
        }
        match self.marks.front() {
            Some(&(o, f)) if o <= out => f.saturating_add((out - o) as usize),
            _ => out as usize,
        }
    }

    /// A data line starts: remember where it is when lines were left out before it.
    fn data_line_starts(&mut self) {
        let diff = self.line as u64 - self.out_line;
        let last = self.marks.back().map(|&(o, f)| f as u64 - o);
        if last != Some(diff) {
            self.marks.push_back((self.out_line, self.line));
        }
    }
}

fn too_long(line: usize) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, LineTooLong { line })
}

impl<R: BufRead> Read for LogLines<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        // A line ends; `emitted`: its `\n` went out. Written as a macro because the input
        // buffer borrows `self.inner` meanwhile.
        macro_rules! end_line {
            ($terminator:expr, $emitted:expr) => {{
                self.line += 1;
                if $emitted {
                    self.out_line += 1;
                }
                self.line_len = 0;
                self.skip_lf = $terminator == b'\r';
                self.state = State::LineStart;
            }};
        }
        let mut n = 0;
        while n < out.len() {
            if self.state == State::Flush {
                let rest = self.held.get(self.flushed..).unwrap_or_default();
                let k = rest.len().min(out.len() - n);
                out[n..n + k].copy_from_slice(&rest[..k]);
                n += k;
                self.flushed += k;
                if self.flushed >= self.held.len() {
                    self.held.clear();
                    self.flushed = 0;
                    self.state = State::Data;
                }
                continue;
            }
            let buf = self.inner.fill_buf()?;
            if buf.is_empty() {
                match self.state {
                    // A last line of blanks only is a blank line.
                    State::LineStart if !self.held.is_empty() => {
                        self.held.clear();
                        self.blank_lines += 1;
                    }
                    // A file that is a partial byte-order mark: those bytes are data.
                    State::Bom(k) if k > 0 => {
                        self.held = BOM[..k].to_vec();
                        self.data_line_starts();
                        self.state = State::Flush;
                        continue;
                    }
                    _ => {}
                }
                return Ok(n);
            }
            let mut i = 0;
            if self.skip_lf {
                self.skip_lf = false;
                if buf[0] == b'\n' {
                    i = 1;
                }
            }
            match self.state {
                State::Bom(k) => {
                    let mut k = k;
                    while k < BOM.len() && i < buf.len() && buf[i] == BOM[k] {
                        k += 1;
                        i += 1;
                    }
                    if k == BOM.len() {
                        self.state = State::LineStart;
                    } else if i < buf.len() {
                        // Not a byte-order mark: what was taken for one is data.
                        self.state = State::LineStart;
                        if k > 0 {
                            self.held = BOM[..k].to_vec();
                            self.data_line_starts();
                            self.state = State::Flush;
                        }
                    } else {
                        self.state = State::Bom(k);
                    }
                }
                State::LineStart => {
                    while i < buf.len() {
                        let b = buf[i];
                        match b {
                            b' ' | b'\t' => {
                                if self.held.len() >= MAX_LINE_BYTES {
                                    return Err(too_long(self.line));
                                }
                                self.held.push(b);
                                i += 1;
                            }
                            b'#' => {
                                self.held.clear();
                                self.comment_lines += 1;
                                self.state = State::Comment;
                                i += 1;
                                break;
                            }
                            b'\n' | b'\r' => {
                                self.held.clear();
                                self.blank_lines += 1;
                                i += 1;
                                end_line!(b, false);
                                // A `\n` after this `\r` may be in the same buffer.
                                if self.skip_lf && buf.get(i) == Some(&b'\n') {
                                    self.skip_lf = false;
                                    i += 1;
                                }
                            }
                            _ => {
                                self.line_len = self.held.len();
                                self.state = if self.held.is_empty() {
                                    State::Data
                                } else {
                                    State::Flush
                                };
                                // As in `data_line_starts`, inline: `buf` borrows `inner`.
                                let diff = self.line as u64 - self.out_line;
                                let last = self.marks.back().map(|&(o, f)| f as u64 - o);
                                if last != Some(diff) {
                                    self.marks.push_back((self.out_line, self.line));
                                }
                                break;
                            }
                        }
                    }
                }
                State::Data => {
                    let avail = &buf[i..];
                    let room = out.len() - n;
                    let lim = avail.len().min(room);
                    match avail[..lim].iter().position(|&b| b == b'\n' || b == b'\r') {
                        Some(p) => {
                            out[n..n + p].copy_from_slice(&avail[..p]);
                            out[n + p] = b'\n';
                            n += p + 1;
                            i += p + 1;
                            let t = avail[p];
                            end_line!(t, true);
                            if self.skip_lf && avail.get(p + 1) == Some(&b'\n') {
                                self.skip_lf = false;
                                i += 1;
                            }
                        }
                        None => {
                            out[n..n + lim].copy_from_slice(&avail[..lim]);
                            n += lim;
                            i += lim;
                            self.line_len += lim;
                            if self.line_len > MAX_LINE_BYTES {
                                self.inner.consume(i);
                                return Err(too_long(self.line));
                            }
                        }
                    }
                }
                State::Comment => match buf[i..].iter().position(|&b| b == b'\n' || b == b'\r') {
                    Some(p) => {
                        let t = buf[i + p];
                        i += p + 1;
                        end_line!(t, false);
                        if self.skip_lf && buf.get(i) == Some(&b'\n') {
                            self.skip_lf = false;
                            i += 1;
                        }
                    }
                    None => i = buf.len(),
                },
                State::Flush => {}
            }
            self.inner.consume(i);
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Filters `input` read in chunks of `chunk` bytes; returns the output, the file line of
    /// every output line, and the comment and blank line counts.
    fn filter(input: &[u8], chunk: usize) -> (String, Vec<usize>, usize, usize) {
        let mut f = LogLines::new(io::BufReader::with_capacity(chunk.max(1), input));
        let mut out = Vec::new();
        let mut buf = vec![0u8; chunk.max(1)];
        loop {
            let k = f.read(&mut buf).unwrap();
            if k == 0 {
                break;
            }
            out.extend_from_slice(&buf[..k]);
        }
        let text = String::from_utf8_lossy(&out).into_owned();
        let lines = (1..=text.lines().count() as u64)
            .map(|o| f.file_line(o))
            .collect();
        (text, lines, f.comment_lines(), f.blank_lines())
    }

    #[test]
    fn comments_and_blank_lines_are_left_out_and_lines_mapped() {
        let input = b"\xEF\xBB\xBF# head\r\nt,y\r\n  # indented\n\t\n0,1\r1,2\r\n   \n#\n2,3";
        for chunk in [1, 2, 3, 5, 64, 4096] {
            let (out, lines, comments, blanks) = filter(input, chunk);
            assert_eq!(out, "t,y\n0,1\n1,2\n2,3", "chunk {chunk}");
            assert_eq!(lines, vec![2, 5, 6, 9], "chunk {chunk}");
            assert_eq!((comments, blanks), (3, 2), "chunk {chunk}");
        }
    }

    #[test]
    fn leading_blanks_of_data_lines_are_kept() {
        let (out, lines, _, _) = filter(b"  t,\ty\n \t0,1\n", 2);
        assert_eq!(out, "  t,\ty\n \t0,1\n");
        assert_eq!(lines, vec![1, 2]);
    }

    #[test]
    fn a_partial_byte_order_mark_is_data() {
        for chunk in [1, 2, 64] {
            for input in [&b"\xEF\xBBt\n"[..], b"\xEF"] {
                let mut f = LogLines::new(io::BufReader::with_capacity(chunk, input));
                let mut out = Vec::new();
                f.read_to_end(&mut out).unwrap();
                assert_eq!(out, input, "chunk {chunk}");
            }
        }
    }

    #[test]
    fn an_over_long_data_line_names_its_line() {
        let mut input = b"# c\nt,y\n".to_vec();
        input.extend(std::iter::repeat_n(b'1', MAX_LINE_BYTES + 10));
        let mut f = LogLines::new(&input[..]);
        let mut out = Vec::new();
        let e = f.read_to_end(&mut out).unwrap_err();
        let inner = e.get_ref().and_then(|e| e.downcast_ref::<LineTooLong>());
        assert_eq!(inner, Some(&LineTooLong { line: 3 }));
        // An over-long comment is fine.
        let mut input = b"#".to_vec();
        input.extend(std::iter::repeat_n(b'x', MAX_LINE_BYTES + 10));
        input.extend_from_slice(b"\nt,y\n");
        let mut out = Vec::new();
        LogLines::new(&input[..]).read_to_end(&mut out).unwrap();
        assert_eq!(out, b"t,y\n");
    }
}
