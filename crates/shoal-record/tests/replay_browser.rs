//! `replay.html` in a real browser: headless Chromium opens a demo replay from `file://`
//! (software WebGL, SwiftShader), and the page must report that it rendered (the status
//! attributes its viewer sets on `<html>`), draw a picture that is not blank, and load nothing
//! from outside the file — watched in Chromium's NetLog while it plays, with a leaky copy of
//! the page to show that the watch sees what it should.
//!
//! Chromium is required: without it these tests fail and say how to install it
//! (`scripts/install-chromium.sh`, which `scripts/test.sh` runs first).

mod support;

use std::path::{Path, PathBuf};
use support::browser::{self, chromium, chromium_observed, html_attr};

use shoal_record::replay::{ReplayData, html};
use support::demo::demo;

/// Vehicles of the demo replay the browser opens.
const VEHICLES: usize = 12;

/// A fresh folder for one test.
fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "shoal-replay-browser-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 12-vehicle, 20-s demo replay in `d`; its absolute path.
fn demo_page(d: &Path) -> PathBuf {
    page_of(d, &demo(VEHICLES, 20.0))
}

/// The page of `data` in `d`; its absolute path.
fn page_of(d: &Path, data: &ReplayData) -> PathBuf {
    let path = html::write(&d.join("replay.html"), data).unwrap();
    std::fs::canonicalize(path).unwrap()
}

/// The link events of `data` the page shows at `t` \[s\] (those of the 0.3 s before it), by
/// outcome code: all, and the acknowledgements among them.
fn shown_at(data: &ReplayData, t: f64) -> ([u32; 5], [u32; 5]) {
    let (mut all, mut acks) = ([0; 5], [0; 5]);
    for e in &data.links {
        let te = f64::from(e.t);
        if te > t - 0.3 && te <= t {
            all[e.outcome.code() as usize] += 1;
            acks[e.outcome.code() as usize] += u32::from(e.ack);
        }
    }
    (all, acks)
}

