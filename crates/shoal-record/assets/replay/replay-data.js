/* shoal replay viewer, part 1 of 3: the data embedded in the page, decoded, and the small
 * formatting helpers the other parts share. Defines window.shoalReplay.load() and helpers;
 * replay-scene.js and replay.js (after this file in the same script element) use them.
 *
 * Data (see crates/shoal-sim/src/replay/mod.rs): the JSON header #shoal-meta and four
 * little-endian arrays as base64 — #shoal-pos (u16, frames × vehicles × 3, x = q/65535·pool.x),
 * #shoal-att (i16, frames × vehicles × 3: roll, pitch, yaw = q·π/32767), #shoal-panel (f32,
 * rows × vehicles × meta.panel.length, a row every meta.panel_dt s) and #shoal-links (events × 16 bytes: t f32, sender
 * u32, receiver u32, outcome word u32). They are decoded once and their elements removed.
 * The outcome word is the outcome's code (index into meta.outcomes) in its low bits, with its
 * top bit (0x80000000) set when the frame was an acknowledgement: decoded as outcome =
 * word & 0x7fffffff and ack = word >>> 31. Acknowledgements are drawn dashed (ACK_DASHES dashes
 * per line) in their outcome's colour; the legend's entry for them is meta.ack_label.
 *
 * Status for headless tests: data-link-colors on <html> lists the colours the link lines are
 * drawn in (from meta.outcomes); data-decoder says how the base64 was decoded (fromBase64 or atob).
 */
