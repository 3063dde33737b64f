#!/usr/bin/env python3
"""Frame times of replay.html pages in headless Chromium, in real time (not in CI).

Usage: scripts/replay-frame-times.py [--seconds S] [--size 1280x720] PAGE.html[#state] ...

(#state: the viewer's address fragment, e.g. #aa=0 for no antialiasing; see replay.js.)

For each page: starts headless Chromium (software WebGL, SwiftShader) with the Chrome DevTools
Protocol on a pipe (--remote-debugging-pipe: requests on fd 3, replies on fd 4, NUL-terminated
JSON), opens the page from file://, waits for the viewer's first status report (time to the
first frame), lets it play for S seconds (default 10) and reads the viewer's counters
(window.shoalReplayStats, updated every frame): frames rendered in that window, their mean
interval, the viewer's own JavaScript per frame in it (poses, links, trails, panel, timeline)
and the renderer. Python standard library only; prints one Markdown table row per page.
The viewport is what headless Chromium gives the page for --window-size (1280×720 → 1280×577).
"""
import argparse
import json
import os
import subprocess
import sys
import time


class Cdp:
    """A Chromium with the DevTools protocol on a pipe."""

    def __init__(self, url, size):
        to_child_r, self._w = os.pipe()
        self._r, from_child_w = os.pipe()

        def fds():
            # Via fresh numbers (above the four pipe ends), so that neither end is overwritten
            # and both lose close-on-exec (dup2 onto the same number would keep it).
            a, b = os.dup(to_child_r), os.dup(from_child_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        w, h = size
        self.proc = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-dev-shm-usage",
             "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars",
             f"--window-size={w},{h}", "--remote-debugging-pipe", url],
            # close_fds would close 3 and 4 after preexec_fn has set them.
            preexec_fn=fds, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, close_fds=False)
        os.close(to_child_r)
        os.close(from_child_w)
        self._buf = b""
        self._id = 0
        self.session = None

    def call(self, method, params=None, session=True):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self._w, json.dumps(msg).encode() + b"\0")
        while True:
            reply = self._next()
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def _next(self):
        while b"\0" not in self._buf:
            chunk = os.read(self._r, 1 << 16)
            if not chunk:
                raise RuntimeError("chromium closed the pipe")
            self._buf += chunk
        msg, self._buf = self._buf.split(b"\0", 1)
        return json.loads(msg)

    def attach_page(self):
        for _ in range(100):
            pages = [t for t in self.call("Target.getTargets", session=False)["targetInfos"]
                     if t["type"] == "page"]
            if pages:
                self.session = self.call("Target.attachToTarget",
                                         {"targetId": pages[0]["targetId"], "flatten": True},
                                         session=False)["sessionId"]
                return
            time.sleep(0.05)
        raise RuntimeError("no page target")

    def eval(self, expr):
        r = self.call("Runtime.evaluate", {"expression": expr, "returnByValue": True})
        return r["result"].get("value")

    def close(self):
        try:
            self.call("Browser.close", session=False)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


STATUS = "JSON.stringify(Object.assign({}, document.documentElement.dataset, " \
         "window.shoalReplayStats || {}, {w: innerWidth, h: innerHeight}))"


def measure(page, seconds, size):
    start = time.monotonic()
    path, _, fragment = page.partition("#")
    cdp = Cdp("file://" + os.path.abspath(path) + ("#" + fragment if fragment else ""), size)
    try:
        cdp.attach_page()
        first = None
        while time.monotonic() - start < 120:
            s = json.loads(cdp.eval(STATUS) or "{}")
            if s.get("status") == "error":
                raise RuntimeError(f"{page}: {s.get('errors')}")
            if s.get("status") == "ok":
                first = time.monotonic() - start
                break
            time.sleep(0.1)
        if first is None:
            raise RuntimeError(f"{page}: no frame within 120 s")
        time.sleep(1.0)  # past the first frames (shader compilation)
        a = json.loads(cdp.eval(STATUS))
        time.sleep(seconds)
        b = json.loads(cdp.eval(STATUS))
        # The viewer's exact counters at its last frame (window.shoalReplayStats).
        frames = b["frames"] - a["frames"]
        ms = (b["now"] - a["now"]) / frames if frames > 0 else float("nan")
        update = (b["updateMsSum"] - a["updateMsSum"]) / frames if frames > 0 else float("nan")
        return {"page": page, "mb": os.path.getsize(path) / 1e6, "vehicles": b["vehicles"],
                "first_s": first, "frames": frames, "frame_ms": ms,
                "update_ms": update, "viewport": f"{b['w']}×{b['h']}",
                "renderer": b.get("glRenderer", "")}
    finally:
        cdp.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("pages", nargs="+")
    args = ap.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    print("| page | MB | vehicles | first frame [s] | frames in window | mean frame [ms] | "
          "viewer JS per frame [ms] | viewport |")
    print("|---|---|---|---|---|---|---|---|")
    renderer = ""
    for page in args.pages:
        r = measure(page, args.seconds, size)
        renderer = r["renderer"]
        print(f"| {os.path.join(os.path.basename(os.path.dirname(r['page'])), os.path.basename(r['page']))} | {r['mb']:.1f} | {r['vehicles']} | {r['first_s']:.1f} | "
              f"{r['frames']} | {r['frame_ms']:.0f} | {r['update_ms']:.2f} | {r['viewport']} |",
              flush=True)
    print(f"\nrenderer: {renderer}", file=sys.stderr)


if __name__ == "__main__":
    main()
