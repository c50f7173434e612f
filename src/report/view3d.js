// treedyn report's 3-D view (view3d.py inlines it after three.js). Reads the
// JSON in #treedyn-motion: times, scene (bodies, parents, shapes, dimensions,
// com_to_joint in body frames) and runs (pose rows: per body x y z q0 q1 q2 q3).
// "#frame=K" in the address starts paused at frame K (used by the tests).
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("treedyn-motion").textContent);
  var box = document.getElementById("treedyn-view");
  var scene = data.scene, n = scene.bodies.length, frames = data.times.length;

  var renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(box.clientWidth, box.clientHeight);
  renderer.setClearColor(0xffffff);
  box.appendChild(renderer.domElement);
  var world = new THREE.Scene();
  world.add(new THREE.AmbientLight(0xffffff, 0.55));
  var sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, -2, 3);
  world.add(sun);

  function quaternion(p, b) {  // pose row p, body b: q0 is the scalar
    return new THREE.Quaternion(p[7 * b + 4], p[7 * b + 5], p[7 * b + 6], p[7 * b + 3]);
  }
  function centre(p, b) { return new THREE.Vector3(p[7 * b], p[7 * b + 1], p[7 * b + 2]); }
  function joint(p, b) {  // inboard joint: CoM + A c_bb
    var c = scene.com_to_joint[b];
    return new THREE.Vector3(c[0], c[1], c[2]).applyQuaternion(quaternion(p, b)).add(centre(p, b));
  }

  function shapeGeometry(b) {
    var d = scene.dimensions[b], s = scene.shapes[b];
    if (s === "box") return new THREE.BoxBufferGeometry(d[0], d[1], d[2]);
    if (s === "sphere") return new THREE.SphereBufferGeometry(d[0], 24, 16);
    if (s === "cylinder") {  // three's cylinder runs along y; the body's along z
      var g = new THREE.CylinderBufferGeometry(d[0], d[0], d[2], 20);
      g.rotateX(Math.PI / 2);
      return g;
    }
    return new THREE.SphereBufferGeometry(size * 0.015, 16, 12);  // no shape: a dot at the CoM
  }

  var palette = [0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728, 0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f];
  // One drawn run: a mesh per shaped body and the stick figure's segments.
  function makeRun(run) {
    var drawn = {run: run, meshes: [], joints: [], sticks: null};
    var jointGeometry = new THREE.SphereBufferGeometry(size * 0.008, 12, 8);
    for (var b = 0; b < n; ++b) {
      var g = shapeGeometry(b), mesh = null;
      if (g) {
        mesh = new THREE.Mesh(g, new THREE.MeshLambertMaterial({
          color: run.ghost ? 0x999999 : palette[b % palette.length], transparent: run.ghost,
          opacity: run.ghost ? 0.18 : 1.0, depthWrite: !run.ghost}));
        world.add(mesh);
      }
      drawn.meshes.push(mesh);
      var dot = new THREE.Mesh(jointGeometry, new THREE.MeshLambertMaterial({
        color: run.ghost ? 0xaaaaaa : 0x222222, transparent: run.ghost, opacity: run.ghost ? 0.3 : 1.0}));
      world.add(dot);
      drawn.joints.push(dot);
    }
    var segments = 0;
    for (b = 0; b < n; ++b) segments += scene.parents[b] >= 0 ? 2 : 1;
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(segments * 6), 3));
    drawn.sticks = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({
      color: run.ghost ? 0xaaaaaa : 0x222222, transparent: run.ghost, opacity: run.ghost ? 0.4 : 1.0}));
    world.add(drawn.sticks);
    return drawn;
  }

  function place(drawn, k) {
    var p = drawn.run.pose[k], at = drawn.sticks.geometry.attributes.position, i = 0;
    function put(v) { at.setXYZ(i++, v.x, v.y, v.z); }
    for (var b = 0; b < n; ++b) {
      if (drawn.meshes[b]) {
        drawn.meshes[b].position.copy(centre(p, b));
        drawn.meshes[b].quaternion.copy(quaternion(p, b));
      }
      drawn.joints[b].position.copy(joint(p, b));
      put(joint(p, b)); put(centre(p, b));
      if (scene.parents[b] >= 0) { put(joint(p, b)); put(centre(p, scene.parents[b])); }
    }
    at.needsUpdate = true;
  }

  var root = scene.parents.indexOf(-1);
  // The base point's path (the root body's inboard joint) and the bounds of everything.
  var bounds = new THREE.Box3(), path = [];
  data.runs[0].pose.forEach(function (p) {
    path.push(joint(p, root));
    for (var b = 0; b < n; ++b) { bounds.expandByPoint(centre(p, b)); bounds.expandByPoint(joint(p, b)); }
  });
  var pathLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints(path),
                                new THREE.LineDashedMaterial({color: 0xc62828, dashSize: 0.02, gapSize: 0.02}));
  var size = bounds.getSize(new THREE.Vector3()).length() || 1;
  pathLine.material.dashSize = pathLine.material.gapSize = size / 100;
  pathLine.computeLineDistances();
  world.add(pathLine);
  var runs = data.runs.map(makeRun);
  var middle = bounds.getCenter(new THREE.Vector3());
  var camera = new THREE.PerspectiveCamera(40, box.clientWidth / box.clientHeight, size / 1000, size * 100);
  camera.up.set(0, 0, 1);
  camera.position.copy(middle).add(new THREE.Vector3(1.2, -1.6, 0.8).multiplyScalar(0.6 * size));
  camera.lookAt(middle);
  var controls = THREE.OrbitControls ? new THREE.OrbitControls(camera, renderer.domElement) : null;
  if (controls) { controls.target.copy(middle); controls.update(); }

  var slider = document.getElementById("treedyn-time"), clock = document.getElementById("treedyn-clock");
  var button = document.getElementById("treedyn-play");
  slider.max = frames - 1;
  var frame = 0, playing = true, last = null;
  var asked = /frame=(\d+)/.exec(window.location.hash);
  if (asked) { frame = Math.min(frames - 1, parseInt(asked[1], 10)); playing = false; }
  button.textContent = playing ? "pause" : "play";

  function show(k) {
    frame = k;
    runs.forEach(function (r) { place(r, k); });
    slider.value = k;
    clock.textContent = "t = " + data.times[k].toFixed(3) + " s (" + data.runs[0].label + ")";
    renderer.render(world, camera);
  }
  button.onclick = function () { playing = !playing; button.textContent = playing ? "pause" : "play"; last = null; };
  slider.oninput = function () { show(parseInt(slider.value, 10)); };
  if (controls) controls.addEventListener("change", function () { renderer.render(world, camera); });
  // Real time: the frame whose time has come since play started.
  function tick(now) {
    if (playing) {
      if (last === null) last = now - 1000 * (data.times[frame] - data.times[0]);
      var t = data.times[0] + (now - last) / 1000, k = frame;
      while (k + 1 < frames && data.times[k + 1] <= t) ++k;
      if (t > data.times[frames - 1]) { k = 0; last = now; }
      if (k !== frame) show(k);
    }
    window.requestAnimationFrame(tick);
  }
  show(frame);
  // "#frame=K&probe": the drawn canvas's pixels, summarised in data-probe for the tests (headless Chromium's
  // --dump-dom): how many differ from the background, and a hash that differs when the picture does.
  if (/probe/.test(window.location.hash)) {
    var gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    var pixels = new Uint8Array(w * h * 4), drawn = 0, hash = 0;
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    for (var i = 0; i < pixels.length; i += 4) {  // drawn: not the colour of the corner (the background)
      if (pixels[i] !== pixels[0] || pixels[i + 1] !== pixels[1] || pixels[i + 2] !== pixels[2] ||
          pixels[i + 3] !== pixels[3]) {
        ++drawn;
        hash = (hash * 31 + i + pixels[i] + 7 * pixels[i + 1] + 13 * pixels[i + 2]) >>> 0;
      }
    }
    box.setAttribute("data-probe", "frame=" + frame + " drawn=" + drawn + " of " + (w * h) + " hash=" + hash);
  }
  window.requestAnimationFrame(tick);
})();
