//! `replay.html`: writing a [`ReplayData`] into the self-contained page, and reading it back.
//!
//! The page is the template `assets/replay/replay.html` with its `@@NAME@@` markers replaced:
//! the style sheet (`replay.css`), the JSON header (`shoal-meta`, every `<` written as
//! `\u003c` so no string can end the element), the four arrays as base64 of little-endian
//! values (`shoal-pos`, `shoal-att`, `shoal-panel`, `shoal-links`, each in its own
//! `<script type="application/octet-stream">`), the vendored three.js bundle and the viewer:
//! three files, one after the other in the one `<script>` of the marker `VIEWER`, in this
//! order: `replay-data.js` (decoding the embedded data, formatting helpers), `replay-scene.js`
//! (the three.js scene and its per-frame update) and `replay.js` (state, controls, timeline,
//! panel and the render loop; it runs the viewer). All of them are embedded in the binary
//! with `include_str!`; nothing is loaded from anywhere when the page opens.
//!
//! Each link event is 16 bytes of `shoal-links`: t \[s\] (f32), sender (u32), receiver (u32)
//! and the outcome word (u32, [`LinkEvent::word`]): the [`super::Outcome`] code in its low bits,
//! and its top bit ([`super::ACK_BIT`], `0x8000_0000`) set when the frame was an
//! acknowledgement — drawn dashed, in its outcome's colour ([`crate::link_key::ACK_LABEL`],
//! which the header carries as `ack_label`). Pages written before the flag have it clear.
//!
//! [`write()`] streams the page through an [`AtomicFile`] (the arrays are converted and
//! base64-encoded in small chunks, never copied whole); [`read()`] parses a page back, for
//! tools that draw a replay without a browser.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use base64::Engine;
use base64::engine::general_purpose::STANDARD;
use base64::write::EncoderWriter;

use super::{LinkEvent, Meta, ReplayData};
use shoal_output::files::{AtomicFile, FileError};

/// Version of the vendored three.js (`assets/replay/three-<version>.min.js`).
pub const THREE_VERSION: &str = "0.187.0";

/// The page with `@@NAME@@` markers.
const TEMPLATE: &str = include_str!("../../assets/replay/replay.html");
/// The style sheet.
const CSS: &str = include_str!("../../assets/replay/replay.css");
/// The viewer, part 1: decoding the embedded data, formatting helpers.
const VIEWER_DATA: &str = include_str!("../../assets/replay/replay-data.js");
/// The viewer, part 2: the three.js scene and its per-frame update.
const VIEWER_SCENE: &str = include_str!("../../assets/replay/replay-scene.js");
/// The viewer, part 3: state, controls, timeline, panel, render loop (runs the other two).
const VIEWER: &str = include_str!("../../assets/replay/replay.js");
/// The viewer's files by name, in the order the page embeds them (each uses what the ones
/// before it define).
const VIEWER_FILES: [(&str, &str); 3] = [
    ("replay-data.js", VIEWER_DATA),
    ("replay-scene.js", VIEWER_SCENE),
    ("replay.js", VIEWER),
];
/// three.js and OrbitControls as one IIFE defining the global `THREE`.
const THREE: &str = include_str!("../../assets/replay/three-0.187.0.min.js");

/// Element ids of the embedded data.
const META_ID: &str = "shoal-meta";
const POS_ID: &str = "shoal-pos";
const ATT_ID: &str = "shoal-att";
const PANEL_ID: &str = "shoal-panel";
const LINKS_ID: &str = "shoal-links";

/// Bytes of one link event in the `links` array: t (f32), sender, receiver, outcome word
/// (u32: the outcome's code, the top bit set for an acknowledgement).
const LINK_BYTES: usize = 16;

/// Values converted per chunk while streaming an array.
const CHUNK: usize = 8192;

/// Writes `data` as the page `path` (through its temporary name; see [`shoal_output::files`]);
/// returns `path`. Data whose arrays disagree with the header ([`ReplayData::check`]) is
/// refused with an `InvalidData` error naming the file.
pub fn write(path: &Path, data: &ReplayData) -> Result<PathBuf, FileError> {
    data.check().map_err(|e| FileError {
        path: path.to_path_buf(),
        reason: io::Error::new(io::ErrorKind::InvalidData, format!("bad replay data: {e}")),
    })?;
    let mut f = AtomicFile::create(path)?;
    let written = {
        let mut w = BufWriter::with_capacity(1 << 16, &mut f);
        write_page(&mut w, data).and_then(|()| w.flush())
    };
    written.map_err(|e| f.error(e))?;
    f.commit()
}

