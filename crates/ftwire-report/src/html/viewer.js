// The 3-D views of an ftwire report (ftwire-report's `html` module writes this file into the
// page). `THREE` is the vendored three.js, imported above this text; the scenes are the JSON of
// the script element `#ftwire-scenes`, one per element `[data-view="k"]`.
//
// Drag to turn the view, the wheel to zoom, double-click to reset; the slider walks through the
// steps. A polyline's colour follows its name, the same in every view of the page. After the
// first frame each view reads its pixels back and the page records on <html> `data-canvas`
// ("nonblank" when every view drew something) and `data-views` ("drawn/total"), which the
// browser test (`.ci/browser-test`) reads.

const PALETTE = [0xd62728, 0x1f77b4, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf];
const BOX_FILL = 0x9aa5b1;
const BOX_EDGE = 0x4b5563;
const GRIPPER = 0x111827;

const css = (c) => "#" + c.toString(16).padStart(6, "0");
const finite = (p) => Array.isArray(p) && p.length === 3 && p.every(Number.isFinite);

// A 4×4 matrix from a rotation by rows and a translation.
function pose(rotation, t) {
  const r = rotation || [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  return new THREE.Matrix4().set(
    r[0][0], r[0][1], r[0][2], t[0],
    r[1][0], r[1][1], r[1][2], t[1],
    r[2][0], r[2][1], r[2][2], t[2],
    0, 0, 0, 1);
}

function placed(object, matrix) {
  object.matrixAutoUpdate = false;
  object.matrix.copy(matrix);
  return object;
}

// Centre and radius of everything the view draws.
function bounds(scene) {
  const box = new THREE.Box3();
  for (const b of scene.boxes) {
    const m = pose(b.rotation, b.centre);
    const h = b.half_extents;
    for (let i = 0; i < 8; i++) {
      const v = new THREE.Vector3(i & 1 ? h[0] : -h[0], i & 2 ? h[1] : -h[1], i & 4 ? h[2] : -h[2]);
      box.expandByPoint(v.applyMatrix4(m));
    }
  }
  for (const line of scene.polylines) {
    for (const p of line.points.filter(finite)) box.expandByPoint(new THREE.Vector3(...p));
  }
  for (const step of scene.steps) {
    for (const line of step.polylines) {
      for (const p of line.points.filter(finite)) box.expandByPoint(new THREE.Vector3(...p));
    }
    for (const g of step.grippers.filter((g) => finite(g.position))) {
      box.expandByPoint(new THREE.Vector3(...g.position));
    }
  }
  if (box.isEmpty()) box.expandByPoint(new THREE.Vector3());
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
  return { centre, radius };
}

// The names of a view's polylines in order of first appearance.
function names(scene) {
  const seen = new Set();
  for (const lines of [...scene.steps.map((s) => s.polylines), scene.polylines]) {
    for (const line of lines) seen.add(line.name);
  }
  return [...seen];
}

// A colour for each polyline name of the page: the same name in the same colour in every view.
function colours(scenes) {
  const map = new Map();
  for (const name of scenes.flatMap(names)) {
    if (!map.has(name)) map.set(name, PALETTE[map.size % PALETTE.length]);
  }
  return map;
}

// The polylines and grippers of a step (or of the whole view, which has no grippers).
function stepGroup(step, colour, size) {
  const group = new THREE.Group();
  for (const line of step.polylines) {
    const points = line.points.filter(finite).map((p) => new THREE.Vector3(...p));
    if (points.length < 2) continue;
    const geometry = new THREE.BufferGeometry().setFromPoints(points);
    group.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: colour.get(line.name) })));
  }
  for (const g of (step.grippers || []).filter((g) => finite(g.position))) {
    const sphere = new THREE.Mesh(
      new THREE.SphereGeometry(0.015 * size, 16, 12),
      new THREE.MeshBasicMaterial({ color: GRIPPER }));
    sphere.position.set(...g.position);
    group.add(sphere);
    if (g.rotation) group.add(placed(new THREE.AxesHelper(0.08 * size), pose(g.rotation, g.position)));
  }
  return group;
}

function legend(colour, scene) {
  const list = document.createElement("ul");
  list.className = "legend";
  const item = (text, c) => {
    const li = document.createElement("li");
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = css(c);
    li.append(swatch, document.createTextNode(text));
    list.append(li);
  };
  for (const name of names(scene)) item(name, colour.get(name));
  if (scene.boxes.length > 0) item("obstacles", BOX_FILL);
  if (scene.steps.some((s) => s.grippers.length > 0)) item("grippers (axes: x red, y green, z blue)", GRIPPER);
  return list;
}