/// The numbers of the status attribute `name` of `dom`.
fn numbers(dom: &str, name: &str) -> Vec<u32> {
    html_attr(dom, name)
        .unwrap_or_else(|| panic!("no {name}"))
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
fn the_replay_renders_in_headless_chromium() {
    let d = dir("dom");
    let page = demo_page(&d);
    let out = chromium(&page, "", &["--virtual-time-budget=2000", "--dump-dom"]);
    let dom = String::from_utf8_lossy(&out.stdout);
    let attr = |n: &str| html_attr(&dom, n);
    assert_eq!(attr("data-errors"), None, "the page reported errors");
    assert_eq!(
        attr("data-status").as_deref(),
        Some("ok"),
        "{}",
        &dom[..dom.len().min(2000)]
    );
    let frames: u32 = attr("data-frames-rendered")
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    assert!(frames >= 1, "frames rendered: {frames}");
    assert_eq!(attr("data-vehicles"), Some(VEHICLES.to_string()));
    assert_eq!(attr("data-three-revision").as_deref(), Some("187"));
    // Chromium 156 has Uint8Array.fromBase64 (the click test covers the fallback).
    assert_eq!(attr("data-decoder").as_deref(), Some("fromBase64"));
    assert!(attr("data-gl-renderer").is_some_and(|r| !r.is_empty()));
    assert!(
        dom.contains("<title>shoal replay: "),
        "the title counts frames"
    );
    // The data elements are gone once decoded (the DOM stays small).
    for id in [
        "shoal-meta",
        "shoal-pos",
        "shoal-att",
        "shoal-panel",
        "shoal-links",
    ] {
        assert!(
            !dom.contains(&format!("id=\"{id}\"")),
            "{id} is still in the page"
        );
    }
    assert!(dom.len() < 2_000_000, "DOM of {} bytes", dom.len());
    // The info line names the world and the vehicles.
    assert!(
        dom.contains("demo: 12 vehicles on circles"),
        "no world name in the page"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The page draws link lines and its legend in the colours of the one key
/// (`shoal_record::link_key`), which it reads from the header; acknowledgement frames (every
/// fourth link event of the demo, here) are told apart from the others in the outcome word's
/// top bit, drawn dashed — several segments each — and have one legend entry.
#[test]
fn links_and_legend_wear_the_colours_of_the_one_key() {
    let d = dir("key");
    let mut data = demo(VEHICLES, 20.0);
    for (k, e) in data.links.iter_mut().enumerate() {
        e.ack = k % 4 == 1;
    }
    let page = page_of(&d, &data);
    // Paused at the end of the busiest window for acknowledgements.
    let t = data
        .links
        .iter()
        .map(|e| f64::from(e.t))
        .max_by_key(|&t| shown_at(&data, t).1.iter().sum::<u32>())
        .unwrap();
    let out = chromium(
        &page,
        &format!("#t={t}&paused"),
        &["--virtual-time-budget=2000", "--dump-dom"],
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(html_attr(&dom, "data-status").as_deref(), Some("ok"));
    let key = &shoal_record::link_key::LINK_KEY;
    let hex: Vec<String> = key
        .iter()
        .map(|k| shoal_record::link_key::hex(k.outcome))
        .collect();
    // The colours the link lines are drawn in.
    assert_eq!(html_attr(&dom, "data-link-colors"), Some(hex.join(" ")));
    // The legend: one swatch per outcome, in its colour, with its label.
    let at = dom.find("id=\"link-legend\"").expect("no link legend");
    let legend = &dom[at..at + dom[at..].find("id=\"groups\"").unwrap()];
    let rows: Vec<&str> = legend.split("<div>").skip(1).collect();
    assert_eq!(rows.len(), key.len() + 1, "{legend}");
    let swatches: Vec<(String, String)> = rows[..key.len()]
        .iter()
        .map(|row| {
            let bg = row.split("background: ").nth(1).unwrap_or("");
            let colour = bg[..bg.find(';').unwrap_or(0)].to_string();
            let label = row[row.find("</i>").map_or(0, |i| i + 4)..]
                .split('<')
                .next()
                .unwrap_or("")
                .to_string();
            (label, colour)
        })
        .collect();
    let want: Vec<(String, String)> = key
        .iter()
        .map(|k| {
            let (r, g, b) = k.rgb;
            (k.label.to_string(), format!("rgb({r}, {g}, {b})"))
        })
        .collect();
    assert_eq!(swatches, want, "{legend}");
    // The one entry for acknowledgements: a dashed swatch and the key's label.
    let ack_row = rows[key.len()];
    assert!(ack_row.contains("class=\"sw dashed\""), "{ack_row}");
    assert!(
        ack_row.contains(&format!("</i>{}<", shoal_record::link_key::ACK_LABEL)),
        "{ack_row}"
    );
    // The lines drawn at t, by outcome, and the acknowledgements among them: the page read
    // each event's outcome and flag from its outcome word.
    let (all, acks) = shown_at(&data, t);
    assert!(acks.iter().sum::<u32>() >= 2, "{all:?} {acks:?}");
    assert_eq!(numbers(&dom, "data-link-lines"), all, "lines by outcome");
    assert_eq!(
        numbers(&dom, "data-ack-lines"),
        acks,
        "acknowledgements by outcome"
    );
    // Each acknowledgement is drawn as dashes (several segments), every other line as one.
    let (lines, dashed) = (all.iter().sum::<u32>(), acks.iter().sum::<u32>());
    let extra = numbers(&dom, "data-link-segments")[0] - lines;
    assert!(
        extra.is_multiple_of(dashed) && extra / dashed >= 2,
        "{dashed} acknowledgements of {lines} lines take {extra} more segments"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The text of the element with the id `id` in `dom` (up to the next tag).
fn text_of<'a>(dom: &'a str, id: &str) -> Option<&'a str> {
    let open = format!("id=\"{id}\"");
    let at = dom.find(&open)?;
    let start = at + dom[at..].find('>')? + 1;
    Some(&dom[start..start + dom[start..].find('<')?])
}

#[test]
fn a_click_selects_a_vehicle_and_the_timeline_seeks() {
    let d = dir("click");
    let page = demo_page(&d);
    // The page clicks, as DOM events, where auv05 is drawn (from above, 4× size, so nothing
    // hides it) and at the middle of the timeline strip; it decodes its arrays with atob (the
    // fallback for browsers without Uint8Array.fromBase64).
    let fragment = "#t=3&paused&view=top&size=4&ranges=off&click=auv05&tlclick=0.5&atob";
    let out = chromium(
        &page,
        fragment,
        &["--virtual-time-budget=2000", "--dump-dom"],
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        html_attr(&dom, "data-errors"),
        None,
        "the page reported errors"
    );
    assert_eq!(html_attr(&dom, "data-status").as_deref(), Some("ok"));
    let panel = dom.find("id=\"panel\"").expect("no panel");
    let panel_tag = &dom[panel..panel + dom[panel..].find('>').unwrap()];
    assert!(
        !panel_tag.contains("hidden"),
        "the panel is hidden: {panel_tag}"
    );
    assert_eq!(html_attr(&dom, "data-decoder").as_deref(), Some("atob"));
    assert_eq!(
        text_of(&dom, "p-name"),
        Some("auv05"),
        "the click picked another vehicle"
    );
    assert_eq!(text_of(&dom, "p-mode"), Some("auto"));
    assert!(text_of(&dom, "p-depth").is_some_and(|t| t.ends_with(" m)")));
    // 20 s long: the middle of the timeline is 10 s.
    assert_eq!(text_of(&dom, "time"), Some("10.00 / 20.0 s"));
    let _ = std::fs::remove_dir_all(&d);
}

/// The region of a 1280 × 720 screenshot that shows the 3D view between the overlays (info
/// top left, legend top right, timeline and controls at the bottom; the legend's swatches have
/// the group colours too).
fn in_view(x: u32, y: u32) -> bool {
    (300..1040).contains(&x) && (100..590).contains(&y)
}

/// A 1280 × 720 screenshot of `page` with the viewer state `fragment`.
fn screenshot(page: &Path, fragment: &str) -> image::RgbImage {
    let png = page.with_extension("png");
    let shot = format!("--screenshot={}", png.display());
    chromium(page, fragment, &["--virtual-time-budget=2000", &shot]);
    let img = image::open(&png).expect("no screenshot").to_rgb8();
    assert_eq!(img.dimensions(), (1280, 720));
    img
}

#[test]
fn the_screenshot_shows_the_pool_and_the_vehicles() {
    let d = dir("png");
    // From above, paused, the hulls drawn 4× their size, without range spheres; and the same
    // view of the same pool without vehicles, to tell the vehicles from the pool.
    let fragment = "#t=10&paused&view=top&size=4&ranges=off";
    let img = screenshot(&demo_page(&d), fragment);
    let empty = html::write(&d.join("empty.html"), &demo(0, 20.0)).unwrap();
    let control = screenshot(&std::fs::canonicalize(empty).unwrap(), fragment);
    let background = [0x07u8, 0x14, 0x1f];
    let mut colours = std::collections::HashSet::new();
    let (mut drawn, mut changed, mut blue, mut orange) = (0usize, 0usize, 0usize, 0usize);
    for (x, y, p) in img.enumerate_pixels() {
        if !in_view(x, y) {
            continue;
        }
        let [r, g, b] = p.0;
        colours.insert((r >> 3, g >> 3, b >> 3));
        let off = |q: [u8; 3]| {
            (0..3)
                .map(|k| u32::from(p.0[k].abs_diff(q[k])))
                .sum::<u32>()
        };
        if off(background) > 30 {
            drawn += 1;
        }
        if off(control.get_pixel(x, y).0) <= 30 {
            continue;
        }
        changed += 1;
        // What the vehicles changed, by colour: the two groups' hulls, tab10 blue
        // (31, 119, 180) and orange (255, 127, 14), lit.
        let (r, g, b) = (i32::from(r), i32::from(g), i32::from(b));
        if b > 110 && b > r + 60 && b > g + 15 {
            blue += 1;
        }
        if r > 130 && r > b + 70 && r > g + 30 {
            orange += 1;
        }
    }
    let total = 740 * 490;
    eprintln!(
        "screenshot: {drawn} of {total} pixels drawn, {} colours; the vehicles changed \
         {changed}: {blue} blue, {orange} orange",
        colours.len()
    );
    assert!(drawn * 10 > total, "only {drawn} of {total} pixels drawn");
    assert!(
        colours.len() > 150,
        "only {} distinct colours",
        colours.len()
    );
    assert!(
        orange > 1500,
        "{orange} orange pixels: the relays' hulls are not drawn"
    );
    assert!(
        blue > 1500,
        "{blue} blue pixels: the scouts' hulls are not drawn"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Chromium loads and plays the page from `file://` for 3 s (virtual time) and its network
/// stack is asked for nothing on the page's behalf; the page's text names nothing outside
/// either.
#[test]
fn the_page_loads_nothing_from_outside() {
    let d = dir("offline");
    let page = demo_page(&d);
    let (out, requests) =
        chromium_observed(&page, "", &["--virtual-time-budget=3000", "--dump-dom"]);
    let dom = String::from_utf8_lossy(&out.stdout);
    assert_eq!(html_attr(&dom, "data-status").as_deref(), Some("ok"));
    // It played: the clock (`t / duration s`) moved on from 0.
    let time = text_of(&dom, "time").expect("no clock");
    let t: f64 = time.split(" / ").next().unwrap().parse().unwrap();
    let frames = html_attr(&dom, "data-frames-rendered");
    eprintln!("played to {time} in {frames:?} frames");
    assert!(
        t > 0.0,
        "the page did not play: {time} ({frames:?} frames rendered)"
    );
    browser::assert_no_outside_requests(&requests);
    browser::assert_offline(&std::fs::read_to_string(&page).unwrap());
    let _ = std::fs::remove_dir_all(&d);
}

/// The observer sees a page that does load from outside: a copy of the replay with a
/// script from an https address (a name that cannot resolve) and an image from a loopback
/// port is caught with exactly those two requests.
#[test]
fn the_network_observer_sees_a_page_that_loads_from_outside() {
    let d = dir("leaky");
    let page = std::fs::read_to_string(demo_page(&d)).unwrap();
    let script = "https://cdn.example.invalid/three.js";
    let img = "http://127.0.0.1:9/x.png";
    let head = page.find("<head>").unwrap() + "<head>".len();
    let leaky = format!(
        "{}<script src=\"{script}\"></script><img src=\"{img}\">{}",
        &page[..head],
        &page[head..]
    );
    let path = d.join("leaky.html");
    std::fs::write(&path, leaky).unwrap();
    let (_, mut requests) =
        chromium_observed(&path, "", &["--virtual-time-budget=1000", "--dump-dom"]);
    requests.sort();
    assert_eq!(requests, vec![img.to_string(), script.to_string()]);
    let caught = std::panic::catch_unwind(|| browser::assert_no_outside_requests(&requests));
    assert!(
        caught.is_err(),
        "assert_no_outside_requests let {requests:?} pass"
    );
    let _ = std::fs::remove_dir_all(&d);
}
