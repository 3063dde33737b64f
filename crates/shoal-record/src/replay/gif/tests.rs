//! Tests of the GIF renderer: synthetic runs drawn and decoded again.

use super::geometry::obstacle_outline;
use super::layout::{Layout, Panel, PanelKind};
use super::palette::{BG, GifPalette, OBSTACLE, TEXT, TRANSPARENT_INDEX, WATER, parse_hex};
use super::scene::Scene;
use super::*;
use crate::replay::{GroupMeta, LinkEvent, Meta, ObstacleMeta, Outcome, Timeline};
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

mod ack;

const POOL: [f64; 3] = [10.0, 8.0, 3.0];
const HULL: [f64; 3] = [0.6, 0.2, 0.15];
const COLORS: [&str; 3] = ["#1f77b4", "#ff7f0e", "#2ca02c"];

/// Start and end (x, y, z) \[m\] and attitude (roll, pitch, yaw) \[rad\] of each vehicle of
/// the synthetic run: one goes north, one east, one north and down.
fn paths() -> [([f64; 3], [f64; 3], [f64; 3]); 3] {
    [
        ([2.0, 2.0, 1.0], [8.0, 2.0, 1.0], [0.0, 0.0, 0.0]),
        ([2.0, 3.0, 1.5], [2.0, 7.0, 1.5], [0.0, 0.0, FRAC_PI_2]),
        (
            [4.0, 6.0, 0.5],
            [7.0, 6.0, 2.5],
            [0.0, -(2.0f64 / 3.0).atan(), 0.0],
        ),
    ]
}

fn ev(t: f32, from: u32, to: u32, outcome: Outcome) -> LinkEvent {
    LinkEvent {
        t,
        from,
        to,
        outcome,
        ack: false,
    }
}