// Does the canvas hold more than one colour? (A blank view is the clear colour only.)
function nonblank(renderer) {
  const gl = renderer.getContext();
  const w = gl.drawingBufferWidth;
  const h = gl.drawingBufferHeight;
  const pixels = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  const seen = new Set();
  for (let i = 0; i < pixels.length && seen.size < 2; i += 4) {
    seen.add((pixels[i] << 16) | (pixels[i + 1] << 8) | pixels[i + 2]);
  }
  return seen.size > 1;
}

// Builds one view into `host`; returns whether its first frame drew anything.
function view(host, scene, colour) {
  const { centre, radius } = bounds(scene);
  const world = new THREE.Scene();
  world.background = new THREE.Color(0xffffff);
  for (const b of scene.boxes) {
    const m = pose(b.rotation, b.centre);
    const h = b.half_extents;
    const geometry = new THREE.BoxGeometry(2 * h[0], 2 * h[1], 2 * h[2]);
    world.add(placed(new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
      color: BOX_FILL, transparent: true, opacity: 0.25, depthWrite: false,
    })), m));
    world.add(placed(new THREE.LineSegments(new THREE.EdgesGeometry(geometry),
      new THREE.LineBasicMaterial({ color: BOX_EDGE })), m));
  }
  world.add(stepGroup(scene, colour, radius));
  const steps = scene.steps.map((s) => stepGroup(s, colour, radius));
  for (const group of steps) world.add(group);

  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  const camera = new THREE.PerspectiveCamera(40, 1, radius / 100, radius * 100);
  camera.up.set(0, 0, 1);
  const home = { azimuth: -Math.PI / 3, elevation: Math.PI / 7, distance: 2.4 * radius };
  const orbit = { ...home };

  const render = () => {
    const e = orbit.elevation;
    const a = orbit.azimuth;
    camera.position.set(
      centre.x + orbit.distance * Math.cos(e) * Math.cos(a),
      centre.y + orbit.distance * Math.cos(e) * Math.sin(a),
      centre.z + orbit.distance * Math.sin(e));
    camera.lookAt(centre);
    renderer.render(world, camera);
  };
  const resize = () => {
    const width = Math.max(host.clientWidth, 320);
    const height = Math.round(Math.min(600, 0.65 * width));
    renderer.setSize(width, height);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
    render();
  };

  // Turn by dragging, zoom with the wheel, reset by double-click.
  const canvas = renderer.domElement;
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    orbit.azimuth -= 0.008 * (e.clientX - drag.x);
    orbit.elevation = Math.min(1.55, Math.max(-1.55, orbit.elevation + 0.008 * (e.clientY - drag.y)));
    drag = { x: e.clientX, y: e.clientY };
    render();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    orbit.distance = Math.min(50 * radius, Math.max(0.2 * radius, orbit.distance * Math.exp(0.001 * e.deltaY)));
    render();
  }, { passive: false });
  canvas.addEventListener("dblclick", () => { Object.assign(orbit, home); render(); });

  // The slider over the steps.
  const controls = document.createElement("div");
  controls.className = "controls";
  const slider = document.createElement("input");
  slider.type = "range";
  slider.min = "0";
  slider.max = String(Math.max(steps.length - 1, 0));
  slider.value = "0";
  slider.disabled = steps.length < 2;
  const label = document.createElement("span");
  const show = (k) => {
    steps.forEach((g, j) => { g.visible = j === k; });
    const step = scene.steps[k];
    label.textContent = step ? `step ${k + 1} of ${steps.length}: ${step.label}` : "no steps";
    render();
  };
  slider.addEventListener("input", () => show(Number(slider.value)));
  controls.append(slider, label);
  host.append(canvas, controls, legend(colour, scene));
  window.addEventListener("resize", resize);
  resize();
  show(0);
  return nonblank(renderer);
}

const root = document.documentElement;
const data = document.getElementById("ftwire-scenes");
const scenes = data ? JSON.parse(data.textContent) : [];
const colour = colours(scenes);
let drawn = 0;
scenes.forEach((scene, k) => {
  const host = document.querySelector(`[data-view="${k}"]`);
  if (host && view(host, scene, colour)) drawn += 1;
});
root.dataset.views = `${drawn}/${scenes.length}`;
root.dataset.canvas = scenes.length > 0 && drawn === scenes.length ? "nonblank" : "blank";
