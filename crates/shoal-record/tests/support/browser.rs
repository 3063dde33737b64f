//! Headless Chromium for the replay tests of shoal-sim and shoal-cli (the latter includes this
//! file by path): run it on a page, read the status attributes the viewer sets on `<html>`,
//! and check that a page reaches nothing outside itself — by watching what Chromium's network
//! stack is asked for while it loads and plays the page ([`chromium_observed`], from its
//! NetLog) and by reading the page's text ([`assert_offline`]).
//!
//! Chromium itself reaches out in the background (component updates, network time, account
//! checks) even with its background networking switched off. [`chromium`] therefore resolves
//! no host name (`--host-resolver-rules`) and sends every HTTP(S) request to a proxy on a
//! closed loopback port: nothing leaves this machine, and every request still shows in the
//! NetLog.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};
use std::time::Instant;

/// Flags that keep Chromium's own traffic off the network (see the module documentation).
const NO_NETWORK: [&str; 10] = [
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-default-apps",
    "--disable-domain-reliability",
    "--no-first-run",
    "--no-pings",
    "--disable-features=NetworkTimeServiceQuerying",
    "--host-resolver-rules=MAP * ~NOTFOUND",
    "--proxy-server=127.0.0.1:1",
];

/// Runs headless Chromium on the page `page` (with the address fragment `fragment`, the
/// viewer's initial state) with `extra` arguments (at most 120 s). Fails the test with the
/// install command when there is no `chromium`.
pub fn chromium(page: &Path, fragment: &str, extra: &[&str]) -> Output {
    let found = Command::new("chromium").arg("--version").output();
    if !found.as_ref().is_ok_and(|o| o.status.success()) {
        panic!(
            "chromium is missing; the replay browser tests need it. Install it with \
             scripts/install-chromium.sh (as root: apt-get update && apt-get install -y chromium)"
        );
    }
    let start = Instant::now();
    let out = Command::new("timeout")
        .args([
            "120",
            "chromium",
            "--headless",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--window-size=1280,720",
            "--hide-scrollbars",
            // Frames are produced in virtual time, not by the wall clock: without it a loaded
            // machine ends the virtual-time budget after a single animation frame (seen in CI:
            // a page that "did not play", 0.00 s after 3 s of budget).
            "--run-all-compositor-stages-before-draw",
        ])
        .args(NO_NETWORK)
        .args(extra)
        .arg(format!("file://{}{fragment}", page.display()))
        .output()
        .expect("cannot run timeout/chromium");
    eprintln!("chromium {extra:?}: {:.1} s", start.elapsed().as_secs_f64());
    assert!(
        out.status.success(),
        "chromium failed ({}): {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// [`chromium`] with its NetLog (`--log-net-log`, written beside the page): the output and
/// the URL of every request its network stack started on behalf of a document — a request
/// whose initiator is an origin (a `file:` page's is `null`) or whose isolation key names
/// `file://`. Requests Chromium makes for itself (initiator "not an origin") are left out.
/// A page from `file://` that loads nothing from outside makes none: its own file, `data:`
/// and `blob:` URLs never reach the network stack.
pub fn chromium_observed(page: &Path, fragment: &str, extra: &[&str]) -> (Output, Vec<String>) {
    let log = page.with_extension("netlog.json");
    let _ = std::fs::remove_file(&log);
    let flag = format!("--log-net-log={}", log.display());
    let mut args = vec![flag.as_str()];
    args.extend_from_slice(extra);
    let out = chromium(page, fragment, &args);
    let text = std::fs::read_to_string(&log)
        .unwrap_or_else(|e| panic!("no NetLog at {}: {e}", log.display()));
    let json: serde_json::Value = serde_json::from_str(&text).expect("the NetLog is JSON");
    let start = json["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
        .as_u64()
        .expect("the NetLog names URL_REQUEST_START_JOB");
    let events = json["events"].as_array().expect("the NetLog's events");
    assert!(!events.is_empty(), "the NetLog recorded nothing");
    let mut mine = Vec::new();
    for p in events
        .iter()
        .filter(|e| e["type"].as_u64() == Some(start))
        .map(|e| &e["params"])
    {
        let Some(url) = p["url"].as_str() else {
            continue; // the end of a job (its net_error)
        };
        let initiator = p["initiator"].as_str().unwrap_or("not an origin");
        let key = p["network_isolation_key"].as_str().unwrap_or("");
        if initiator != "not an origin" || key.contains("file://") {
            mine.push(url.to_string());
        } else {
            eprintln!("chromium's own request (not the page's): {url}");
        }
    }
    (out, mine)
}

/// Asserts that `requests` (from [`chromium_observed`]) reached nothing outside the page:
/// only `file:`, `data:` and `blob:` URLs.
pub fn assert_no_outside_requests(requests: &[String]) {
    let outside: Vec<&String> = requests
        .iter()
        .filter(|u| !["file:", "data:", "blob:"].iter().any(|s| u.starts_with(s)))
        .collect();
    assert!(
        outside.is_empty(),
        "the page asked the network for {outside:?}"
    );
}

/// The attribute `name` of the `<html …>` start tag in `dom`, unescaped.
pub fn html_attr(dom: &str, name: &str) -> Option<String> {
    let s = dom.find("<html")?;
    let tag = &dom[s..s + dom[s..].find('>')?];
    let k = format!(" {name}=\"");
    let i = tag.find(&k)? + k.len();
    Some(
        tag[i..i + tag[i..].find('"')?]
            .replace("&quot;", "\"")
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&"),
    )
}

/// Every tag of `page` outside script and style contents, as its text `<…>`.
pub fn tags(page: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = page;
    while let Some(i) = rest.find('<') {
        rest = &rest[i..];
        let end = rest.find('>').map_or(rest.len(), |e| e + 1);
        let tag = &rest[..end];
        out.push(tag);
        rest = &rest[end..];
        let lower = tag.to_ascii_lowercase();
        for raw in ["script", "style"] {
            if lower.starts_with(&format!("<{raw}")) {
                let close = format!("</{raw}");
                let at = rest.to_ascii_lowercase().find(&close).unwrap_or(rest.len());
                rest = &rest[at..];
            }
        }
    }
    out
}

/// Asserts that the replay page text `page` loads nothing from outside: no tag names a
/// source, link or URL, the style sheet imports nothing, and the code (the page without its
/// base64 arrays) neither fetches nor names a URL other than the XHTML namespace.
pub fn assert_offline(page: &str) {
    let tags = tags(page);
    assert!(
        tags.len() > 20,
        "the tag scanner found only {} tags",
        tags.len()
    );
    let scripts = tags.iter().filter(|t| t.starts_with("<script")).count();
    assert_eq!(scripts, 8, "guard, meta, 4 arrays, three.js, viewer");
    for t in &tags {
        let lower = t.to_ascii_lowercase();
        for bad in [
            "src=",
            "href=",
            "srcset=",
            "url(",
            "http:",
            "https:",
            "//",
            "<link",
            "<iframe",
            "<img",
            "<object",
            "<embed",
            "<base",
            "<meta http-equiv",
        ] {
            assert!(!lower.contains(bad), "the tag {t} contains {bad}");
        }
    }
    // Nor do the style sheet or the viewer reach out (three.js only names the XHTML
    // namespace, in createElementNS).
    let style = &page[page.find("<style>").unwrap()..page.find("</style>").unwrap()];
    for bad in ["url(", "@import", "http"] {
        assert!(!style.contains(bad), "the style sheet contains {bad}");
    }
    // The page without the base64 arrays (random letters could spell anything).
    let mut code = String::new();
    let mut rest = page;
    let data = "type=\"application/octet-stream\"";
    while let Some(i) = rest.find(data) {
        code.push_str(&rest[..i]);
        rest = &rest[i + rest[i..].find("</script>").unwrap()..];
    }
    code.push_str(rest);
    assert!(
        page.len() - code.len() > 10_000,
        "the arrays were not cut out"
    );
    for bad in [
        "fetch(",
        "XMLHttpRequest",
        "import(",
        "WebSocket",
        "EventSource",
        "sendBeacon",
    ] {
        assert!(!code.contains(bad), "the page contains {bad}");
    }
    let urls: Vec<&str> = code
        .match_indices("http")
        .map(|(i, _)| &code[i..(i + 40).min(code.len())])
        .collect();
    assert!(
        urls.iter()
            .all(|u| u.starts_with("http://www.w3.org/1999/xhtml")),
        "URLs in the page: {urls:?}"
    );
}