/// A 20-s replay at 10 frames per second of three vehicles on straight paths (each its
/// own group), one vertical cylinder and a few link attempts.
fn synthetic() -> ReplayData {
    let (frames, dt) = (201usize, 0.1);
    let paths = paths();
    let n = paths.len();
    let mut pos = Vec::with_capacity(frames * n * 3);
    let mut att = Vec::with_capacity(frames * n * 3);
    for f in 0..frames {
        let s = f as f64 / (frames - 1) as f64;
        for (a, b, rpy) in &paths {
            for k in 0..3 {
                let p = a[k] + s * (b[k] - a[k]);
                pos.push((p / POOL[k] * 65535.0).round() as u16);
                att.push((rpy[k] / std::f64::consts::PI * 32767.0).round() as i16);
            }
        }
    }
    let meta = Meta {
        version: 1,
        world: "synthetic".into(),
        seed: 1,
        duration_s: 20.0,
        frame_dt: dt,
        panel_dt: 1.0,
        frames,
        vehicles: n,
        pool: POOL,
        obstacles: vec![ObstacleMeta {
            name: "pillar".into(),
            kind: "cylinder".into(),
            size: None,
            radius: Some(0.4),
            height: Some(3.0),
            position: [5.0, 4.0, 1.5],
            // Local y (the cylinder's axis) turned onto z: a vertical pillar.
            rotation: [FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2],
        }],
        groups: ["north", "east", "dive"]
            .iter()
            .zip(COLORS)
            .map(|(name, color)| GroupMeta {
                name: (*name).into(),
                color: color.into(),
                count: 1,
            })
            .collect(),
        group_of: vec![0, 1, 2],
        names: vec!["a".into(), "b".into(), "c".into()],
        hull: vec![HULL; 3],
        modem_range_m: 5.0,
        panel: Vec::new(),
        modes: Vec::new(),
        links_kept: 4,
        links_total: 4,
        timeline: Timeline::default(),
        outcomes: crate::replay::outcome_key(),
        ack_label: crate::link_key::ACK_LABEL.to_string(),
    };
    ReplayData {
        meta,
        pos,
        att,
        panel: Vec::new(),
        links: vec![
            ev(1.0, 0, 1, Outcome::Occluded),
            ev(10.0, 1, 2, Outcome::OutOfBudget),
            ev(19.8, 0, 2, Outcome::Delivered),
            ev(19.9, 2, 1, Outcome::Collided),
        ],
    }
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shoal-gif-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A decoded GIF: size, global palette, each frame composed on the canvas (palette
/// indices) and each frame's delay \[1/100 s\].
struct Decoded {
    w: usize,
    h: usize,
    palette: Vec<u8>,
    frames: Vec<Vec<u8>>,
    delays: Vec<u16>,
}

impl Decoded {
    fn rgb(&self, frame: usize, (x, y): (i32, i32)) -> [u8; 3] {
        let i = usize::from(self.frames[frame][y as usize * self.w + x as usize]);
        [
            self.palette[3 * i],
            self.palette[3 * i + 1],
            self.palette[3 * i + 2],
        ]
    }

    /// Pixels of colour `c` in frame `frame` inside `rect`: count, centroid, bounding box
    /// (x0, y0, x1, y1).
    fn blob(&self, frame: usize, rect: (i32, i32, i32, i32), c: RGBColor) -> Blob {
        let mut b = Blob {
            n: 0,
            cx: 0.0,
            cy: 0.0,
            bbox: (i32::MAX, i32::MAX, i32::MIN, i32::MIN),
        };
        for y in rect.1..rect.1 + rect.3 {
            for x in rect.0..rect.0 + rect.2 {
                if self.rgb(frame, (x, y)) == [c.0, c.1, c.2] {
                    b.n += 1;
                    b.cx += f64::from(x);
                    b.cy += f64::from(y);
                    b.bbox = (
                        b.bbox.0.min(x),
                        b.bbox.1.min(y),
                        b.bbox.2.max(x),
                        b.bbox.3.max(y),
                    );
                }
            }
        }
        b.cx /= b.n.max(1) as f64;
        b.cy /= b.n.max(1) as f64;
        b
    }
}

#[derive(Debug)]
struct Blob {
    n: usize,
    cx: f64,
    cy: f64,
    bbox: (i32, i32, i32, i32),
}

impl Blob {
    fn size(&self) -> (i32, i32) {
        (self.bbox.2 - self.bbox.0 + 1, self.bbox.3 - self.bbox.1 + 1)
    }
    fn centre(&self) -> (f64, f64) {
        (
            0.5 * f64::from(self.bbox.0 + self.bbox.2),
            0.5 * f64::from(self.bbox.1 + self.bbox.3),
        )
    }
}

fn decode(path: &Path) -> Decoded {
    let mut o = ::gif::DecodeOptions::new();
    o.set_color_output(::gif::ColorOutput::Indexed);
    let mut d = o.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (usize::from(d.width()), usize::from(d.height()));
    let palette = d.global_palette().unwrap().to_vec();
    let mut canvas = vec![0u8; w * h];
    let (mut frames, mut delays) = (Vec::new(), Vec::new());
    while let Some(f) = d.read_next_frame().unwrap() {
        assert_eq!(f.dispose, ::gif::DisposalMethod::Keep);
        let (fw, left, top) = (
            usize::from(f.width),
            usize::from(f.left),
            usize::from(f.top),
        );
        for (i, &c) in f.buffer.iter().enumerate() {
            if Some(c) != f.transparent {
                canvas[(top + i / fw) * w + left + i % fw] = c;
            }
        }
        frames.push(canvas.clone());
        delays.push(f.delay);
    }
    Decoded {
        w,
        h,
        palette,
        frames,
        delays,
    }
}

fn opts() -> GifOptions {
    GifOptions {
        width_px: 600,
        ..GifOptions::default()
    }
}

/// The frame count, size and timing follow from the options; the maps show the vehicles
/// where they are, turned as they head, east to the right and north up; obstacles and
/// links are drawn; no temporary is left.
#[test]
fn a_gif_shows_the_run_where_it_happened() {
    let d = dir("geometry");
    let path = d.join("run.gif");
    let data = synthetic();
    let opts = opts();
    assert_eq!(render(&data, &path, &opts).unwrap(), path);
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("run.gif")]);

    let gif = decode(&path);
    // 20 s at 4× and 10 fps: a frame every 0.4 s, at 0, 0.4, …, 20 s, each shown 0.1 s,
    // the last 2 s longer.
    assert_eq!(gif.frames.len(), 51);
    assert!(
        gif.delays[..50].iter().all(|&d| d == 10),
        "{:?}",
        gif.delays
    );
    assert_eq!(gif.delays[50], 10 + 200);
    let scene = Scene::new(&data, &path).unwrap();
    let lay = Layout::new(&scene, &opts);
    assert_eq!((gif.w, gif.h), (600, lay.size.1 as usize));
    let last = gif.frames.len() - 1;
    assert_ne!(gif.frames[0], gif.frames[last]);
    if let Ok(out) = std::env::var("SHOAL_GIF_DEBUG_PNG") {
        let mut img = Vec::new();
        for y in 0..gif.h {
            for x in 0..gif.w {
                img.extend(gif.rgb(last, (x as i32, y as i32)));
            }
        }
        image::save_buffer(
            &out,
            &img,
            gif.w as u32,
            gif.h as u32,
            image::ColorType::Rgb8,
        )
        .unwrap();
        std::fs::copy(&path, format!("{out}.gif")).unwrap();
    }

    let [top, side] = [lay.panels[0], lay.panels[1]];
    assert_eq!((top.kind, side.kind), (PanelKind::Top, PanelKind::Side));
    let ends = paths().map(|p| p.1);
    let color = |g: usize| parse_hex(COLORS[g]).unwrap();
    let rgb = |c: RGBColor| [c.0, c.1, c.2];
    // Each vehicle's own colour where the layout puts it, in both views.
    for (v, end) in ends.iter().enumerate() {
        assert_eq!(
            gif.rgb(last, top.px(*end)),
            rgb(color(v)),
            "vehicle {v} top"
        );
        assert_eq!(
            gif.rgb(last, side.px(*end)),
            rgb(color(v)),
            "vehicle {v} side"
        );
    }
    // The same, found from the pixels alone: the northbound vehicle (8, 2) is above the
    // eastbound one (2, 7), which is to its right, at equal scales (Δeast 5 m across,
    // Δnorth 6 m up).
    let blobs: Vec<Blob> = (0..3).map(|v| gif.blob(last, top.rect, color(v))).collect();
    assert!(blobs.iter().all(|b| b.n > 20), "{blobs:?}");
    let (north, east) = (&blobs[0], &blobs[1]);
    assert!(
        north.cy < east.cy - 100.0,
        "north is up: {north:?} {east:?}"
    );
    assert!(
        east.cx > north.cx + 100.0,
        "east is right: {north:?} {east:?}"
    );
    let ratio = (east.cx - north.cx) / (east.cy - north.cy);
    assert!((ratio - 5.0 / 6.0).abs() < 0.03, "aspect {ratio}");
    // Pointed bodies along the heading: long the way they go, the wide tail behind.
    let (nw, nh) = north.size();
    let (ew, eh) = east.size();
    assert!(nh > 2 * nw && ew > 2 * eh, "{north:?} {east:?}");
    assert!(north.cy > north.centre().1, "tail to the south: {north:?}");
    assert!(east.cx < east.centre().0, "tail to the west: {east:?}");
    // The hull's length at the map's scale.
    let len = HULL[0] * top.scale;
    assert!((f64::from(nh) - len).abs() < 3.0, "{nh} px for {len} px");
    // Side view: north to the right, depth down; the diver (7, depth 2.5) is below and
    // left of the northbound one (8, depth 1).
    let sb: Vec<Blob> = (0..3)
        .map(|v| gif.blob(last, side.rect, color(v)))
        .collect();
    assert!(
        sb[2].cy > sb[0].cy + 50.0 && sb[2].cx < sb[0].cx - 20.0,
        "{sb:?}"
    );
    assert!(sb[1].cx < sb[2].cx, "{sb:?}");

    // The pillar: filled at its centre, not beyond its radius.
    let grey = rgb(OBSTACLE);
    assert_eq!(gif.rgb(last, top.px([5.0, 4.0, 1.5])), grey);
    assert_eq!(gif.rgb(last, top.px([5.3, 4.0, 1.5])), grey);
    assert_eq!(gif.rgb(last, top.px([5.0, 4.3, 1.5])), grey);
    assert_ne!(gif.rgb(last, top.px([5.55, 4.0, 1.5])), grey);
    assert_eq!(gif.rgb(last, side.px([5.0, 4.0, 1.5])), grey);
    assert_ne!(gif.rgb(last, side.px([5.6, 4.0, 1.5])), grey);
    // Water inside the pool.
    assert_eq!(gif.rgb(last, top.px([6.3, 5.3, 1.0])), rgb(WATER));

    // Links of the last moments, each in its outcome's colour, near their midpoints; the
    // old ones are gone.
    let near = |panel: &Panel, a: [f64; 3], b: [f64; 3], c: RGBColor| {
        let m = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
        let (x, y) = panel.px(m);
        (-2..=2).any(|dy| (-2..=2).any(|dx| gif.rgb(last, (x + dx, y + dy)) == rgb(c)))
    };
    // The colours are the one key's (crate::link_key), read from its table.
    let key = |o: Outcome| {
        let (r, g, b) = crate::link_key::LINK_KEY[o.code() as usize].rgb;
        RGBColor(r, g, b)
    };
    let delivered = key(Outcome::Delivered);
    let collided = key(Outcome::Collided);
    assert!(near(&top, ends[0], ends[2], delivered));
    assert!(near(&top, ends[2], ends[1], collided));
    assert!(near(&side, ends[0], ends[2], delivered));
    assert!(!near(&top, ends[0], ends[1], key(Outcome::Occluded)));
    // The legend shows every outcome in its key colour: each colour is on the frame.
    let on_frame = |c: RGBColor| {
        (0..gif.h as i32).any(|y| (0..gif.w as i32).any(|x| gif.rgb(last, (x, y)) == rgb(c)))
    };
    for o in Outcome::ALL {
        assert!(on_frame(key(o)), "{o:?} is not drawn in its key colour");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Beyond `max_frames`, that many frames cover the whole run at the same speed.
#[test]
fn frames_are_capped_and_the_end_is_still_shown() {
    let d = dir("cap");
    let path = d.join("cap.gif");
    let data = synthetic();
    let opts = GifOptions {
        max_frames: 12,
        view: View::Top,
        ..opts()
    };
    render(&data, &path, &opts).unwrap();
    let gif = decode(&path);
    assert_eq!(gif.frames.len(), 12);
    // 5 s of playback from the first frame to the last, as uncapped.
    let total: u32 = gif.delays[..11].iter().map(|&d| u32::from(d)).sum();
    assert_eq!(total, 500);
    let scene = Scene::new(&data, &path).unwrap();
    let lay = Layout::new(&scene, &opts);
    assert_eq!(lay.panels.len(), 1);
    let c = parse_hex(COLORS[0]).unwrap();
    assert_eq!(gif.rgb(11, lay.panels[0].px(paths()[0].1)), [c.0, c.1, c.2]);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_side_view_alone_renders() {
    let d = dir("side");
    let path = d.join("side.gif");
    let opts = GifOptions {
        view: View::Side,
        max_frames: 3,
        links: false,
        trail_s: 0.0,
        ..opts()
    };
    render(&synthetic(), &path, &opts).unwrap();
    let gif = decode(&path);
    assert_eq!(gif.frames.len(), 3);
    let _ = std::fs::remove_dir_all(&d);
}

/// Empty or inconsistent replays and bad options are errors naming the file; nothing is
/// written.
#[test]
fn bad_input_is_an_error_not_a_panic() {
    let d = dir("errors");
    let path = d.join("bad.gif");
    let mut empty = synthetic();
    empty.meta.frames = 0;
    empty.pos.clear();
    empty.att.clear();
    let e = render(&empty, &path, &opts()).unwrap_err();
    assert!(matches!(e, RenderError::Empty { .. }), "{e}");
    assert!(
        e.to_string().contains("bad.gif") && e.to_string().contains("empty"),
        "{e}"
    );
    let mut none = synthetic();
    none.meta.vehicles = 0;
    assert!(matches!(
        render(&none, &path, &opts()),
        Err(RenderError::Empty { .. })
    ));
    let mut short = synthetic();
    short.pos.pop();
    let e = render(&short, &path, &opts()).unwrap_err();
    assert!(e.to_string().contains("`pos`"), "{e}");
    let mut group = synthetic();
    group.meta.group_of[1] = 7;
    let e = render(&group, &path, &opts()).unwrap_err();
    assert!(e.to_string().contains("group 7"), "{e}");
    for (o, field) in [
        (GifOptions { fps: 0.0, ..opts() }, "fps"),
        (
            GifOptions {
                fps: 100.0,
                ..opts()
            },
            "fps",
        ),
        (
            GifOptions {
                speed: f64::NAN,
                ..opts()
            },
            "speed",
        ),
        (
            GifOptions {
                width_px: 10,
                ..opts()
            },
            "width_px",
        ),
        (
            GifOptions {
                max_frames: 0,
                ..opts()
            },
            "max_frames",
        ),
        (
            GifOptions {
                max_frames: usize::MAX,
                ..opts()
            },
            "max_frames",
        ),
        (
            GifOptions {
                trail_s: -1.0,
                ..opts()
            },
            "trail_s",
        ),
    ] {
        let e = render(&synthetic(), &path, &o).unwrap_err();
        assert!(matches!(e, RenderError::Options { .. }), "{e}");
        assert!(
            e.to_string().contains(field) && e.to_string().contains("bad.gif"),
            "{e}"
        );
    }
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0);
    // A folder that does not exist: the file system's reason, with the file's name.
    let missing = d.join("no-such-folder").join("x.gif");
    let e = render(&synthetic(), &missing, &opts()).unwrap_err();
    assert!(matches!(e, RenderError::File(_)), "{e}");
    assert!(e.to_string().contains("x.gif"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_schedule_keeps_the_playback_clock() {
    let o = GifOptions::default();
    // 100 s at 4× and 10 fps: 0, 0.4, …, 100 s.
    let (t, d) = schedule(100.0, &o);
    assert_eq!(t.len(), 251);
    assert!((t[250] - 100.0).abs() < 1e-9);
    assert!(d[..250].iter().all(|&d| d == 10) && d[250] == 10 + 200);
    // The last frame at 99.9 s: the 100-s frame is not there.
    assert_eq!(schedule(99.9, &o).0.len(), 250);
    // 15 fps: delays of 6 and 7 hundredths that add up to the exact clock.
    let (t, d) = schedule(
        30.0,
        &GifOptions {
            fps: 15.0,
            ..o.clone()
        },
    );
    assert_eq!(t.len(), 113);
    let sum: u32 = d[..112].iter().map(|&d| u32::from(d)).sum();
    assert_eq!(sum, (112.0f64 * 100.0 / 15.0).round() as u32);
    assert!(d[..112].iter().all(|&d| d == 6 || d == 7));
    // Capped: the whole run in 5 frames, the same playback time.
    let (t, d) = schedule(
        100.0,
        &GifOptions {
            max_frames: 5,
            ..o.clone()
        },
    );
    assert_eq!(t, vec![0.0, 25.0, 50.0, 75.0, 100.0]);
    assert_eq!(d, vec![625, 625, 625, 625, 625 + 200]);
    // A speed that would take more frames than there are numbers: capped.
    let tiny = GifOptions {
        speed: 1e-300,
        max_frames: 3,
        ..o.clone()
    };
    assert_eq!(schedule(100.0, &tiny).0, vec![0.0, 50.0, 100.0]);
    // One frame: the end.
    let (t, _) = schedule(100.0, &GifOptions { max_frames: 1, ..o });
    assert_eq!(t, vec![100.0]);
}

#[test]
fn every_palette_colour_maps_to_itself() {
    let data = synthetic();
    let scene = Scene::new(&data, Path::new("x.gif")).unwrap();
    let mut colors = vec![BG, TEXT, OBSTACLE, WATER];
    colors.extend(scene.groups.iter().map(|g| g.color));
    colors.extend((0..32u8).map(|i| RGBColor(i * 8, i * 8, i * 8)));
    let p = GifPalette::new(&colors);
    for i in 0..p.len {
        let c = [p.rgb[3 * i], p.rgb[3 * i + 1], p.rgb[3 * i + 2]];
        assert_eq!(usize::from(p.index(c)), i, "{c:?}");
    }
    // A colour off the palette goes to its nearest entry, never to the transparent one.
    let blue = p.index([31, 119, 180]);
    assert_eq!(p.index([35, 115, 185]), blue);
    assert!((0..=255u8).all(|v| p.index([v, 255 - v, v / 2]) != TRANSPARENT_INDEX));
}

#[test]
fn obstacle_outlines_follow_shape_and_pose() {
    let o = |kind: &str, rotation: [f64; 4]| ObstacleMeta {
        name: "o".into(),
        kind: kind.into(),
        size: Some([2.0, 1.0, 0.5]),
        radius: Some(0.5),
        height: Some(2.0),
        position: [3.0, 4.0, 1.0],
        rotation,
    };
    let ident = [0.0, 0.0, 0.0, 1.0];
    let extent = |pts: &[(f64, f64)]| {
        let f = |g: fn(&(f64, f64)) -> f64| {
            let v: Vec<f64> = pts.iter().map(g).collect();
            (
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            )
        };
        (f(|p| p.0), f(|p| p.1))
    };
    let close = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
    // A box 2 m along x (north, up in the top view), 1 m along y (east, across).
    let (h, v) = extent(&obstacle_outline(&o("box", ident), PanelKind::Top).unwrap());
    assert!(close(h, (3.5, 4.5)) && close(v, (2.0, 4.0)), "{h:?} {v:?}");
    // Turned 90° about z (down): now 2 m along east.
    let s = FRAC_1_SQRT_2;
    let (h, v) = extent(&obstacle_outline(&o("box", [0.0, 0.0, s, s]), PanelKind::Top).unwrap());
    assert!(close(h, (3.0, 5.0)) && close(v, (2.5, 3.5)), "{h:?} {v:?}");
    // A cylinder with its axis (local y) untouched lies along east: 2 m across from above,
    // a 1-m disc seen from the side.
    let (h, v) = extent(&obstacle_outline(&o("cylinder", ident), PanelKind::Top).unwrap());
    assert!(close(h, (3.0, 5.0)) && close(v, (2.5, 3.5)), "{h:?} {v:?}");
    let (h, v) = extent(&obstacle_outline(&o("cylinder", ident), PanelKind::Side).unwrap());
    assert!(close(h, (2.5, 3.5)) && close(v, (0.5, 1.5)), "{h:?} {v:?}");
    // A capsule along z: 3 m tall from the side (2 m straight + two 0.5-m caps).
    let (_, v) = extent(&obstacle_outline(&o("capsule", ident), PanelKind::Side).unwrap());
    assert!(close(v, (-0.5, 2.5)), "{v:?}");
    // Unknown kinds, missing sizes and bad rotations are skipped, not drawn wrong.
    assert!(obstacle_outline(&o("torus", ident), PanelKind::Top).is_none());
    assert!(obstacle_outline(&o("box", [0.0; 4]), PanelKind::Top).is_none());
    let mut no_r = o("sphere", ident);
    no_r.radius = None;
    assert!(obstacle_outline(&no_r, PanelKind::Top).is_none());
}

#[test]
fn a_crowded_swarm_is_drawn_as_separate_vehicles() {
    // 2,500 vehicles on a 1.2 m grid in a 62 × 62 m pool, on a 240-px map (≈ 3 px/m): grid
    // neighbours are ≈ 3.5 px apart, so at MIN_BODY_PX (9 px) the swarm would merge into one
    // blot. Drawn at 0.6 × the side of each vehicle's share of the map (≈ 2 px), water stays
    // visible between them.
    let mut data = crate::replay::demo::demo(2500, 1.0);
    let pool = [62.0, 62.0, 3.0];
    data.meta.pool = pool;
    data.meta.obstacles.clear();
    for k in 0..data.meta.frames {
        for v in 0..2500 {
            let (x, y) = (1.0 + 1.2 * (v % 50) as f64, 1.0 + 1.2 * (v / 50) as f64);
            let i = (k * 2500 + v) * 3;
            data.pos[i] = (x / pool[0] * 65535.0).round() as u16;
            data.pos[i + 1] = (y / pool[1] * 65535.0).round() as u16;
            data.pos[i + 2] = (1.5 / pool[2] * 65535.0).round() as u16;
        }
    }
    let d = dir("crowded");
    let path = d.join("crowded.gif");
    let opts = GifOptions {
        view: View::Top,
        width_px: 240,
        trail_s: 0.0,
        links: false,
        ..GifOptions::default()
    };
    render(&data, &path, &opts).unwrap();
    let gif = decode(&path);
    let scene = Scene::new(&data, &path).unwrap();
    let lay = Layout::new(&scene, &opts);
    let top = lay.panels[0];
    let (x0, y0, w, h) = top.rect;
    let (mut water, mut all) = (0usize, 0usize);
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            all += 1;
            if gif.rgb(0, (x, y)) == [WATER.0, WATER.1, WATER.2] {
                water += 1;
            }
        }
    }
    eprintln!("crowded: {water} of {all} map pixels show water");
    assert!(
        water * 5 > all,
        "only {water} of {all} map pixels show water between the vehicles"
    );
    let _ = std::fs::remove_dir_all(&d);
}
