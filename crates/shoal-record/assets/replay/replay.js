/* shoal replay viewer: draws the run embedded in this page with three.js (global THREE, the
 * vendored bundle in the script element before this one). Nothing is loaded from anywhere.
 *
 * Data (see crates/shoal-sim/src/replay/mod.rs): the JSON header #shoal-meta and four
 * little-endian arrays as base64 — #shoal-pos (u16, frames × vehicles × 3, x = q/65535·pool.x),
 * #shoal-att (i16, frames × vehicles × 3: roll, pitch, yaw = q·π/32767), #shoal-panel (f32,
 * rows × vehicles × meta.panel.length, a row every meta.panel_dt s) and #shoal-links (events × 16 bytes: t f32, sender
 * u32, receiver u32, outcome u32). They are decoded once and their elements removed.
 *
 * Coordinates. The data is NED: x north, y east, z down, surface at z = 0, pool corner at the
 * origin; attitude is roll, pitch, yaw about body x (forward), y (starboard), z (down), applied
 * as R = Rz(yaw)·Ry(pitch)·Rx(roll). Everything from the data lives in one group, `ned`, whose
 * matrix maps NED onto the display frame
 *     three (X, Y, Z) = (y east, x north, −z)     (a proper rotation, det +1)
 * so the display is z-up (camera.up = +Z), east to the right and north away from a viewer
 * standing south. Positions, obstacle poses and vehicle matrices are written in NED inside
 * `ned`; only the camera and the lights use display coordinates (toDisplay()).
 *
 * Status for headless tests: every 10 rendered frames (and after the first) <html> gets
 * data-status="ok" data-frames-rendered data-vehicles data-mean-frame-ms data-mean-update-ms
 * data-gl-renderer data-three-revision, and document.title says how many frames were rendered;
 * data-link-colors lists the colours the link lines are drawn in (from meta.outcomes);
 * data-decoder says how the base64 was decoded (fromBase64 or atob).
 * Failures are recorded by the guard script in <head> (data-status="error", data-errors).
 */