/// Writes the page to `w`.
fn write_page(w: &mut impl Write, data: &ReplayData) -> io::Result<()> {
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("@@") {
        w.write_all(&rest.as_bytes()[..start])?;
        let after = &rest[start + 2..];
        let end = after
            .find("@@")
            .ok_or_else(|| io::Error::other("replay.html: a @@ marker is not closed"))?;
        write_part(w, &after[..end], data)?;
        rest = &after[end + 2..];
    }
    w.write_all(rest.as_bytes())
}

/// Writes what the template's marker `name` stands for.
fn write_part(w: &mut impl Write, name: &str, data: &ReplayData) -> io::Result<()> {
    match name {
        "CSS" => w.write_all(CSS.as_bytes()),
        "THREE" => w.write_all(THREE.as_bytes()),
        "VIEWER" => VIEWER_FILES.iter().try_for_each(|(_, text)| {
            w.write_all(text.as_bytes())?;
            w.write_all(b"\n")
        }),
        // The colour key is the page's: a replay as gathered has none yet.
        "META" if data.meta.outcomes.is_empty() || data.meta.ack_label.is_empty() => {
            let mut meta = data.meta.clone();
            super::fill_key(&mut meta);
            serde_json::to_writer(EscapeLt(&mut *w), &meta).map_err(io::Error::from)
        }
        "META" => serde_json::to_writer(EscapeLt(&mut *w), &data.meta).map_err(io::Error::from),
        "POS" => base64_of(w, &data.pos, |v, b| b.extend_from_slice(&v.to_le_bytes())),
        "ATT" => base64_of(w, &data.att, |v, b| b.extend_from_slice(&v.to_le_bytes())),
        "PANEL" => base64_of(w, &data.panel, |v, b| b.extend_from_slice(&v.to_le_bytes())),
        "LINKS" => base64_of(w, &data.links, |e, b| {
            b.extend_from_slice(&e.t.to_le_bytes());
            b.extend_from_slice(&e.from.to_le_bytes());
            b.extend_from_slice(&e.to.to_le_bytes());
            b.extend_from_slice(&e.word().to_le_bytes());
        }),
        other => Err(io::Error::other(format!(
            "replay.html: unknown marker @@{other}@@"
        ))),
    }
}

/// Writes `values` to `w` as base64 of their bytes (`bytes` appends one value's), converting
/// [`CHUNK`] values at a time.
fn base64_of<T>(
    w: &mut impl Write,
    values: &[T],
    bytes: impl Fn(&T, &mut Vec<u8>),
) -> io::Result<()> {
    let mut enc = EncoderWriter::new(w, &STANDARD);
    let mut buf = Vec::with_capacity(CHUNK * LINK_BYTES);
    for chunk in values.chunks(CHUNK) {
        buf.clear();
        for v in chunk {
            bytes(v, &mut buf);
        }
        enc.write_all(&buf)?;
    }
    enc.finish()?;
    Ok(())
}

/// A writer that writes every `<` as the JSON escape `\u003c` (valid anywhere `<` can occur
/// in JSON: inside strings), so embedded JSON cannot contain `</script` or `<!--`.
struct EscapeLt<W>(W);

