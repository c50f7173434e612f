// treedyn report's 3-D view (view3d.py inlines it after three.js). Reads the
// JSON in #treedyn-motion: times, scene (bodies, parents, shapes, dimensions,
// com_to_joint in body frames), bounds (the box holding every shape at every
// frame), grid (its square's length) and runs (pose rows: per body x y z q0
// q1 q2 q3). "#frame=K" in the address starts paused at frame K, "speed=S"
// plays at S times real time (used by the tests).
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
  // Every shape at every frame (view3d.py's bounds_of), so nothing moves out of the picture.
  var bounds = new THREE.Box3(new THREE.Vector3().fromArray(data.bounds[0]),
                              new THREE.Vector3().fromArray(data.bounds[1]));
  var size = bounds.getSize(new THREE.Vector3()).length() || 1;
  var path = data.runs[0].pose.map(function (p) { return joint(p, root); });  // the base point's
  var pathLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints(path), new THREE.LineDashedMaterial(
      {color: 0xc62828, dashSize: size / 100, gapSize: size / 100}));
  pathLine.computeLineDistances();
  world.add(pathLine);

  // A text label facing the camera, `height` tall in metres.
  function label(words, at, height) {
    var canvas = document.createElement("canvas"), pen = canvas.getContext("2d");
    canvas.width = 256; canvas.height = 64;
    pen.font = "bold 44px sans-serif";
    pen.fillStyle = "#333";
    pen.textAlign = "center";
    pen.textBaseline = "middle";
    pen.fillText(words, 128, 32);
    var sprite = new THREE.Sprite(new THREE.SpriteMaterial({map: new THREE.CanvasTexture(canvas), depthTest: false}));
    sprite.scale.set(4 * height, height, 1);
    sprite.position.copy(at);
    world.add(sprite);
  }
  // The ground: a grid under the lowest point, its lines on multiples of the step, and the axes at its
  // corner, one step long, labelled: the scale of the picture. Returns the box it spans.
  function ground(step) {
    var lo = bounds.min, hi = bounds.max, z = lo.z, points = [];
    var x0 = Math.floor(lo.x / step) * step, x1 = Math.max(Math.ceil(hi.x / step) * step, x0 + step);
    var y0 = Math.floor(lo.y / step) * step, y1 = Math.max(Math.ceil(hi.y / step) * step, y0 + step);
    for (var x = x0; x <= x1 + step / 2; x += step) {
      points.push(new THREE.Vector3(x, y0, z), new THREE.Vector3(x, y1, z));
    }
    for (var y = y0; y <= y1 + step / 2; y += step) {
      points.push(new THREE.Vector3(x0, y, z), new THREE.Vector3(x1, y, z));
    }
    world.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(points),
                                     new THREE.LineBasicMaterial({color: 0xd0d0d0})));
    var corner = new THREE.Vector3(x0, y0, z), axes = new THREE.AxesHelper(step);
    axes.position.copy(corner);
    world.add(axes);
    var h = 0.45 * step;
    label("x", corner.clone().add(new THREE.Vector3(1.15 * step, 0, 0)), h);
    label("y", corner.clone().add(new THREE.Vector3(0, 1.15 * step, 0)), h);
    label("z", corner.clone().add(new THREE.Vector3(0, 0, 1.15 * step)), h);
    label(data.grid.label, corner.clone().add(new THREE.Vector3(0.5 * step, -0.35 * step, 0)), h);
    return new THREE.Box3(new THREE.Vector3(x0 - 0.5 * step, y0 - 0.5 * step, z),
                          new THREE.Vector3(x1, y1, z + step));
  }
  var framed = ground(data.grid.step).union(bounds.clone());  // the motion and its grid, labels included
  var runs = data.runs.map(makeRun);
  var middle = framed.getCenter(new THREE.Vector3()), reach = framed.getSize(new THREE.Vector3()).length();
  var aspect = box.clientWidth / box.clientHeight;
  var camera = new THREE.PerspectiveCamera(40, aspect, reach / 1000, reach * 100);
  camera.up.set(0, 0, 1);
  // Far enough that the box's enclosing sphere fits the narrower of the two fields of view.
  var halfView = Math.min(Math.PI / 9, Math.atan(Math.tan(Math.PI / 9) * aspect));  // 20 degrees: half of 40
  camera.position.copy(middle).add(new THREE.Vector3(1.2, -1.6, 0.8).normalize()
                                   .multiplyScalar(1.05 * 0.5 * reach / Math.sin(halfView)));
  camera.lookAt(middle);
  var controls = THREE.OrbitControls ? new THREE.OrbitControls(camera, renderer.domElement) : null;
  if (controls) { controls.target.copy(middle); controls.update(); }

  var slider = document.getElementById("treedyn-time"), clock = document.getElementById("treedyn-clock");
  var button = document.getElementById("treedyn-play"), speeds = document.getElementById("treedyn-speed");
  slider.max = frames - 1;
  var frame = 0, playing = true, last = null;
  var asked = /frame=(\d+)/.exec(window.location.hash), fast = /speed=([0-9.]+)/.exec(window.location.hash);
  if (asked) { frame = Math.min(frames - 1, parseInt(asked[1], 10)); playing = false; }
  if (fast) speeds.value = fast[1];
  var speed = parseFloat(speeds.value) || 1, played = data.times[frame];  // played: the motion's time shown
  button.textContent = playing ? "pause" : "play";

  function show(k) {
    frame = k;
    runs.forEach(function (r) { place(r, k); });
    slider.value = k;
    clock.textContent = "t = " + data.times[k].toFixed(3) + " s (" + data.runs[0].label + ")";
    renderer.render(world, camera);
  }
  function frameAt(t) {  // the last frame at or before time t (at most 400 frames: a scan is quick)
    var k = 0;
    while (k + 1 < frames && data.times[k + 1] <= t) ++k;
    return k;
  }
  // `seconds` of real time played at the chosen speed: the motion's time moves on speed times as far, and
  // starts again at the first frame after the last.
  function advance(seconds) {
    played += seconds * speed;
    if (played > data.times[frames - 1]) played = data.times[0];
    return frameAt(played);
  }
  button.onclick = function () { playing = !playing; button.textContent = playing ? "pause" : "play"; };
  speeds.onchange = function () { speed = parseFloat(speeds.value) || 1; };
  slider.oninput = function () { show(parseInt(slider.value, 10)); played = data.times[frame]; };
  if (controls) controls.addEventListener("change", function () { renderer.render(world, camera); });
  function tick(now) {
    if (playing && last !== null) {
      var k = advance((now - last) / 1000);
      if (k !== frame) show(k);
    }
    last = now;
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
    // framed: every corner of the bounds projects inside the picture; after_1s: the time one second of
    // playing from here reaches at this speed.
    var inside = 1;
    for (var c = 0; c < 8; ++c) {
      var v = new THREE.Vector3(c & 1 ? bounds.max.x : bounds.min.x, c & 2 ? bounds.max.y : bounds.min.y,
                                c & 4 ? bounds.max.z : bounds.min.z).project(camera);
      if (Math.abs(v.x) > 1 || Math.abs(v.y) > 1) inside = 0;
    }
    var before = played, reached = data.times[advance(1.0)];
    played = before;
    box.setAttribute("data-probe", "frame=" + frame + " drawn=" + drawn + " of " + (w * h) + " hash=" + hash +
                     " framed=" + inside + " speed=" + speed + " after_1s=" + reached);
  }
  window.requestAnimationFrame(tick);
})();