(function () {
  'use strict';
  var fail = window.__shoalFail || function (m) { throw new Error(m); };
  var LITTLE = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

  function main() {
    // ---------------------------------------------------------------- data
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
    var LINK_WINDOW_S = 0.3;   // link events shown this long after they happen [s]
    var MAX_LINES = 20000;     // link lines drawn at once at most
    var TRAIL_S = 4;           // trail length [s]
    var MAX_TRAIL_SEGMENTS = 120000;
    var PALETTE = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',
      '#7f7f7f', '#bcbd22', '#17becf'];

    // ---------------------------------------------------------------- scene
    var view = document.getElementById('view');
    var renderer;
    try {
      // #aa=0 in the address turns multisampling off (faster on software renderers).
      var aa = !/(^#|&)aa=0(&|$)/.test(location.hash || '');
      renderer = new THREE.WebGLRenderer({ antialias: aa, preserveDrawingBuffer: true });
    } catch (e) {
      throw new Error('WebGL is not available: ' + (e && e.message || e));
    }
    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    view.appendChild(renderer.domElement);
    var scene = new THREE.Scene();
    scene.background = new THREE.Color(0x07141f);
    var camera = new THREE.PerspectiveCamera(45, 16 / 9, 0.02, 500);
    camera.up.set(0, 0, 1);
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.enableDamping = false;
    controls.screenSpacePanning = true;

    scene.add(new THREE.HemisphereLight(0xd6ecff, 0x0b2233, 1.6));
    var sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(P[1] * 0.3 + 4, -6, 12);
    scene.add(sun);

    var ned = new THREE.Group();
    ned.matrixAutoUpdate = false;
    ned.matrix.set(0, 1, 0, 0, 1, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1);
    ned.matrixWorldNeedsUpdate = true;
    scene.add(ned);
    function toDisplay(x, y, z) { return new THREE.Vector3(y, x, -z); }
    var CENTRE = toDisplay(P[0] / 2, P[1] / 2, P[2] / 2);

    buildPool();
    buildObstacles();

    // Vehicles: one InstancedMesh per body part, all sharing one instance-matrix attribute.
    // Unit body: length, width, height 1 along body x, y, z; each instance is scaled by its
    // group's hull size.
    var cap = Math.max(N, 1);
    // Fewer triangles per vehicle for bigger swarms: detail 0–3 = 596, 216, 106 and 36
    // triangles (3: box hull and bow); #lod=N in the address overrides the choice.
    var lodHash = /(^#|&)lod=([0-3])(&|$)/.exec(location.hash || '');
    var lod = lodHash ? +lodHash[2] : N <= 300 ? 0 : N <= 2000 ? 1 : N <= 5000 ? 2 : 3;
    var LOD = [[6, 16, 12, 8], [3, 10, 8, 5], [2, 7, 6, 3]][lod];
    var hullGeo, noseGeo;
    if (LOD) {
      hullGeo = new THREE.CapsuleGeometry(0.5, 0.5, LOD[0], LOD[1]);
      hullGeo.rotateZ(-Math.PI / 2);           // capsule axis y → body x (forward)
      hullGeo.scale(1 / 1.5, 1, 1);            // total length 1
      noseGeo = new THREE.SphereGeometry(0.2, LOD[2], LOD[3]);
    } else {
      hullGeo = new THREE.BoxGeometry(1, 0.9, 0.9);
      noseGeo = new THREE.BoxGeometry(0.2, 0.45, 0.45);
    }
    var hull = new THREE.InstancedMesh(hullGeo,
      new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.45, metalness: 0.1 }), cap);
    noseGeo.translate(0.5, 0, 0);              // the bow
    var nose = new THREE.InstancedMesh(noseGeo, new THREE.MeshBasicMaterial({ color: 0xfff2a8 }), cap);
    var finGeo = new THREE.BoxGeometry(0.4, 0.08, 0.3);
    finGeo.translate(-0.1, 0, -0.55);          // on top (body z is down)
    var fin = new THREE.InstancedMesh(finGeo,
      new THREE.MeshStandardMaterial({ color: 0x1b2733, roughness: 0.8 }), cap);
    hull.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    nose.instanceMatrix = hull.instanceMatrix;
    fin.instanceMatrix = hull.instanceMatrix;
    var groupColors = (meta.groups || []).map(function (g, i) {
      return new THREE.Color(g.color || PALETTE[i % PALETTE.length]);
    });
    var hullSize = new Float32Array(cap * 3);
    for (var i = 0; i < N; i++) {
      var g = meta.group_of[i] | 0;
      hull.setColorAt(i, groupColors[g] || new THREE.Color(PALETTE[g % PALETTE.length]));
      var hs = (meta.hull && meta.hull[g]) || [0.27, 0.16, 0.18];
      hullSize[3 * i] = hs[0]; hullSize[3 * i + 1] = hs[1]; hullSize[3 * i + 2] = hs[2];
    }
    [hull, nose, fin].forEach(function (m) { m.count = N; m.frustumCulled = false; ned.add(m); });
    if (hull.instanceColor) hull.instanceColor.needsUpdate = true;

    // The selected vehicle: a box around it.
    var selBox = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(1.3, 1.7, 1.7)),
      new THREE.LineBasicMaterial({ color: 0xffe45c }));
    selBox.matrixAutoUpdate = false;
    selBox.visible = false;
    ned.add(selBox);

    /* `segments` line segments, preallocated and updated in place, with RGBA vertex colours
     * (alpha fades), added to the scene: { geo, pos, col, lines }. */
    function dynamicSegments(segments) {
      var geo = new THREE.BufferGeometry();
      var pos = new THREE.BufferAttribute(new Float32Array(segments * 6), 3);
      var col = new THREE.BufferAttribute(new Float32Array(segments * 8), 4);
      pos.setUsage(THREE.DynamicDrawUsage);
      col.setUsage(THREE.DynamicDrawUsage);
      geo.setAttribute('position', pos);
      geo.setAttribute('color', col);
      geo.setDrawRange(0, 0);
      var lines = new THREE.LineSegments(geo, new THREE.LineBasicMaterial({
        vertexColors: true, transparent: true, depthWrite: false }));
      lines.frustumCulled = false;
      ned.add(lines);
      return { geo: geo, pos: pos, col: col, lines: lines };
    }

    // Link lines: one LineSegments of MAX_LINES.
    var linkSeg = dynamicSegments(MAX_LINES);
    var linkGeo = linkSeg.geo, linkPos = linkSeg.pos, linkCol = linkSeg.col;

    // Trails: one LineSegments, at most MAX_TRAIL_SEGMENTS segments for the whole swarm.
    var trailFrames = N > 0 ? Math.min(Math.round(TRAIL_S / DT), Math.floor(MAX_TRAIL_SEGMENTS / N)) : 0;
    var trailStep = trailFrames > 0 ? Math.max(1, Math.round(TRAIL_S / DT / trailFrames)) : 1;
    var trailSeg = dynamicSegments(Math.max(trailFrames * N, 1));
    var trailGeo = trailSeg.geo, trailPos = trailSeg.pos, trailCol = trailSeg.col;
    var trails = trailSeg.lines;

    // Modem range spheres (radius meta.modem_range_m).
    var RANGE = meta.modem_range_m > 0 ? meta.modem_range_m : 0;
    var spheres = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 24, 14),
      // Back faces only: the far half of a sphere is behind its own vehicle and never veils it.
      new THREE.MeshBasicMaterial({ color: 0x55c7ff, transparent: true, opacity: 0.045, depthWrite: false,
        side: THREE.BackSide }), cap);
    spheres.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    spheres.frustumCulled = false;
    spheres.count = 0;
    ned.add(spheres);

    // ---------------------------------------------------------------- state
    var state = {
      t: 0, playing: true, speed: 1, selected: -1, follow: false,
      onlyDelivered: false, ranges: RANGE > 0 ? 'selected' : 'off',
      trails: N <= 200 && trailFrames >= 2, size: 1
    };
    var cur = new Float32Array(cap * 6);    // current x, y, z, roll, pitch, yaw of every vehicle
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
      if (i >= 0) { updateSelection(); updatePanel(state.t, performance.now()); }
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
    var raycaster = new THREE.Raycaster();
    var down = null;
    renderer.domElement.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('click', function (e) {
      var moved = down && Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 5;
      down = null;
      if (moved || e.button !== 0) return;
      var r = renderer.domElement.getBoundingClientRect();
      var ndc = new THREE.Vector2((e.clientX - r.left) / r.width * 2 - 1, -(e.clientY - r.top) / r.height * 2 + 1);
      raycaster.setFromCamera(ndc, camera);
      hull.computeBoundingSphere();
      var hit = N > 0 ? raycaster.intersectObject(hull, false) : [];
      select(hit.length ? hit[0].instanceId : -1);
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

    // ---------------------------------------------------------------- per-frame update
    var AS = Math.PI / 32767;
    var sx = P[0] / 65535, sy = P[1] / 65535, sz = P[2] / 65535;
    function wrap(a) { return a - 2 * Math.PI * Math.round(a / (2 * Math.PI)); }

    function updatePoses(t) {
      var fr = Math.min(Math.max(t / DT, 0), F - 1);
      var f0 = Math.floor(fr), f1 = Math.min(f0 + 1, F - 1), w = fr - f0;
      var a = f0 * N * 3, b = f1 * N * 3;
      var m = hull.instanceMatrix.array;
      for (var i = 0; i < N; i++, a += 3, b += 3) {
        var x = (pos[a] + w * (pos[b] - pos[a])) * sx;
        var y = (pos[a + 1] + w * (pos[b + 1] - pos[a + 1])) * sy;
        var z = (pos[a + 2] + w * (pos[b + 2] - pos[a + 2])) * sz;
        var r0 = att[a] * AS, p0 = att[a + 1] * AS, y0 = att[a + 2] * AS;
        var roll = r0 + w * wrap(att[b] * AS - r0);
        var pitch = p0 + w * wrap(att[b + 1] * AS - p0);
        var yaw = y0 + w * wrap(att[b + 2] * AS - y0);
        var c = 6 * i;
        cur[c] = x; cur[c + 1] = y; cur[c + 2] = z; cur[c + 3] = roll; cur[c + 4] = pitch; cur[c + 5] = yaw;
        // Column-major: columns are the body axes scaled by the hull size, then the position.
        var cf = Math.cos(roll), sf = Math.sin(roll), ct = Math.cos(pitch), st = Math.sin(pitch);
        var cp = Math.cos(yaw), sp = Math.sin(yaw);
        var L = hullSize[3 * i] * state.size, W = hullSize[3 * i + 1] * state.size, H = hullSize[3 * i + 2] * state.size;
        var o = 16 * i;
        m[o] = cp * ct * L; m[o + 1] = sp * ct * L; m[o + 2] = -st * L; m[o + 3] = 0;
        m[o + 4] = (cp * st * sf - sp * cf) * W; m[o + 5] = (sp * st * sf + cp * cf) * W; m[o + 6] = ct * sf * W; m[o + 7] = 0;
        m[o + 8] = (cp * st * cf + sp * sf) * H; m[o + 9] = (sp * st * cf - cp * sf) * H; m[o + 10] = ct * cf * H; m[o + 11] = 0;
        m[o + 12] = x; m[o + 13] = y; m[o + 14] = z; m[o + 15] = 1;
      }
      hull.instanceMatrix.needsUpdate = true;
    }

    function updateSelection() {
      var i = state.selected;
      selBox.visible = i >= 0;
      if (i >= 0) {
        selBox.matrix.fromArray(hull.instanceMatrix.array, 16 * i);
        selBox.matrixWorldNeedsUpdate = true;
      }
    }

    function updateSpheres() {
      if (RANGE > 0 && state.ranges === 'all') {
        spheres.count = N;
        for (var i = 0; i < N; i++) sphereAt(i, i);
      } else if (RANGE > 0 && state.ranges === 'selected' && state.selected >= 0) {
        spheres.count = 1;
        sphereAt(0, state.selected);
      } else {
        spheres.count = 0;
      }
      spheres.instanceMatrix.needsUpdate = true;
    }
    function sphereAt(k, i) {
      var m = spheres.instanceMatrix.array, o = 16 * k, c = 6 * i;
      for (var j = 0; j < 16; j++) m[o + j] = 0;
      m[o] = m[o + 5] = m[o + 10] = RANGE;
      m[o + 12] = cur[c]; m[o + 13] = cur[c + 1]; m[o + 14] = cur[c + 2]; m[o + 15] = 1;
    }

    var shownLinks = 0;
    function updateLinks(t) {
      var n = 0;
      var P3 = linkPos.array, C4 = linkCol.array;
      var hi = upperBound(links.t, t), lo = upperBound(links.t, t - LINK_WINDOW_S);
      for (var k = hi - 1; k >= lo && n < MAX_LINES; k--) {
        var oc = links.outcome[k];
        if (state.onlyDelivered && oc !== 0) continue;
        var st = OUTCOMES[oc] || OUTCOMES[3];
        var s = 6 * links.from[k], r = 6 * links.to[k];
        if (s >= 6 * N || r >= 6 * N) continue;
        var fade = 1 - (t - links.t[k]) / LINK_WINDOW_S;
        var a = st.alpha * Math.max(fade, 0);
        var o = 6 * n;
        P3[o] = cur[s]; P3[o + 1] = cur[s + 1]; P3[o + 2] = cur[s + 2];
        P3[o + 3] = cur[s] + st.reach * (cur[r] - cur[s]);
        P3[o + 4] = cur[s + 1] + st.reach * (cur[r + 1] - cur[s + 1]);
        P3[o + 5] = cur[s + 2] + st.reach * (cur[r + 2] - cur[s + 2]);
        var q = 8 * n;
        C4[q] = C4[q + 4] = st.color[0]; C4[q + 1] = C4[q + 5] = st.color[1]; C4[q + 2] = C4[q + 6] = st.color[2];
        C4[q + 3] = a; C4[q + 7] = a * 0.35;   // brighter at the sender
        n++;
      }
      shownLinks = n;
      linkGeo.setDrawRange(0, 2 * n);
      linkPos.clearUpdateRanges(); linkPos.addUpdateRange(0, 6 * n); linkPos.needsUpdate = true;
      linkCol.clearUpdateRanges(); linkCol.addUpdateRange(0, 8 * n); linkCol.needsUpdate = true;
    }

    function updateTrails(t) {
      if (!state.trails || trailFrames < 2) { trailGeo.setDrawRange(0, 0); trails.visible = false; return; }
      trails.visible = true;
      var P3 = trailPos.array, C4 = trailCol.array, n = 0;
      var fnow = Math.min(Math.floor(t / DT), F - 1);
      for (var i = 0; i < N; i++) {
        var g = groupColors[meta.group_of[i] | 0] || new THREE.Color(0xffffff);
        var px = cur[6 * i], py = cur[6 * i + 1], pz = cur[6 * i + 2];
        for (var j = 0; j < trailFrames; j++) {
          var f = fnow - j * trailStep;
          if (f < 0) break;
          var a = (f * N + i) * 3;
          var x = pos[a] * sx, y = pos[a + 1] * sy, z = pos[a + 2] * sz;
          var o = 6 * n;
          P3[o] = px; P3[o + 1] = py; P3[o + 2] = pz; P3[o + 3] = x; P3[o + 4] = y; P3[o + 5] = z;
          var q = 8 * n, a0 = 0.8 * (1 - j / trailFrames), a1 = 0.8 * (1 - (j + 1) / trailFrames);
          C4[q] = C4[q + 4] = g.r; C4[q + 1] = C4[q + 5] = g.g; C4[q + 2] = C4[q + 6] = g.b;
          C4[q + 3] = a0; C4[q + 7] = a1;
          px = x; py = y; pz = z;
          n++;
        }
      }
      trailGeo.setDrawRange(0, 2 * n);
      trailPos.clearUpdateRanges(); trailPos.addUpdateRange(0, 6 * n); trailPos.needsUpdate = true;
      trailCol.clearUpdateRanges(); trailCol.addUpdateRange(0, 8 * n); trailCol.needsUpdate = true;
    }

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
        '\nlines now: ' + shownLinks + (state.onlyDelivered ? ' (delivered only)' : '');
      info.appendChild(document.createTextNode(lines));
    }

    // ---------------------------------------------------------------- loop
    var framesRendered = 0, lastNow = -1, frameSum = 0, frameCount = 0, updSum = 0, updCount = 0;
    var lastInfo = -1e9, lastFollow = null;
    var glRenderer = rendererName();
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
        updatePoses(state.t);
        updateSelection();
        updateSpheres();
        updateLinks(state.t);
        updateTrails(state.t);
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
      else if (q.view === 'follow') { updatePoses(state.t); setFollow(true); }
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
    function vehicleDisplay(i) {
      var c = 6 * i;
      return toDisplay(cur[c], cur[c + 1], cur[c + 2]);
    }
    function rendererName() {
      try {
        var gl = renderer.getContext();
        var ext = gl.getExtension('WEBGL_debug_renderer_info');
        return String(gl.getParameter(ext ? ext.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
      } catch (e) {
        return 'unknown';
      }
    }
    function buildPool() {
      var box = new THREE.BoxGeometry(P[0], P[1], P[2]);
      var walls = new THREE.Mesh(box, new THREE.MeshStandardMaterial({
        color: 0x3f8fb5, transparent: true, opacity: 0.1, depthWrite: false, side: THREE.DoubleSide }));
      walls.position.set(P[0] / 2, P[1] / 2, P[2] / 2);
      walls.renderOrder = 2;
      ned.add(walls);
      var edges = new THREE.LineSegments(new THREE.EdgesGeometry(box),
        new THREE.LineBasicMaterial({ color: 0x7cc4e4, transparent: true, opacity: 0.7 }));
      edges.position.copy(walls.position);
      ned.add(edges);
      var floor = new THREE.Mesh(new THREE.PlaneGeometry(P[0], P[1]),
        new THREE.MeshStandardMaterial({ color: 0x12303f, roughness: 1, side: THREE.DoubleSide }));
      floor.position.set(P[0] / 2, P[1] / 2, P[2]);
      ned.add(floor);
      // Floor grid: a line every metre (every 0.5 m in pools under 4 m).
      var step = Math.max(P[0], P[1]) < 4 ? 0.5 : 1, v = [];
      for (var x = 0; x <= P[0] + 1e-9; x += step) v.push(x, 0, 0, x, P[1], 0);
      for (var y = 0; y <= P[1] + 1e-9; y += step) v.push(0, y, 0, P[0], y, 0);
      var gridGeo = new THREE.BufferGeometry();
      gridGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(v), 3));
      var grid = new THREE.LineSegments(gridGeo, new THREE.LineBasicMaterial({ color: 0x2f6c8a }));
      grid.position.set(0, 0, P[2] - 0.003);
      ned.add(grid);
      var surface = new THREE.Mesh(new THREE.PlaneGeometry(P[0], P[1]), new THREE.MeshStandardMaterial({
        color: 0x6fd3ff, transparent: true, opacity: 0.16, depthWrite: false, side: THREE.DoubleSide,
        roughness: 0.2 }));
      surface.position.set(P[0] / 2, P[1] / 2, 0);
      surface.renderOrder = 3;
      ned.add(surface);
    }
    function buildObstacles() {
      var mat = new THREE.MeshStandardMaterial({ color: 0x9a8b70, roughness: 0.85 });
      (meta.obstacles || []).forEach(function (o) {
        var geo;
        if (o.kind === 'box' && o.size) {
          geo = new THREE.BoxGeometry(o.size[0], o.size[1], o.size[2]);
        } else if (o.kind === 'sphere') {
          geo = new THREE.SphereGeometry(o.radius, 32, 16);
        } else if (o.kind === 'cylinder') {
          geo = new THREE.CylinderGeometry(o.radius, o.radius, o.height, 40);   // axis local y
        } else if (o.kind === 'capsule') {
          geo = new THREE.CapsuleGeometry(o.radius, o.height, 8, 24);
          geo.rotateX(Math.PI / 2);                                            // axis y → local z
        } else {
          console.warn('replay: obstacle ' + o.name + ' of unknown kind ' + o.kind + ' drawn as a small box');
          geo = new THREE.BoxGeometry(0.2, 0.2, 0.2);
        }
        var mesh = new THREE.Mesh(geo, mat);
        mesh.position.set(o.position[0], o.position[1], o.position[2]);
        var q = o.rotation || [0, 0, 0, 1];
        mesh.quaternion.set(q[0], q[1], q[2], q[3]);
        mesh.name = o.name;
        ned.add(mesh);
        var edges = new THREE.LineSegments(new THREE.EdgesGeometry(geo, 30),
          new THREE.LineBasicMaterial({ color: 0xd9c9a6, transparent: true, opacity: 0.5 }));
        mesh.add(edges);
      });
    }
    function text(id, s) {
      var e = document.getElementById(id);
      if (e.textContent !== s) e.textContent = s;
    }
  }

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
  /** Link events as columns, sorted by time. */
  function decodeLinks(bytes) {
    var f = typed(bytes, Float32Array), u = typed(bytes, Uint32Array), n = Math.floor(f.length / 4);
    var t = new Float32Array(n), from = new Uint32Array(n), to = new Uint32Array(n), outcome = new Uint8Array(n);
    var sorted = true;
    for (var k = 0; k < n; k++) {
      t[k] = f[4 * k]; from[k] = u[4 * k + 1]; to[k] = u[4 * k + 2]; outcome[k] = Math.min(u[4 * k + 3], 255);
      if (k > 0 && t[k] < t[k - 1]) sorted = false;
    }
    if (!sorted) {
      var idx = Array.from({ length: n }, function (_, k) { return k; }).sort(function (a, b) { return t[a] - t[b]; });
      var t2 = new Float32Array(n), f2 = new Uint32Array(n), to2 = new Uint32Array(n), o2 = new Uint8Array(n);
      idx.forEach(function (j, k) { t2[k] = t[j]; f2[k] = from[j]; to2[k] = to[j]; o2[k] = outcome[j]; });
      t = t2; from = f2; to = to2; outcome = o2;
    }
    return { t: t, from: from, to: to, outcome: outcome, length: n };
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

  try {
    main();
  } catch (e) {
    fail((e && e.stack) || e);
  }
})();