(function () {
  'use strict';
  var shoal = window.shoalReplay = window.shoalReplay || {};
  var LITTLE = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

  /** The replay of this page: header, arrays and the values derived from them (sizes, time
   * step [s], duration [s], link outcome styles), read once (their elements are removed). */
  shoal.load = function () {
    var meta = JSON.parse(take('shoal-meta'));
    var N = meta.vehicles | 0;
    var F = Math.max(meta.frames | 0, 1);
    var DT = meta.frame_dt > 0 ? meta.frame_dt : 1;
    var P = meta.pool;
    var T_END = Math.max(meta.duration_s || 0, (F - 1) * DT);
    var pos = typed(decode(take('shoal-pos')), Uint16Array);
    var att = typed(decode(take('shoal-att')), Int16Array);
    var panel = typed(decode(take('shoal-panel')), Float32Array);
    var links = decodeLinks(decode(take('shoal-links')));
    if (pos.length < F * N * 3 || att.length < F * N * 3) {
      throw new Error('replay data: pos/att hold ' + pos.length + '/' + att.length +
        ' values, not frames × vehicles × 3 = ' + F * N * 3);
    }
    var PW = (meta.panel || []).length;
    var PANEL_ROWS = N > 0 && PW > 0 ? Math.floor(panel.length / (N * PW)) : 0;
    var PANEL_DT = meta.panel_dt > 0 ? meta.panel_dt : 1;
    var col = {};
    (meta.panel || []).forEach(function (name, i) { col[name] = i; });
    var tl = meta.timeline || {};
    var SECONDS = (tl.attempted || []).length;

    // Link outcomes by code: name and colour from the header (meta.outcomes, the one colour
    // key of shoal_sim::link_key; no colour is written here), alpha and how far the line
    // reaches towards the receiver from LINE_STYLE.
    var LINE_STYLE = [
      { alpha: 0.95, reach: 1.0 },   // delivered
      { alpha: 0.9, reach: 0.85 },   // collided
      { alpha: 0.7, reach: 0.5 },    // occluded
      { alpha: 0.6, reach: 0.65 },   // out of budget
      { alpha: 0.85, reach: 0.85 }   // half-duplex
    ];
    var OUTCOMES = (meta.outcomes || []).map(function (o, k) {
      var c = new THREE.Color(o.color);   // sRGB → the renderer's linear working space
      var st = LINE_STYLE[k] || LINE_STYLE[3];
      return { name: o.name, hex: o.color, color: [c.r, c.g, c.b], alpha: st.alpha, reach: st.reach };
    });
    if (OUTCOMES.length < 5) throw new Error('replay data: the header has ' + OUTCOMES.length + ' link outcomes, not 5');
    document.documentElement.dataset.linkColors = OUTCOMES.map(function (o) { return o.hex; }).join(' ');
    var ACK_LABEL = typeof meta.ack_label === 'string' ? meta.ack_label : '';
    var ACK_DASHES = 7;        // dashes of an acknowledgement's line (each a line segment)
    var LINK_WINDOW_S = 0.3;   // link events shown this long after they happen [s]
    var MAX_LINES = 20000;     // link lines drawn at once at most
    var TRAIL_S = 4;           // trail length [s]
    var MAX_TRAIL_SEGMENTS = 120000;
    var PALETTE = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',
      '#7f7f7f', '#bcbd22', '#17becf'];
    return {
      meta: meta, N: N, F: F, DT: DT, P: P, T_END: T_END, pos: pos, att: att, panel: panel,
      links: links, PW: PW, PANEL_ROWS: PANEL_ROWS, PANEL_DT: PANEL_DT, col: col, tl: tl,
      SECONDS: SECONDS, OUTCOMES: OUTCOMES, ACK_LABEL: ACK_LABEL, ACK_DASHES: ACK_DASHES,
      LINK_WINDOW_S: LINK_WINDOW_S, MAX_LINES: MAX_LINES,
      TRAIL_S: TRAIL_S, MAX_TRAIL_SEGMENTS: MAX_TRAIL_SEGMENTS, PALETTE: PALETTE
    };
  };

  // ------------------------------------------------------------------ decoding
  /** The text of the element `id`, which is then removed (frees the string; keeps the DOM small). */
  function take(id) {
    var e = document.getElementById(id);
    if (!e) throw new Error('replay data: no element ' + id);
    var s = e.textContent;
    e.remove();
    return s;
  }
  function decode(b64) {
    b64 = b64.trim();
    // #atob in the address forces the fallback (so tests on new browsers exercise it too).
    if (typeof Uint8Array.fromBase64 === 'function' && !/(^#|&)atob(&|$)/.test(location.hash || '')) {
      document.documentElement.dataset.decoder = 'fromBase64';
      return Uint8Array.fromBase64(b64);
    }
    document.documentElement.dataset.decoder = 'atob';
    var s = atob(b64), n = s.length, out = new Uint8Array(n);
    for (var i = 0; i < n; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  /** `bytes` (little-endian values) as a typed array of `Ctor`. */
  function typed(bytes, Ctor) {
    var size = Ctor.BYTES_PER_ELEMENT, n = Math.floor(bytes.length / size);
    if (LITTLE && bytes.byteOffset % size === 0) return new Ctor(bytes.buffer, bytes.byteOffset, n);
    var out = new Ctor(n), dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    var get = { 2: Ctor === Int16Array ? 'getInt16' : 'getUint16', 4: Ctor === Float32Array ? 'getFloat32' : 'getUint32' }[size];
    for (var i = 0; i < n; i++) out[i] = dv[get](i * size, true);
    return out;
  }
  /** Link events as columns, sorted by time: outcome code (255 for codes beyond) and
   * acknowledgement flag (1 or 0) from the outcome word. */
  function decodeLinks(bytes) {
    var f = typed(bytes, Float32Array), u = typed(bytes, Uint32Array), n = Math.floor(f.length / 4);
    var t = new Float32Array(n), from = new Uint32Array(n), to = new Uint32Array(n), outcome = new Uint8Array(n);
    var ack = new Uint8Array(n);
    var sorted = true;
    for (var k = 0; k < n; k++) {
      var word = u[4 * k + 3];
      t[k] = f[4 * k]; from[k] = u[4 * k + 1]; to[k] = u[4 * k + 2];
      outcome[k] = Math.min(word & 0x7fffffff, 255); ack[k] = word >>> 31;
      if (k > 0 && t[k] < t[k - 1]) sorted = false;
    }
    if (!sorted) {
      var idx = Array.from({ length: n }, function (_, k) { return k; }).sort(function (a, b) { return t[a] - t[b]; });
      var t2 = new Float32Array(n), f2 = new Uint32Array(n), to2 = new Uint32Array(n), o2 = new Uint8Array(n);
      var a2 = new Uint8Array(n);
      idx.forEach(function (j, k) { t2[k] = t[j]; f2[k] = from[j]; to2[k] = to[j]; o2[k] = outcome[j]; a2[k] = ack[j]; });
      t = t2; from = f2; to = to2; outcome = o2; ack = a2;
    }
    return { t: t, from: from, to: to, outcome: outcome, ack: ack, length: n };
  }
  /** First index whose value is greater than x in the sorted array a. */
  function upperBound(a, x) {
    var lo = 0, hi = a.length;
    while (lo < hi) {
      var mid = (lo + hi) >> 1;
      if (a[mid] <= x) lo = mid + 1; else hi = mid;
    }
    return lo;
  }
  function fmt(x, digits) { return isFinite(x) ? Number(x).toFixed(digits) : '—'; }
  function deg360(rad) { var d = rad * 180 / Math.PI % 360; return d < 0 ? d + 360 : d; }
  function sum(a) { var s = 0; for (var i = 0; i < a.length; i++) s += a[i]; return s; }
  function niceStep(span, maxTicks) {
    var raw = span / Math.max(maxTicks, 1), p = Math.pow(10, Math.floor(Math.log10(raw || 1)));
    var steps = [1, 2, 5, 10];
    for (var i = 0; i < steps.length; i++) if (steps[i] * p >= raw) return steps[i] * p;
    return 10 * p;
  }
  shoal.upperBound = upperBound;
  shoal.fmt = fmt;
  shoal.deg360 = deg360;
  shoal.sum = sum;
  shoal.niceStep = niceStep;
})();
