//! Drawing a frame: the hard-edged backend, the still background (water, pool, obstacles, ticks, legend) and the moving parts (vehicles, trails, link lines — acknowledgements dashed —, title).

use super::geometry::{
    ACK_DASH_PX, body_points, clip_convex, convex_hull, dashes, obstacle_outline, tick_label,
    tick_step,
};
use super::layout::{
    ACK_SAMPLE, LEFT_W, LEGEND_FONT, LEGEND_ROW, LEGEND_SAMPLE, Layout, LegendEntry, Panel,
    PanelKind, RIGHT_W, TITLE_H,
};
use super::options::{CROWDED_BODY_SHARE, GifOptions, LINK_WINDOW_S, MIN_BODY_PX};
use super::palette::{
    BG, FRAME, GRID, OBSTACLE, OBSTACLE_EDGE, OUTCOMES, OUTSIDE, SURFACE, TEXT, TEXT_GREY, WALL,
    WATER, outcome_color,
};
use super::scene::Scene;
use nalgebra::{Rotation3, Vector3};
use plotters::backend::{BitMapBackend, RGBPixel};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendColor, BackendCoord, DrawingErrorKind};
use shoal_output::plot::clip_polyline;

// Through its path: its style traits' methods would clash with plotters' `Color`.
use plotters_backend as backend;

/// A plotters error as text.
pub(super) fn de<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    e.to_string()
}

/// The bitmap the GIF is drawn on: plotters' RGB bitmap with hard-edged shapes. plotters
/// blends the edge pixels of lines and polygons with what lies under them, and in a palette
/// image such blends go to unrelated entries (the edge of a teal link to a group's blue);
/// here an edge pixel is drawn in full where it is at least half covered, else not at all.
/// Text keeps its smooth edges: black or grey on white, which the grey ramp holds.
pub(super) struct Crisp<'a>(BitMapBackend<'a, RGBPixel>);

pub(super) type CrispError<'a> =
    DrawingErrorKind<<BitMapBackend<'a, RGBPixel> as DrawingBackend>::ErrorType>;

impl<'a> DrawingBackend for Crisp<'a> {
    type ErrorType = <BitMapBackend<'a, RGBPixel> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), CrispError<'a>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), CrispError<'a>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), CrispError<'a>> {
        if color.alpha < 0.5 {
            return Ok(());
        }
        self.0.draw_pixel(
            point,
            BackendColor {
                alpha: 1.0,
                rgb: color.rgb,
            },
        )
    }

    fn draw_rect<S: backend::BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), CrispError<'a>> {
        // Axis-aligned: hard edges already, and the bitmap's own fill is fast.
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_text<T: backend::BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), CrispError<'a>> {
        self.0.draw_text(text, style, pos)
    }

    fn estimate_text_size<T: backend::BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), CrispError<'a>> {
        self.0.estimate_text_size(text, style)
    }
}

pub(super) type Area<'a> = DrawingArea<Crisp<'a>, Shift>;

/// An RGB buffer of `size` as a drawing area.
pub(super) fn area_of(buf: &mut [u8], size: (u32, u32)) -> Result<Area<'_>, String> {
    BitMapBackend::<RGBPixel>::with_buffer_and_format(buf, size)
        .map(|b| Crisp(b).into_drawing_area())
        .map_err(|e| e.to_string())
}

pub(super) fn rect_px(p: &Panel, h: (f64, f64), v: (f64, f64)) -> [(i32, i32); 2] {
    let a = p.px_i((h.0.max(p.h.0), v.0.max(p.v.0)));
    let b = p.px_i((h.1.min(p.h.1), v.1.min(p.v.1)));
    [(a.0.min(b.0), a.1.min(b.1)), (a.0.max(b.0), a.1.max(b.1))]
}

/// Whether the map ranges `h` × `v` overlap the panel's.
pub(super) fn overlaps(p: &Panel, h: (f64, f64), v: (f64, f64)) -> bool {
    h.0 < p.h.1 && h.1 > p.h.0 && v.0 < p.v.1 && v.1 > p.v.0
}

