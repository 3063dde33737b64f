/* shoal replay viewer, part 2 of 3: the 3D scene — pool, obstacles, vehicles, link lines,
 * trails and range spheres — drawn with three.js (global THREE, the vendored bundle in an
 * earlier script element) and updated for a time. Defines window.shoalReplay.createScene().
 *
 * Coordinates. The data is NED: x north, y east, z down, surface at z = 0, pool corner at the
 * origin; attitude is roll, pitch, yaw about body x (forward), y (starboard), z (down), applied
 * as R = Rz(yaw)·Ry(pitch)·Rx(roll). Everything from the data lives in one group, `ned`, whose
 * matrix maps NED onto the display frame
 *     three (X, Y, Z) = (y east, x north, −z)     (a proper rotation, det +1)
 * so the display is z-up (camera.up = +Z), east to the right and north away from a viewer
 * standing south. Positions, obstacle poses and vehicle matrices are written in NED inside
 * `ned`; only the camera and the lights use display coordinates (toDisplay()).
 */
(function () {
  'use strict';
  var shoal = window.shoalReplay;

  /** The scene of the replay `d` (from shoal.load()) in the element #view: renderer, camera,
   * orbit controls, and the functions that update it for a time t [s] and the viewer's state. */
  shoal.createScene = function (d) {
    var meta = d.meta, N = d.N, F = d.F, DT = d.DT, P = d.P, pos = d.pos, att = d.att;
    var links = d.links, OUTCOMES = d.OUTCOMES, PALETTE = d.PALETTE, LINK_WINDOW_S = d.LINK_WINDOW_S;
    var ACK_DASHES = d.ACK_DASHES;
    var MAX_LINES = d.MAX_LINES, TRAIL_S = d.TRAIL_S, MAX_TRAIL_SEGMENTS = d.MAX_TRAIL_SEGMENTS;
    var upperBound = shoal.upperBound;
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
    var cur = new Float32Array(cap * 6);    // current x, y, z, roll, pitch, yaw of every vehicle

    // ---------------------------------------------------------------- per-frame update
    var AS = Math.PI / 32767;
    var sx = P[0] / 65535, sy = P[1] / 65535, sz = P[2] / 65535;
    function wrap(a) { return a - 2 * Math.PI * Math.round(a / (2 * Math.PI)); }

    function updatePoses(t, state) {
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

    function updateSelection(state) {
      var i = state.selected;
      selBox.visible = i >= 0;
      if (i >= 0) {
        selBox.matrix.fromArray(hull.instanceMatrix.array, 16 * i);
        selBox.matrixWorldNeedsUpdate = true;
      }
    }

    function updateSpheres(state) {
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

    // What updateLinks drew: lines (link events) by outcome code, those of acknowledgements
    // among them, and the segments they took (an acknowledgement's line is ACK_DASHES dashes).
    var shown = { lines: [0, 0, 0, 0, 0], acks: [0, 0, 0, 0, 0], segments: 0, total: 0, totalAcks: 0 };
    function updateLinks(t, state) {
      var n = 0;
      var P3 = linkPos.array, C4 = linkCol.array;
      var hi = upperBound(links.t, t), lo = upperBound(links.t, t - LINK_WINDOW_S);
      shown.lines.fill(0); shown.acks.fill(0); shown.total = 0; shown.totalAcks = 0;
      for (var k = hi - 1; k >= lo; k--) {
        var oc = links.outcome[k];
        if (state.onlyDelivered && oc !== 0) continue;
        var code = OUTCOMES[oc] ? oc : 3;
        var st = OUTCOMES[code];
        var s = 6 * links.from[k], r = 6 * links.to[k];
        if (s >= 6 * N || r >= 6 * N) continue;
        // An acknowledgement: dashes and equal gaps, the first at the sender.
        var pieces = links.ack[k] ? ACK_DASHES : 1;
        if (n + pieces > MAX_LINES) break;
        var fade = 1 - (t - links.t[k]) / LINK_WINDOW_S;
        var a = st.alpha * Math.max(fade, 0);
        var x = cur[s], y = cur[s + 1], z = cur[s + 2];
        var dx = st.reach * (cur[r] - x), dy = st.reach * (cur[r + 1] - y), dz = st.reach * (cur[r + 2] - z);
        for (var j = 0; j < pieces; j++) {
          var f0 = 2 * j / (2 * pieces - 1), f1 = (2 * j + 1) / (2 * pieces - 1);
          var o = 6 * n;
          P3[o] = x + f0 * dx; P3[o + 1] = y + f0 * dy; P3[o + 2] = z + f0 * dz;
          P3[o + 3] = x + f1 * dx; P3[o + 4] = y + f1 * dy; P3[o + 5] = z + f1 * dz;
          var q = 8 * n;
          C4[q] = C4[q + 4] = st.color[0]; C4[q + 1] = C4[q + 5] = st.color[1]; C4[q + 2] = C4[q + 6] = st.color[2];
          // Brighter at the sender: from a there to 0.35 a at the line's end.
          C4[q + 3] = a * (1 - 0.65 * f0); C4[q + 7] = a * (1 - 0.65 * f1);
          n++;
        }
        shown.lines[code]++; shown.total++;
        if (pieces > 1) { shown.acks[code]++; shown.totalAcks++; }
      }
      shown.segments = n;
      linkGeo.setDrawRange(0, 2 * n);
      linkPos.clearUpdateRanges(); linkPos.addUpdateRange(0, 6 * n); linkPos.needsUpdate = true;
      linkCol.clearUpdateRanges(); linkCol.addUpdateRange(0, 8 * n); linkCol.needsUpdate = true;
    }

    function updateTrails(t, state) {
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

    // Click a vehicle: the vehicle drawn at the client point (x, y), or -1.
    var raycaster = new THREE.Raycaster();
    function pick(clientX, clientY) {
      var r = renderer.domElement.getBoundingClientRect();
      var ndc = new THREE.Vector2((clientX - r.left) / r.width * 2 - 1, -(clientY - r.top) / r.height * 2 + 1);
      raycaster.setFromCamera(ndc, camera);
      hull.computeBoundingSphere();
      var hit = N > 0 ? raycaster.intersectObject(hull, false) : [];
      return hit.length ? hit[0].instanceId : -1;
    }

    return {
      renderer: renderer, scene: scene, camera: camera, controls: controls, CENTRE: CENTRE,
      cur: cur, RANGE: RANGE, trailFrames: trailFrames, toDisplay: toDisplay,
      vehicleDisplay: vehicleDisplay, rendererName: rendererName, pick: pick,
      updatePoses: updatePoses, updateSelection: updateSelection, updateSpheres: updateSpheres,
      updateLinks: updateLinks, updateTrails: updateTrails,
      shownLinks: function () { return shown.total; },
      shownAcks: function () { return shown.totalAcks; },
      /* Lines drawn now by outcome code, acknowledgements among them, segments (tests read these). */
      linkCounts: function () { return shown; }
    };
  };
})();