impl<W: Write> Write for EscapeLt<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        for (i, part) in buf.split(|&b| b == b'<').enumerate() {
            if i > 0 {
                self.0.write_all(b"\\u003c")?;
            }
            self.0.write_all(part)?;
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

/// A replay page that could not be read: its name and what was wrong.
#[derive(Debug, thiserror::Error)]
#[error("cannot read replay {}: {what}", path.display())]
pub struct ReadError {
    /// The page.
    pub path: PathBuf,
    /// What was wrong (the OS reason, a missing element, bad JSON or base64, arrays that
    /// disagree with the header).
    pub what: String,
}

/// Reads the replay page `path` (as [`write()`] writes it) back into its data.
pub fn read(path: &Path) -> Result<ReplayData, ReadError> {
    let fail = |what: String| ReadError {
        path: path.to_path_buf(),
        what,
    };
    let page = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
    parse(&page).map_err(fail)
}

/// The data of the page text `page`.
fn parse(page: &str) -> Result<ReplayData, String> {
    let mut meta: Meta = serde_json::from_str(element(page, META_ID)?)
        .map_err(|e| format!("the header ({META_ID}) is not a replay header: {e}"))?;
    // A page written before the key travelled in its header.
    super::fill_key(&mut meta);
    let pos = decode(page, POS_ID, 2, |b| u16::from_le_bytes([b[0], b[1]]))?;
    let att = decode(page, ATT_ID, 2, |b| i16::from_le_bytes([b[0], b[1]]))?;
    let panel = decode(page, PANEL_ID, 4, |b| {
        f32::from_le_bytes([b[0], b[1], b[2], b[3]])
    })?;
    let raw = decode(page, LINKS_ID, LINK_BYTES, |b| {
        let word = |i: usize| [b[i], b[i + 1], b[i + 2], b[i + 3]];
        (
            f32::from_le_bytes(word(0)),
            u32::from_le_bytes(word(4)),
            u32::from_le_bytes(word(8)),
            u32::from_le_bytes(word(12)),
        )
    })?;
    let links = raw
        .into_iter()
        .enumerate()
        .map(|(i, (t, from, to, word))| {
            let (outcome, ack) = LinkEvent::outcome_of(word).ok_or_else(|| {
                format!("link event {i} has the unknown outcome word {word:#010x}")
            })?;
            Ok(LinkEvent {
                t,
                from,
                to,
                outcome,
                ack,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let data = ReplayData {
        meta,
        pos,
        att,
        panel,
        links,
    };
    data.check()?;
    Ok(data)
}

/// The text of the `<script … id="id">` element of `page`.
fn element<'a>(page: &'a str, id: &str) -> Result<&'a str, String> {
    let open = format!(" id=\"{id}\">");
    let start = page
        .find(&open)
        .ok_or_else(|| format!("no element {id} (not a shoal replay page?)"))?
        + open.len();
    let len = page[start..]
        .find("</script>")
        .ok_or_else(|| format!("the element {id} is not closed"))?;
    Ok(&page[start..start + len])
}

/// The base64 element `id` as values of `size` bytes each (`value` reads one).
fn decode<T>(
    page: &str,
    id: &str,
    size: usize,
    value: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, String> {
    let text = element(page, id)?;
    let bytes = STANDARD
        .decode(text.trim())
        .map_err(|e| format!("the array {id} is not base64: {e}"))?;
    if bytes.len() % size != 0 {
        return Err(format!(
            "the array {id} holds {} bytes, not whole values of {size} bytes",
            bytes.len()
        ));
    }
    Ok(bytes.chunks_exact(size).map(value).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::replay::Outcome;
    use crate::replay::demo::demo;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shoal-replay-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// Every event keeps its outcome and its acknowledgement flag (every third event is
    /// flagged here, of every outcome), the flag in the top bit of its outcome word.
    #[test]
    fn a_page_reads_back_as_written() {
        let d = dir("roundtrip");
        let mut data = demo(7, 4.0);
        data.meta.world = "a </script><!-- world & \"quotes\"".into();
        crate::replay::fill_key(&mut data.meta);
        for (k, e) in data.links.iter_mut().enumerate() {
            e.ack = k % 3 == 1;
        }
        for o in Outcome::ALL {
            let of = |ack| data.links.iter().any(|e| e.outcome == o && e.ack == ack);
            assert!(of(true) && of(false), "{o:?}: flagged and not");
        }
        let p = write(&d.join("replay.html"), &data).unwrap();
        let back = read(&p).unwrap();
        assert_eq!(back, data);
        // The words as the page holds them: the code, and the top bit for acknowledgements.
        let bytes = STANDARD
            .decode(element(&std::fs::read_to_string(&p).unwrap(), LINKS_ID).unwrap())
            .unwrap();
        assert_eq!(bytes.len(), LINK_BYTES * data.links.len());
        for (e, b) in data.links.iter().zip(bytes.chunks_exact(LINK_BYTES)) {
            let word = u32::from_le_bytes([b[12], b[13], b[14], b[15]]);
            let flag = if e.ack { 0x8000_0000 } else { 0 };
            assert_eq!(word, e.outcome.code() | flag, "{e:?}");
        }
        let page = std::fs::read_to_string(&p).unwrap();
        assert!(page.contains(r#"a \u003c/script>\u003c!-- world"#));
        assert!(!d.join(".replay.html.tmp").exists());
        let _ = std::fs::remove_dir_all(&d);
    }

    /// A replay as the world gathers it has no colour key: the page gets the one key of
    /// `crate::link_key`, by outcome code, in its header.
    #[test]
    fn a_gathered_replay_gets_the_colour_key_in_its_header() {
        let d = dir("key");
        let mut data = demo(3, 2.0);
        data.meta.outcomes.clear();
        data.meta.ack_label.clear();
        let back = read(&write(&d.join("replay.html"), &data).unwrap()).unwrap();
        assert_eq!(back.meta.ack_label, crate::link_key::ACK_LABEL);
        let key: Vec<(String, String)> = crate::link_key::LINK_KEY
            .iter()
            .map(|k| {
                let (r, g, b) = k.rgb;
                (k.label.to_string(), format!("#{r:02x}{g:02x}{b:02x}"))
            })
            .collect();
        let header: Vec<(String, String)> = back
            .meta
            .outcomes
            .iter()
            .map(|o| (o.name.clone(), o.color.clone()))
            .collect();
        assert_eq!(header, key);
        for (i, o) in back.meta.outcomes.iter().enumerate() {
            let code = Outcome::from_code(i as u32).unwrap();
            assert_eq!(o.name, crate::link_key::style(code).label);
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    /// The viewer writes no colour of a link outcome of its own: it takes them from the
    /// header (`meta.outcomes`, the one key of `crate::link_key`).
    #[test]
    fn the_viewer_takes_link_colours_from_the_header() {
        let page = [("replay.html", TEMPLATE), ("replay.css", CSS)];
        for (name, text) in page.into_iter().chain(VIEWER_FILES) {
            let lower = text.to_ascii_lowercase();
            for k in &crate::link_key::LINK_KEY {
                let hex = crate::link_key::hex(k.outcome);
                assert!(!lower.contains(&hex), "{name} writes {hex} ({})", k.label);
            }
        }
        assert!(VIEWER_DATA.contains("meta.outcomes"));
        // The legend's entry for acknowledgements comes from the header too.
        for (name, text) in VIEWER_FILES {
            let label = crate::link_key::ACK_LABEL;
            assert!(!text.contains(label), "{name} writes {label:?}");
        }
        assert!(VIEWER_DATA.contains("meta.ack_label"));
        assert!(
            !TEMPLATE.contains("style=\"background"),
            "replay.html has colour swatches of its own"
        );
    }

    #[test]
    fn every_marker_is_replaced() {
        let d = dir("markers");
        let p = write(&d.join("r.html"), &demo(2, 1.0)).unwrap();
        let page = std::fs::read_to_string(&p).unwrap();
        assert!(!page.contains("@@"), "a marker is left in the page");
        for id in [META_ID, POS_ID, ATT_ID, PANEL_ID, LINKS_ID] {
            assert_eq!(page.matches(&format!(" id=\"{id}\">")).count(), 1, "{id}");
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    /// The viewer's files are in the page, each once, after the three.js bundle, in the
    /// order of `VIEWER_FILES` (each uses what the ones before it define) and in one
    /// `<script>` element.
    #[test]
    fn the_viewer_files_are_embedded_in_order() {
        let d = dir("order");
        let p = write(&d.join("r.html"), &demo(2, 1.0)).unwrap();
        let page = std::fs::read_to_string(&p).unwrap();
        let mut after = page
            .find(THREE)
            .expect("the three.js bundle is in the page");
        for (k, (name, text)) in VIEWER_FILES.into_iter().enumerate() {
            assert_eq!(
                page.matches(text).count(),
                1,
                "{name} is not in the page once"
            );
            let at = page.find(text).unwrap();
            assert!(at > after, "{name} comes before the file it follows");
            assert!(
                k == 0 || !page[after..at].contains("<script"),
                "{name} is in a script element of its own"
            );
            after = at;
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn embedded_text_cannot_end_its_element() {
        let others = [("replay.css", CSS), ("three", THREE)];
        for (name, text) in others.into_iter().chain(VIEWER_FILES) {
            let lower = text.to_ascii_lowercase();
            for bad in ["</script", "</style", "<!--", "@@"] {
                assert!(!lower.contains(bad), "{name} contains {bad}");
            }
        }
        assert!(
            THREE.contains("@license"),
            "the MIT header of three.js is kept"
        );
        assert!(THREE.starts_with("var THREE=("), "an IIFE defining THREE");
    }

    /// Every `THREE.Name` the viewer's files use is an export of the bundle (the list in
    /// assets/replay/three-entry.js; scripts/vendor-three.sh rebuilds the bundle from it).
    #[test]
    fn the_bundle_exports_what_the_viewer_uses() {
        let mut missing = Vec::new();
        for (file, viewer) in VIEWER_FILES {
            for (i, _) in viewer.match_indices("THREE.") {
                let name: String = viewer[i + 6..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                let missed = format!("{name} ({file})");
                if !THREE.contains(&format!("{name}:()=>")) && !missing.contains(&missed) {
                    missing.push(missed);
                }
            }
        }
        assert!(
            missing.is_empty(),
            "not in the three.js bundle: {missing:?}"
        );
    }

    #[test]
    fn no_url_outside_the_page() {
        // The page's own parts (the bundle's license header names three's site in a comment).
        let page = [("replay.html", TEMPLATE), ("replay.css", CSS)];
        for (name, text) in page.into_iter().chain(VIEWER_FILES) {
            for bad in ["http://", "https://", "url(", "@import", "src=", "href="] {
                assert!(!text.contains(bad), "{name} contains {bad}");
            }
        }
    }

    #[test]
    fn bad_pages_are_errors_naming_the_file() {
        let d = dir("bad");
        let good = d.join("good.html");
        write(&good, &demo(3, 2.0)).unwrap();
        let page = std::fs::read_to_string(&good).unwrap();
        let links_at = page.find(" id=\"shoal-links\">").unwrap() + 18;
        let cases: Vec<(&str, String)> = vec![
            ("empty", String::new()),
            ("not a page", "<html><body>hello</body></html>".into()),
            (
                "bad json",
                page.replacen("{\"version\"", "{\"version\"x", 1),
            ),
            (
                "bad base64",
                page.replacen(" id=\"shoal-pos\">", " id=\"shoal-pos\">!!", 1),
            ),
            (
                "short array",
                page.replacen(" id=\"shoal-att\">", " id=\"shoal-att\">AAAA", 1),
            ),
            ("unclosed", page[..links_at + 10].to_string()),
            (
                "huge vehicle count",
                page.replacen("\"vehicles\":3,", "\"vehicles\":18446744073709551615,", 1)
                    .replacen("\"frames\":41,", "\"frames\":0,", 1),
            ),
            ("bad outcome", bad_word(&page, links_at, 9)),
            // A bit beside the acknowledgement flag.
            ("bad outcome bits", bad_word(&page, links_at, 0x4000_0000)),
            (
                "bad flagged outcome",
                bad_word(&page, links_at, 0x8000_0009),
            ),
        ];
        for (what, text) in cases {
            let p = d.join("bad.html");
            std::fs::write(&p, text).unwrap();
            let e = read(&p).unwrap_err();
            assert_eq!(e.path, p, "{what}");
            assert!(e.to_string().contains("bad.html"), "{what}: {e}");
        }
        let e = read(&d.join("missing.html")).unwrap_err();
        assert!(e.to_string().contains("missing.html"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// `page` with the first link event's outcome word (bytes 12..16; the array's text
    /// starts at `links_at`) set to `word`.
    fn bad_word(page: &str, links_at: usize, word: u32) -> String {
        let mut p = page.to_string();
        let b64 = element(page, LINKS_ID).unwrap();
        let mut bytes = STANDARD.decode(b64).unwrap();
        bytes[12..16].copy_from_slice(&word.to_le_bytes());
        p.replace_range(links_at..links_at + b64.len(), &STANDARD.encode(bytes));
        p
    }

    #[test]
    fn inconsistent_data_is_not_written() {
        let d = dir("inconsistent");
        let mut data = demo(3, 2.0);
        data.pos.pop();
        let p = d.join("r.html");
        let e = write(&p, &data).unwrap_err();
        assert_eq!(e.path, p);
        assert_eq!(e.reason.kind(), io::ErrorKind::InvalidData);
        assert!(!p.exists());
        let _ = std::fs::remove_dir_all(&d);
    }
}