/// Draws what does not change: maps with water, walls, obstacles, grid and ticks, and the
/// legend.
pub(super) fn draw_background(area: &Area, scene: &Scene, lay: &Layout) -> Result<(), String> {
    area.fill(&BG).map_err(de)?;
    let pool = scene.pool;
    let small = |c: RGBColor| ("sans-serif", 11).into_font().color(&c);
    for p in &lay.panels {
        let (x0, y0, w, h) = p.rect;
        let full = [(x0, y0), (x0 + w, y0 + h)];
        area.draw(&Rectangle::new(full, OUTSIDE.filled()))
            .map_err(de)?;
        let (water_v, caption) = match p.kind {
            PanelKind::Top => (
                (0.0, pool[0]),
                "from above: north x ↑, east y → [m]".to_string(),
            ),
            PanelKind::Side => (
                (0.0, pool[2]),
                "from the east: north x →, depth z ↓ [m]".to_string(),
            ),
        };
        let water_h = match p.kind {
            PanelKind::Top => (0.0, pool[1]),
            PanelKind::Side => (0.0, pool[0]),
        };
        if p.kind == PanelKind::Side && p.v.0 < 0.0 {
            // Air above the surface.
            area.draw(&Rectangle::new(rect_px(p, p.h, (p.v.0, 0.0)), BG.filled()))
                .map_err(de)?;
        }
        if overlaps(p, water_h, water_v) {
            area.draw(&Rectangle::new(
                rect_px(p, water_h, water_v),
                WATER.filled(),
            ))
            .map_err(de)?;
        }
        // Grid and ticks.
        let hs = tick_step(p.h.1 - p.h.0, f64::from(w));
        let vs = tick_step(p.v.1 - p.v.0, f64::from(h));
        let ticks = |r: (f64, f64), s: f64| {
            let first = (r.0 / s).ceil() as i64;
            let last = (r.1 / s).floor() as i64;
            (first..=last).map(move |i| i as f64 * s)
        };
        for t in ticks(p.h, hs) {
            let (x, _) = p.px_i((t, p.v.0));
            area.draw(&PathElement::new(vec![(x, y0), (x, y0 + h)], GRID))
                .map_err(de)?;
            area.draw(&PathElement::new(vec![(x, y0 + h), (x, y0 + h + 4)], FRAME))
                .map_err(de)?;
            area.draw(&Text::new(
                tick_label(t, hs),
                (x, y0 + h + 6),
                small(TEXT_GREY).pos(Pos::new(HPos::Center, VPos::Top)),
            ))
            .map_err(de)?;
        }
        for t in ticks(p.v, vs) {
            let (_, y) = p.px_i((p.h.0, t));
            area.draw(&PathElement::new(vec![(x0, y), (x0 + w, y)], GRID))
                .map_err(de)?;
            area.draw(&PathElement::new(vec![(x0 - 4, y), (x0, y)], FRAME))
                .map_err(de)?;
            area.draw(&Text::new(
                tick_label(t, vs),
                (x0 - 6, y),
                small(TEXT_GREY).pos(Pos::new(HPos::Right, VPos::Center)),
            ))
            .map_err(de)?;
        }
        // Obstacles.
        for o in &scene.data.meta.obstacles {
            let Some(outline) = obstacle_outline(o, p.kind) else {
                continue;
            };
            let clipped = clip_convex(&outline, p.h, p.v);
            if clipped.len() < 3 {
                continue;
            }
            let mut pts: Vec<(i32, i32)> = clipped.iter().map(|&q| p.px_i(q)).collect();
            area.draw(&Polygon::new(pts.clone(), OBSTACLE.filled()))
                .map_err(de)?;
            pts.push(pts[0]);
            area.draw(&PathElement::new(pts, OBSTACLE_EDGE))
                .map_err(de)?;
        }
        // Walls (and the surface, from the side).
        let walls: Vec<(f64, f64)> = match p.kind {
            PanelKind::Top => vec![
                (0.0, 0.0),
                (pool[1], 0.0),
                (pool[1], pool[0]),
                (0.0, pool[0]),
                (0.0, 0.0),
            ],
            PanelKind::Side => vec![
                (0.0, 0.0),
                (0.0, pool[2]),
                (pool[0], pool[2]),
                (pool[0], 0.0),
            ],
        };
        for piece in clip_polyline(&walls, p.h, p.v) {
            let px: Vec<(i32, i32)> = piece.iter().map(|&q| p.px_i(q)).collect();
            area.draw(&PathElement::new(px, WALL.stroke_width(2)))
                .map_err(de)?;
        }
        if p.kind == PanelKind::Side {
            for piece in clip_polyline(&[(0.0, 0.0), (pool[0], 0.0)], p.h, p.v) {
                let px: Vec<(i32, i32)> = piece.iter().map(|&q| p.px_i(q)).collect();
                area.draw(&PathElement::new(px, SURFACE.stroke_width(2)))
                    .map_err(de)?;
            }
        }
        area.draw(&Rectangle::new(full, FRAME.stroke_width(1)))
            .map_err(de)?;
        area.draw(&Text::new(
            caption,
            (x0, y0 - 4),
            ("sans-serif", 13)
                .into_font()
                .color(&TEXT_GREY)
                .pos(Pos::new(HPos::Left, VPos::Bottom)),
        ))
        .map_err(de)?;
    }
    draw_legend(area, lay)
}

