/* shoal replay viewer: draws the run embedded in this page with three.js (global THREE, the
 * vendored bundle in an earlier script element). Nothing is loaded from anywhere.
 *
 * This file, part 3 of 3, is the viewer itself: its state, the controls, keys and mouse, the
 * views, the timeline strip, the vehicle panel and the render loop. It uses replay-data.js
 * (decoding, helpers) and replay-scene.js (the 3D scene), which the page holds before it in
 * the same script element.
 *
 * Status for headless tests: every 10 rendered frames (and after the first) <html> gets
 * data-status="ok" data-frames-rendered data-vehicles data-mean-frame-ms data-mean-update-ms
 * data-gl-renderer data-three-revision, the link lines drawn now — data-link-lines (by outcome
 * code), data-ack-lines (the acknowledgements among them, by outcome code), data-link-segments
 * (the segments they take: an acknowledgement's line is dashed, several segments) — and
 * document.title says how many frames were rendered; data-link-colors and data-decoder are set
 * by replay-data.js.
 * Failures are recorded by the guard script in <head> (data-status="error", data-errors).
 */
(function () {
  'use strict';
  var fail = window.__shoalFail || function (m) { throw new Error(m); };

  function main() {
    var shoal = window.shoalReplay;
    var fmt = shoal.fmt, deg360 = shoal.deg360, sum = shoal.sum, niceStep = shoal.niceStep;
    var upperBound = shoal.upperBound;
    var d = shoal.load();
    var meta = d.meta, N = d.N, F = d.F, DT = d.DT, P = d.P, T_END = d.T_END, panel = d.panel;
    var links = d.links, PW = d.PW, PANEL_ROWS = d.PANEL_ROWS, PANEL_DT = d.PANEL_DT, col = d.col;
    var tl = d.tl, SECONDS = d.SECONDS, OUTCOMES = d.OUTCOMES, PALETTE = d.PALETTE;

    var view = document.getElementById('view');
    var sc = shoal.createScene(d);
    var renderer = sc.renderer, scene = sc.scene, camera = sc.camera, controls = sc.controls;
    var CENTRE = sc.CENTRE, cur = sc.cur, RANGE = sc.RANGE, trailFrames = sc.trailFrames;
    var vehicleDisplay = sc.vehicleDisplay;

    // ---------------------------------------------------------------- state
    var state = {
      t: 0, playing: true, speed: 1, selected: -1, follow: false,
      onlyDelivered: false, ranges: RANGE > 0 ? 'selected' : 'off',
      trails: N <= 200 && trailFrames >= 2, size: 1
    };
    var dirty = true;                       // the scene must be recomputed for state.t

    // ---------------------------------------------------------------- UI
    var $ = function (id) { return document.getElementById(id); };
    var info = $('info');
    var playBtn = $('play');
    var scrub = $('scrub');
    var timeLabel = $('time');
    scrub.max = String(T_END);
    $('trails').checked = state.trails;
    $('trails').disabled = trailFrames < 2;
    $('link-legend').innerHTML = '';
    OUTCOMES.forEach(function (o, k) {
      var div = document.createElement('div');
      var sw = document.createElement('i');
      sw.className = k === 0 ? 'sw' : 'sw short';   // lost frames stop short
      sw.style.background = o.hex;
      div.appendChild(sw);
      div.appendChild(document.createTextNode(o.name));
      $('link-legend').appendChild(div);
    });
    if (d.ACK_LABEL) {
      // The one entry for acknowledgements: drawn dashed, in their outcome's colour.
      var ackRow = document.createElement('div');
      var ackSw = document.createElement('i');
      ackSw.className = 'sw dashed';
      ackRow.appendChild(ackSw);
      ackRow.appendChild(document.createTextNode(d.ACK_LABEL));
      $('link-legend').appendChild(ackRow);
    }
    $('groups').innerHTML = '';
    (meta.groups || []).forEach(function (g, i) {
      var div = document.createElement('div');
      var dot = document.createElement('i');
      dot.className = 'dot';
      dot.style.background = g.color || PALETTE[i % PALETTE.length];
      div.appendChild(dot);
      div.appendChild(document.createTextNode(g.name + ' (' + g.count + ')'));
      $('groups').appendChild(div);
    });
    updateRangeButton();

    function setPlaying(p) {
      if (p && state.t >= T_END) seek(0);
      state.playing = p;
      playBtn.textContent = p ? 'pause' : 'play';
    }
    function seek(t) {
      state.t = Math.min(Math.max(t, 0), T_END);
      showTime();
      dirty = true;
    }
    function showTime() {
      if (document.activeElement !== scrub) scrub.value = String(state.t);
      timeLabel.textContent = fmt(state.t, 2) + ' / ' + fmt(T_END, 1) + ' s';
    }
    function setSpeed(s) {
      state.speed = s;
      $('speed').value = String(s);
    }
    function stepSpeed(dir) {
      var opts = [0.25, 0.5, 1, 2, 4, 8, 16];
      var k = opts.indexOf(state.speed);
      setSpeed(opts[Math.min(Math.max((k < 0 ? 2 : k) + dir, 0), opts.length - 1)]);
    }
    function cycleSize() {   // draw the hulls 1×, 2× or 4× their size (tiny vehicles in big pools)
      state.size = state.size >= 4 ? 1 : state.size * 2;
      $('size').textContent = 'size ' + state.size + '×';
      $('size').classList.toggle('on', state.size > 1);
      dirty = true;
    }
    function toggleRanges() {
      state.ranges = { off: 'selected', selected: 'all', all: 'off' }[state.ranges];
      updateRangeButton();
      dirty = true;
    }
    function updateRangeButton() {
      $('ranges').textContent = 'range: ' + state.ranges;
      $('ranges').disabled = RANGE <= 0;
      $('ranges').classList.toggle('on', state.ranges !== 'off');
    }
    function select(i) {
      state.selected = i;
      if (i < 0 && state.follow) setFollow(false);
      $('panel').hidden = i < 0;
      panelShown = -2;
      dirty = true;
      if (i >= 0) { sc.updateSelection(state); updatePanel(state.t, performance.now()); }
    }
    function setFollow(on) {
      if (on && state.selected < 0 && N > 0) select(0);
      state.follow = on && state.selected >= 0;
      $('v-follow').classList.toggle('on', state.follow);
      if (state.follow) {
        var p = vehicleDisplay(state.selected);
        var yaw = cur[6 * state.selected + 5];
        // Behind and above the vehicle: back along its heading (north = +Y, east = +X).
        camera.position.set(p.x - 2.4 * Math.sin(yaw), p.y - 2.4 * Math.cos(yaw), p.z + 1.2);
        controls.target.copy(p);
        controls.update();
      }
    }
    playBtn.onclick = function () { setPlaying(!state.playing); this.blur(); };
    $('speed').onchange = function () { state.speed = +this.value; this.blur(); };
    scrub.oninput = function () { seek(+this.value); };
    $('v-top').onclick = function () { viewTop(); this.blur(); };
    $('v-side').onclick = function () { viewSide(); this.blur(); };
    $('v-follow').onclick = function () { setFollow(!state.follow); this.blur(); };
    $('only-delivered').onchange = function () { state.onlyDelivered = this.checked; dirty = true; this.blur(); };
    $('ranges').onclick = function () { toggleRanges(); this.blur(); };
    $('trails').onchange = function () { state.trails = this.checked; dirty = true; this.blur(); };
    $('size').onclick = function () { cycleSize(); this.blur(); };
    $('help-btn').onclick = function () { $('help').hidden = !$('help').hidden; this.blur(); };
    $('p-close').onclick = function () { select(-1); };
    addEventListener('keydown', function (e) {
      var tag = e.target && e.target.tagName;
      if (tag === 'SELECT' || e.ctrlKey || e.metaKey || e.altKey) return;
      var onSlider = e.target === scrub;
      var k = e.key;
      if (k === ' ') { setPlaying(!state.playing); }
      else if (k === 'ArrowLeft' && !onSlider) { seek(state.t - 1); }
      else if (k === 'ArrowRight' && !onSlider) { seek(state.t + 1); }
      else if (k === ',') { seek(state.t - DT); }
      else if (k === '.') { seek(state.t + DT); }
      else if (k === '[') { stepSpeed(-1); }
      else if (k === ']') { stepSpeed(1); }
      else if (k === '1') { viewTop(); }
      else if (k === '2') { viewSide(); }
      else if (k === '3') { setFollow(!state.follow); }
      else if (k === '0') { viewDefault(); }
      else if (k === 'd') { $('only-delivered').click(); }
      else if (k === 'r') { toggleRanges(); }
      else if (k === 's') { cycleSize(); }
      else if (k === 't') { if (!$('trails').disabled) $('trails').click(); }
      else if (k === 'h' || k === '?') { $('help').hidden = !$('help').hidden; }
      else if (k === 'Escape') { select(-1); }
      else return;
      e.preventDefault();
    });

    // Click a vehicle: a click that moved less than 5 px since the press (a drag orbits instead).
    var down = null;
    renderer.domElement.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('click', function (e) {
      var moved = down && Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 5;
      down = null;
      if (moved || e.button !== 0) return;
      select(sc.pick(e.clientX, e.clientY));
    });

    // ---------------------------------------------------------------- views
    function fitDistance(halfW, halfH) {
      var tanV = Math.tan(camera.fov * Math.PI / 360);
      return Math.max(halfH / tanV, halfW / (tanV * camera.aspect));
    }
    function place(pos, target) {
      setFollowFlag(false);
      camera.position.copy(pos);
      controls.target.copy(target);
      controls.update();
    }
    function setFollowFlag(on) {
      state.follow = on;
      $('v-follow').classList.toggle('on', on);
    }
    function viewDefault() {   // from the south-west, above
      var radius = 0.5 * Math.hypot(P[0], P[1], P[2]);
      var d = 0.78 * radius / Math.sin(camera.fov * Math.PI / 360);
      var dir = new THREE.Vector3(-0.42, -0.78, 0.62).normalize();
      place(CENTRE.clone().add(dir.multiplyScalar(d)), CENTRE);
    }
    function viewTop() {   // from above, north up on the screen
      var d = fitDistance(P[1] / 2 * 1.12, P[0] / 2 * 1.12) + P[2] / 2;
      place(CENTRE.clone().add(new THREE.Vector3(0, -1e-3 * d, d)), CENTRE);
    }
    function viewSide() {  // from the east, north to the right, surface at the top
      var d = fitDistance(P[0] / 2 * 1.1, P[2] / 2 * 1.3) + P[1] / 2;
      place(CENTRE.clone().add(new THREE.Vector3(d, 0, 0)), CENTRE);
    }

    // ---------------------------------------------------------------- timeline strip
    var tlCanvas = $('timeline');
    var tlCtx = tlCanvas.getContext('2d');
    var tlStatic = document.createElement('canvas');
    var TL_PAD = { l: 8, r: 8, t: 14, b: 14 };
    function tlX(t, w) { return TL_PAD.l + (w - TL_PAD.l - TL_PAD.r) * (T_END > 0 ? t / T_END : 0); }
    function drawTimelineStatic() {
      var dpr = window.devicePixelRatio || 1;
      var w = tlCanvas.clientWidth, h = tlCanvas.clientHeight;
      tlCanvas.width = tlStatic.width = Math.max(1, Math.round(w * dpr));
      tlCanvas.height = tlStatic.height = Math.max(1, Math.round(h * dpr));
      var c = tlStatic.getContext('2d');
      c.setTransform(dpr, 0, 0, dpr, 0, 0);
      c.fillStyle = '#0b1c29';
      c.fillRect(0, 0, w, h);
      var y0 = h - TL_PAD.b, y1 = TL_PAD.t, ph = y0 - y1;
      c.strokeStyle = '#1c3446';
      c.beginPath(); c.moveTo(TL_PAD.l, y0 + 0.5); c.lineTo(w - TL_PAD.r, y0 + 0.5);
      c.moveTo(TL_PAD.l, y1 + 0.5); c.lineTo(w - TL_PAD.r, y1 + 0.5); c.stroke();
      var maxCol = 0;
      for (var k = 0; k < SECONDS; k++) maxCol = Math.max(maxCol, tl.collided[k] || 0);
      // Collisions per second: bars, scaled to the largest.
      if (maxCol > 0) {
        c.fillStyle = OUTCOMES[1].hex; c.globalAlpha = 0.45;
        for (k = 0; k < SECONDS; k++) {
          var bh = ph * (tl.collided[k] || 0) / maxCol;
          var xa = tlX(k, w), xb = tlX(Math.min(k + 1, T_END), w);
          c.fillRect(xa, y0 - bh, Math.max(1, xb - xa - 0.5), bh);
        }
        c.globalAlpha = 1;
      }
      function series(values, color) {
        c.strokeStyle = color; c.lineWidth = 1.5; c.beginPath();
        var pen = false;
        for (var k = 0; k < SECONDS; k++) {
          var v = values(k);
          if (!(v >= 0)) { pen = false; continue; }
          var x = tlX(Math.min(k + 0.5, T_END), w), y = y0 - ph * Math.min(v, 1);
          if (pen) c.lineTo(x, y); else c.moveTo(x, y);
          pen = true;
        }
        c.stroke();
      }
      series(function (k) { return tl.attempted[k] > 0 ? tl.delivered[k] / tl.attempted[k] : NaN; }, OUTCOMES[0].hex);
      series(function (k) { return tl.largest_fraction ? tl.largest_fraction[k] : NaN; }, '#58a6ff');
      c.font = '10px system-ui, sans-serif';
      c.textBaseline = 'top';
      var labels = [['delivery ratio', OUTCOMES[0].hex], ['largest component / vehicles', '#58a6ff'],
        ['collisions/s (max ' + maxCol + ')', OUTCOMES[1].hex]];
      var lx = TL_PAD.l + 2;
      labels.forEach(function (l) {
        c.fillStyle = l[1]; c.fillText(l[0], lx, 1); lx += c.measureText(l[0]).width + 14;
      });
      c.fillStyle = '#6f8ba0'; c.textBaseline = 'bottom';
      var step = niceStep(T_END, w / 70);
      for (var s = 0; s <= T_END + 1e-9; s += step) {
        var x = tlX(s, w);
        c.fillRect(x, y0, 1, 3);
        c.fillText(fmt(s, step < 1 ? 1 : 0) + ' s', Math.min(x + 2, w - 30), h);
      }
      if (SECONDS === 0) { c.fillText('no link statistics', w / 2 - 40, h / 2); }
    }
    function drawTimelineCursor() {
      var w = tlCanvas.clientWidth, h = tlCanvas.clientHeight, dpr = tlCanvas.width / Math.max(w, 1);
      tlCtx.setTransform(1, 0, 0, 1, 0, 0);
      tlCtx.drawImage(tlStatic, 0, 0);
      tlCtx.setTransform(dpr, 0, 0, dpr, 0, 0);
      var x = tlX(state.t, w);
      tlCtx.fillStyle = '#ffe45c';
      tlCtx.fillRect(x - 0.75, 0, 1.5, h);
    }
    var tlDrag = false;
    function tlSeek(e) {
      var r = tlCanvas.getBoundingClientRect();
      var f = (e.clientX - r.left - TL_PAD.l) / Math.max(r.width - TL_PAD.l - TL_PAD.r, 1);
      seek(Math.min(Math.max(f, 0), 1) * T_END);
    }
    tlCanvas.addEventListener('pointerdown', function (e) {
      tlDrag = true;
      try { tlCanvas.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic event */ }
      tlSeek(e);
    });
    tlCanvas.addEventListener('pointermove', function (e) { if (tlDrag) tlSeek(e); });
    tlCanvas.addEventListener('pointerup', function () { tlDrag = false; });

    var panelShown = -2, panelAt = -1;
    function updatePanel(t, now) {
      var i = state.selected;
      if (i < 0) return;
      if (panelShown === i && now - panelAt < 150) return;
      panelShown = i; panelAt = now;
      var c = 6 * i;
      var g = meta.group_of[i] | 0;
      text('p-name', meta.names[i] || ('vehicle ' + i));
      text('p-group', (meta.groups[g] ? meta.groups[g].name : String(g)));
      var row = Math.min(Math.floor(t / PANEL_DT + 1e-9), PANEL_ROWS - 1);
      var rowT = fmt(row * PANEL_DT, 0) + ' s';
      function pv(name) {
        var k = col[name];
        if (row < 0 || k === undefined) return NaN;
        return panel[(row * N + i) * PW + k];
      }
      var reading = pv('depth_reading_m');
      text('p-depth', fmt(cur[c + 2], 2) + ' m' + (isFinite(reading) ? ' (sensor ' + fmt(reading, 2) + ' m)' : ''));
      text('p-heading', fmt(deg360(cur[c + 5]), 0) + '°');
      var mode = pv('mode');
      text('p-mode', isFinite(mode) ? (meta.modes[mode | 0] || String(mode)) : '—');
      var dsp = pv('depth_setpoint_m'), ysp = pv('yaw_setpoint_rad');
      text('p-depth-sp', isFinite(dsp) ? fmt(dsp, 2) + ' m' : '—');
      text('p-heading-sp', isFinite(ysp) ? fmt(deg360(ysp), 0) + '°' : '—');
      var sent = pv('frames_sent'), recv = pv('frames_received');
      text('p-sent', isFinite(sent) ? String(sent) : '—');
      text('p-received', isFinite(recv) ? String(recv) : '—');
      // Current neighbours: senders whose frames reached it in the last second.
      var heard = {};
      var hi = upperBound(links.t, t), lo = upperBound(links.t, t - 1);
      for (var k = lo; k < hi; k++) {
        if (links.to[k] === i && links.outcome[k] === 0) heard[links.from[k]] = true;
      }
      var names = Object.keys(heard).map(function (j) { return meta.names[j] || ('#' + j); }).sort();
      var count = pv('neighbours');
      var shown = names.length > 12 ? names.slice(0, 12).join(', ') + ', … (' + names.length + ')' : names.join(', ');
      text('p-neighbours', (names.length ? shown : 'none') + ' (last 1 s' +
        (isFinite(count) && count !== names.length ? '; ' + count + ' at t = ' + rowT : '') + ')');
      text('p-note', PANEL_ROWS > 0 ? 'panel values at t = ' + rowT + (thinned ? '; neighbours from a sample of the link events' : '') : 'no panel values');
    }

    var thinned = meta.links_total > links.length;
    function updateInfo() {
      var fr = Math.min(Math.round(state.t / DT), F - 1);
      info.textContent = '';
      var b = document.createElement('span');
      b.className = 'world';
      b.textContent = meta.world;
      info.appendChild(b);
      var lines = '\n' + N + ' vehicles · t = ' + fmt(state.t, 2) + ' / ' + fmt(T_END, 1) + ' s · frame ' +
        fr + ' / ' + (F - 1) + ' (' + fmt(1 / DT, DT < 1 ? 0 : 2) + ' fps)' +
        '\nlink attempts: ' + meta.links_total + (SECONDS ? ', delivered ' + sum(tl.delivered) : '') +
        (thinned ? '\nshowing ' + links.length + ' of ' + meta.links_total + ' link events' : '') +
        '\nlines now: ' + sc.shownLinks() + (state.onlyDelivered ? ' (delivered only)' : '') +
        (sc.shownAcks() ? ', ' + sc.shownAcks() + ' of them acknowledgements' : '');
      info.appendChild(document.createTextNode(lines));
    }

    // ---------------------------------------------------------------- loop
    var framesRendered = 0, lastNow = -1, frameSum = 0, frameCount = 0, updSum = 0, updCount = 0;
    var lastInfo = -1e9, lastFollow = null;
    var glRenderer = sc.rendererName();
    // Exact counters for measuring tools (scripts/replay-frame-times.py), every frame.
    var stats = window.shoalReplayStats = { frames: 0, updateMsSum: 0, now: 0 };
    function resize() {
      var w = Math.max(view.clientWidth, 1), h = Math.max(view.clientHeight, 1);
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      drawTimelineStatic();
      dirty = true;
    }
    addEventListener('resize', resize);
    resize();
    viewDefault();
    applyHash();

    function frame(now) {
      requestAnimationFrame(frame);
      try {
        tick(now);
      } catch (e) {
        fail((e && e.stack) || e);
        throw e;
      }
    }
    function tick(now) {
      if (lastNow >= 0) {
        var dtReal = Math.min((now - lastNow) / 1000, 0.25);
        frameSum += now - lastNow; frameCount++;
        if (state.playing) {
          state.t += dtReal * state.speed;
          if (state.t >= T_END) { state.t = T_END; setPlaying(false); }
          dirty = true;
        }
      }
      lastNow = now;
      var u0 = performance.now();
      if (dirty) {
        sc.updatePoses(state.t, state);
        sc.updateSelection(state);
        sc.updateSpheres(state);
        sc.updateLinks(state.t, state);
        sc.updateTrails(state.t, state);
        showTime();
        drawTimelineCursor();
        dirty = false;
      }
      if (state.follow && state.selected >= 0) {
        var p = vehicleDisplay(state.selected);
        if (lastFollow) camera.position.add(p.clone().sub(lastFollow));
        controls.target.copy(p);
        lastFollow = p;
      } else {
        lastFollow = null;
      }
      updatePanel(state.t, now);
      if (now - lastInfo > 200) { updateInfo(); lastInfo = now; }
      updSum += performance.now() - u0; updCount++;
      controls.update();
      renderer.render(scene, camera);
      framesRendered++;
      stats.frames = framesRendered; stats.updateMsSum = updSum; stats.now = performance.now();
      if (hashClicks) clickFromHash();
      if (framesRendered === 1 || framesRendered % 10 === 0) report();
    }
    function report() {
      var d = document.documentElement.dataset;
      if (d.status !== 'error') d.status = 'ok';
      d.framesRendered = String(framesRendered);
      d.vehicles = String(N);
      d.meanFrameMs = frameCount ? (frameSum / frameCount).toFixed(2) : '';
      d.meanUpdateMs = updCount ? (updSum / updCount).toFixed(3) : '';
      d.glRenderer = glRenderer;
      d.threeRevision = THREE.REVISION;
      var lc = sc.linkCounts();
      d.linkLines = lc.lines.join(' ');
      d.ackLines = lc.acks.join(' ');
      d.linkSegments = String(lc.segments);
      document.title = 'shoal replay: ' + framesRendered + ' frames rendered';
    }
    requestAnimationFrame(frame);

    // ---------------------------------------------------------------- helpers
    /** Initial state from the address's #fragment, e.g. replay.html#t=12.5&view=top&select=auv03&paused:
     * t [s], speed, paused, view (top|side|follow), select (name or index), ranges (off|selected|all),
     * trails (0|1), delivered (delivered only), size (1|2|4); aa=0 (no antialiasing) is read at start;
     * lod=0..3 (detail of the hulls) is read at start; click and tlclick (see clickFromHash). */
    function applyHash() {
      var h = (location.hash || '').replace(/^#/, '');
      if (!h) return;
      var q = {};
      h.split('&').forEach(function (kv) {
        var p = kv.split('=');
        q[decodeURIComponent(p[0])] = p.length > 1 ? decodeURIComponent(p.slice(1).join('=')) : '1';
      });
      if (q.t !== undefined && isFinite(+q.t)) seek(+q.t);
      if (q.speed !== undefined && [0.25, 0.5, 1, 2, 4, 8, 16].indexOf(+q.speed) >= 0) setSpeed(+q.speed);
      if (q.paused !== undefined) setPlaying(false);
      if (q.select !== undefined) {
        var i = meta.names.indexOf(q.select);
        if (i < 0 && /^[0-9]+$/.test(q.select) && +q.select < N) i = +q.select;
        if (i >= 0) select(i);
      }
      if (q.ranges === 'off' || q.ranges === 'selected' || q.ranges === 'all') { state.ranges = q.ranges; updateRangeButton(); }
      if (q.trails !== undefined && !$('trails').disabled) { state.trails = q.trails !== '0'; $('trails').checked = state.trails; }
      if (q.delivered !== undefined) { state.onlyDelivered = q.delivered !== '0'; $('only-delivered').checked = state.onlyDelivered; }
      while (q.size !== undefined && state.size < Math.min(+q.size || 1, 4)) cycleSize();
      if (q.view === 'top') viewTop();
      else if (q.view === 'side') viewSide();
      else if (q.view === 'follow') { sc.updatePoses(state.t, state); setFollow(true); }
      dirty = true;
      hashClicks = q;
    }
    /** After the first frame: the clicks the #fragment asks for, as real DOM events (so headless
     * tests exercise the handlers): click=NAME clicks where that vehicle is drawn, tlclick=F
     * clicks the timeline at the fraction F of its width. */
    var hashClicks;
    function clickFromHash() {
      var q = hashClicks;
      hashClicks = null;
      if (q.click !== undefined) {
        var i = meta.names.indexOf(q.click);
        if (i >= 0) {
          var v = vehicleDisplay(i).project(camera), r = renderer.domElement.getBoundingClientRect();
          var at = { clientX: r.left + (v.x + 1) / 2 * r.width, clientY: r.top + (1 - v.y) / 2 * r.height,
            button: 0, bubbles: true };
          renderer.domElement.dispatchEvent(new MouseEvent('click', at));
        }
      }
      if (q.tlclick !== undefined && isFinite(+q.tlclick)) {
        var b = tlCanvas.getBoundingClientRect();
        var p = { clientX: b.left + TL_PAD.l + (+q.tlclick) * (b.width - TL_PAD.l - TL_PAD.r),
          clientY: b.top + b.height / 2, button: 0, bubbles: true, pointerId: 1 };
        tlCanvas.dispatchEvent(new PointerEvent('pointerdown', p));
        tlCanvas.dispatchEvent(new PointerEvent('pointerup', p));
      }
    }
    function text(id, s) {
      var e = document.getElementById(id);
      if (e.textContent !== s) e.textContent = s;
    }
  }

  try {
    main();
  } catch (e) {
    fail((e && e.stack) || e);
  }
})();