/// Draws the legend: group swatches, the link outcomes' lines and the dashed sample of
/// acknowledgement frames, each with its label.
fn draw_legend(area: &Area, lay: &Layout) -> Result<(), String> {
    let font = ("sans-serif", LEGEND_FONT).into_font();
    for (e, x, y) in &lay.legend {
        let yc = y + LEGEND_ROW / 2;
        let text_at = |s: &str, x: i32, c: RGBColor| {
            area.draw(&Text::new(
                s.to_string(),
                (x, yc),
                font.clone()
                    .color(&c)
                    .pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(de)
        };
        match e {
            LegendEntry::Group(c, s) => {
                area.draw(&Rectangle::new(
                    [(x + 2, yc - 5), (x + LEGEND_SAMPLE - 2, yc + 5)],
                    c.filled(),
                ))
                .map_err(de)?;
                text_at(s, x + LEGEND_SAMPLE + 5, TEXT)?;
            }
            LegendEntry::Link(c, s) => {
                area.draw(&PathElement::new(
                    vec![(*x, yc), (x + LEGEND_SAMPLE, yc)],
                    c.stroke_width(2),
                ))
                .map_err(de)?;
                text_at(s, x + LEGEND_SAMPLE + 5, TEXT)?;
            }
            LegendEntry::Ack(s) => {
                let (a, b) = (
                    (f64::from(*x), f64::from(yc)),
                    (f64::from(x + ACK_SAMPLE), f64::from(yc)),
                );
                for d in dashes(a, b, ACK_DASH_PX) {
                    area.draw(&PathElement::new(d.to_vec(), TEXT.stroke_width(2)))
                        .map_err(de)?;
                }
                text_at(s, x + ACK_SAMPLE + 5, TEXT)?;
            }
            LegendEntry::Note(s) => text_at(s, *x, TEXT_GREY)?,
        }
    }
    Ok(())
}

/// What changes from frame to frame, drawn over the background.
pub(super) struct Dynamic<'s> {
    pub(super) scene: &'s Scene<'s>,
    pub(super) opts: &'s GifOptions,
    /// Per group: the body's corners in the body frame \[m\].
    pub(super) bodies: Vec<[Vector3<f64>; 10]>,
    /// Trail length in replay frames, and the step between trail points.
    pub(super) trail: (usize, usize),
    /// Link window \[s\].
    pub(super) window: f64,
    /// Scratch.
    pub(super) pts: Vec<(f64, f64)>,
    pub(super) hull: Vec<(i32, i32)>,
}

impl<'s> Dynamic<'s> {
    pub(super) fn new(scene: &'s Scene<'s>, opts: &'s GifOptions) -> Self {
        let frames = (opts.trail_s / scene.dt).round() as usize;
        let step = frames.div_ceil(24).max(1);
        Self {
            scene,
            opts,
            bodies: scene.groups.iter().map(|g| body_points(g.hull)).collect(),
            trail: (frames, step),
            window: LINK_WINDOW_S.max(opts.speed / opts.fps),
            pts: Vec::with_capacity(16),
            hull: Vec::with_capacity(16),
        }
    }

    pub(super) fn draw(&mut self, area: &Area, lay: &Layout, t: f64) -> Result<(), String> {
        let scene = self.scene;
        let f = scene.frame_at(t);
        let n = scene.vehicles;
        let thin = n > 60;
        for p in &lay.panels {
            // Trails.
            let (len, step) = self.trail;
            if len > 0 && f > 0 {
                let first = f.saturating_sub(len);
                for v in 0..n {
                    let mut line: Vec<(i32, i32)> = (first..f)
                        .step_by(step)
                        .map(|k| p.px(scene.pos(k, v)))
                        .collect();
                    line.push(p.px(scene.pos(f, v)));
                    let c = scene.groups[scene.group_of[v]].trail;
                    area.draw(&PathElement::new(
                        line,
                        c.stroke_width(if thin { 1 } else { 2 }),
                    ))
                    .map_err(de)?;
                }
            }
            if self.opts.links {
                self.draw_links(area, p, f, t)?;
            }
            // Bodies: enlarged to MIN_BODY_PX, or in a crowded map to 0.6 × the side of each
            // vehicle's share of the panel (at least 2 px), so a dense swarm does not merge
            // into one blot.
            let share = f64::from(p.rect.2) * f64::from(p.rect.3) / n.max(1) as f64;
            let min_px = MIN_BODY_PX.min((CROWDED_BODY_SHARE * share.sqrt()).max(2.0));
            for v in 0..n {
                let g = scene.group_of[v];
                let hull = scene.groups[g].hull;
                let grow = (min_px / (hull[0] * p.scale)).max(1.0);
                let [roll, pitch, yaw] = scene.att(f, v);
                let r = Rotation3::from_euler_angles(roll, pitch, yaw);
                let c = Vector3::from(scene.pos(f, v));
                self.pts.clear();
                for b in &self.bodies[g] {
                    let w = c + r * (b * grow);
                    self.pts.push(p.px_hv(p.hv([w.x, w.y, w.z])));
                }
                convex_hull(&mut self.pts, &mut self.hull);
                let color = scene.groups[g].color;
                area.draw(&Polygon::new(self.hull.clone(), color.filled()))
                    .map_err(de)?;
            }
        }
        // Title.
        let meta = &scene.data.meta;
        area.draw(&Text::new(
            format!("{}   t = {:.1} s", meta.world, t),
            (LEFT_W, TITLE_H / 2),
            ("sans-serif", 17)
                .into_font()
                .color(&TEXT)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(de)?;
        let speed = format!("{}× speed", trim(self.opts.speed));
        area.draw(&Text::new(
            speed,
            (lay.size.0 as i32 - RIGHT_W, TITLE_H / 2),
            ("sans-serif", 13)
                .into_font()
                .color(&TEXT_GREY)
                .pos(Pos::new(HPos::Right, VPos::Center)),
        ))
        .map_err(de)?;
        Ok(())
    }

    /// The link attempts of the window before `t` \[s\] on panel `p`, between the vehicles'
    /// positions in replay frame `f`: each in its outcome's colour, losses over deliveries,
    /// acknowledgement frames dashed ([`ACK_DASH_PX`]).
    fn draw_links(&self, area: &Area, p: &Panel, f: usize, t: f64) -> Result<(), String> {
        let scene = self.scene;
        let n = scene.vehicles;
        let events = scene.links_in(t - self.window, t);
        for o in OUTCOMES {
            let c = outcome_color(o);
            for e in events.iter().filter(|e| e.outcome == o) {
                let (a, b) = (e.from as usize, e.to as usize);
                if a >= n || b >= n {
                    continue;
                }
                let (pa, pb) = (scene.pos(f, a), scene.pos(f, b));
                if e.ack {
                    let (a, b) = (p.px_hv(p.hv(pa)), p.px_hv(p.hv(pb)));
                    for d in dashes(a, b, ACK_DASH_PX) {
                        area.draw(&PathElement::new(d.to_vec(), c)).map_err(de)?;
                    }
                } else {
                    let seg = vec![p.px(pa), p.px(pb)];
                    area.draw(&PathElement::new(seg, c)).map_err(de)?;
                }
            }
        }
        Ok(())
    }
}

/// A number without trailing zeros (`4`, `0.5`, `2.25`).
pub(super) fn trim(v: f64) -> String {
    let s = format!("{v:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
