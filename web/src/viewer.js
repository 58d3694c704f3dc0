// flatmorph's report viewer: reads the run's data from the page (#flatmorph-data, written by
// src/report/report.cpp) and draws (a) target and predicted shape in 3D (three.js), (b) the flat
// plate coloured by theta1 or theta2, (c) the print paths of one layer at a time, (d) the metrics.
// Everything is offline: no request leaves the page.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { viridis, cyclic, diverging, css } from './colormaps.js';

const data = JSON.parse(document.getElementById('flatmorph-data').textContent);
const viewer = { ready: false, layerCount: 0, layer: 0 };
window.flatmorphViewer = viewer;

// ---- Data decoding: base64 little-endian typed arrays.
function decode(text, Type) {
  if (!text) return null;
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return new Type(bytes.buffer);
}

function message(container, text) {
  const div = document.createElement('div');
  div.className = 'message';
  div.textContent = text;
  container.appendChild(div);
}

function legend(element, gradientStops, ticks, caption) {
  element.innerHTML = '';
  const cap = document.createElement('div');
  cap.textContent = caption;
  const bar = document.createElement('div');
  bar.className = 'bar';
  bar.style.background = `linear-gradient(to right, ${gradientStops.join(', ')})`;
  const row = document.createElement('div');
  row.className = 'ticks';
  for (const t of ticks) {
    const span = document.createElement('span');
    span.textContent = t;
    row.appendChild(span);
  }
  element.append(cap, bar, row);
}

function stops(fn, n = 24) {
  const out = [];
  for (let i = 0; i <= n; i++) out.push(css(fn(i / n)));
  return out;
}

function fmt(x, digits = 3) {
  return Number.isFinite(x) ? Number(x.toPrecision(digits)).toString() : '–';
}

// A 2D canvas sized to its box at the device's pixel ratio, cleared; returns a context whose unit
// is a CSS pixel, zoomed and panned by `view` ({k, x, y}: screen = k * drawing + (x, y)).
function fitCanvas(canvas, view) {
  const ratio = window.devicePixelRatio || 1;
  const w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
  if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
    canvas.width = Math.round(w * ratio);
    canvas.height = Math.round(h * ratio);
  }
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.setTransform(ratio * view.k, 0, 0, ratio * view.k, ratio * view.x, ratio * view.y);
  return { ctx, w, h };
}

// Wheel zooms about the pointer, dragging pans, a double click resets.
function panZoom(canvas, draw) {
  const view = { k: 1, x: 0, y: 0 };
  let pending = false;
  const redraw = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => {
      pending = false;
      draw();
    });
  };
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const r = canvas.getBoundingClientRect();
    const mx = e.clientX - r.left, my = e.clientY - r.top;
    const k = Math.min(500, Math.max(1, view.k * Math.exp(-e.deltaY * 0.0015)));
    view.x = mx - ((mx - view.x) * k) / view.k;
    view.y = my - ((my - view.y) * k) / view.k;
    view.k = k;
    redraw();
  }, { passive: false });
  let last = null;
  canvas.addEventListener('pointerdown', (e) => {
    last = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!last) return;
    view.x += e.clientX - last[0];
    view.y += e.clientY - last[1];
    last = [e.clientX, e.clientY];
    redraw();
  });
  canvas.addEventListener('pointerup', () => { last = null; });
  canvas.addEventListener('dblclick', () => {
    Object.assign(view, { k: 1, x: 0, y: 0 });
    redraw();
  });
  return view;
}

// Maps plate coordinates (mm, y up) into a w x h box with a margin.
function plateTransform(box, w, h) {
  const [x0, y0, x1, y1] = box;
  const margin = 12;
  const s = Math.min((w - 2 * margin) / Math.max(1e-9, x1 - x0), (h - 2 * margin) / Math.max(1e-9, y1 - y0));
  const ox = (w - s * (x1 - x0)) / 2, oy = (h - s * (y1 - y0)) / 2;
  return { s, x: (x) => ox + (x - x0) * s, y: (y) => h - oy - (y - y0) * s };
}

// ---- The flat plate.
const plate = data.plate ? {
  n: data.plate.vertices,
  xy: decode(data.plate.positions, Float32Array),
  faces: decode(data.plate.indices, Uint32Array),
  theta1: decode(data.plate.theta1, Float32Array),
  theta2: decode(data.plate.theta2, Float32Array),
  shrinkage: decode(data.plate.shrinkage, Float32Array),
} : null;

function boundaryEdges(faces) {
  const count = new Map();
  for (let f = 0; f < faces.length; f += 3) {
    for (let k = 0; k < 3; k++) {
      const a = faces[f + k], b = faces[f + (k + 1) % 3];
      const key = a < b ? a * 4294967296 + b : b * 4294967296 + a;
      count.set(key, (count.get(key) || 0) + 1);
    }
  }
  const edges = [];
  for (const [key, c] of count) if (c === 1) edges.push(Math.floor(key / 4294967296), key % 4294967296);
  return edges;
}

let plateBox = null, outline = null;
if (plate) {
  plateBox = [Infinity, Infinity, -Infinity, -Infinity];
  for (let v = 0; v < plate.n; v++) {
    const x = plate.xy[2 * v], y = plate.xy[2 * v + 1];
    plateBox = [Math.min(plateBox[0], x), Math.min(plateBox[1], y), Math.max(plateBox[2], x), Math.max(plateBox[3], y)];
  }
  outline = boundaryEdges(plate.faces);
}

const plateCanvas = document.getElementById('plate-canvas');
const plateView = panZoom(plateCanvas, () => drawPlate());
function drawPlate() {
  const { ctx, w, h } = fitCanvas(plateCanvas, plateView);
  if (!plate) return;
  const field = document.querySelector('input[name=plate-field]:checked').value;
  const useTheta2 = field === 'theta2' && plate.theta2;
  const useShrinkage = field === 'shrinkage' && plate.shrinkage;
  let max2 = 0;
  if (plate.theta2) for (const t of plate.theta2) max2 = Math.max(max2, Math.abs(t));
  let maxShrinkage = 0;
  if (plate.shrinkage) for (const s of plate.shrinkage) maxShrinkage = Math.max(maxShrinkage, s);
  const T = plateTransform(plateBox, w, h);
  ctx.lineWidth = 0.7 / plateView.k;
  ctx.lineJoin = 'round';
  const F = plate.faces, P = plate.xy;
  for (let f = 0; f < F.length / 3; f++) {
    const a = F[3 * f], b = F[3 * f + 1], c = F[3 * f + 2];
    let color;
    if (useShrinkage) {
      color = css(viridis(maxShrinkage > 0 ? plate.shrinkage[f] / maxShrinkage : 0));
    } else if (useTheta2) {
      const t = (plate.theta2[a] + plate.theta2[b] + plate.theta2[c]) / 3;
      color = css(diverging(max2 > 0 ? t / max2 : 0));
    } else {
      color = css(cyclic(plate.theta1[f] / Math.PI));
    }
    ctx.fillStyle = color;
    ctx.strokeStyle = color;
    ctx.beginPath();
    ctx.moveTo(T.x(P[2 * a]), T.y(P[2 * a + 1]));
    ctx.lineTo(T.x(P[2 * b]), T.y(P[2 * b + 1]));
    ctx.lineTo(T.x(P[2 * c]), T.y(P[2 * c + 1]));
    ctx.closePath();
    ctx.fill();
    ctx.stroke();
  }
  const el = document.getElementById('legend-plate');
  if (useShrinkage) {
    const pct = 100 * maxShrinkage;
    legend(el, stops(viridis), ['0 %', `${fmt(pct / 2)} %`, `${fmt(pct)} %`],
      'σ per face: how much the path shrinks along its direction in hot water (1 − risen / printed length)');
  } else if (useTheta2) {
    const deg = (max2 * 180) / Math.PI;
    legend(el, stops((t) => diverging(2 * t - 1)), [`−${fmt(deg)}°`, '0°', `+${fmt(deg)}°`],
      `θ2 per vertex (layer k prints θ1 + ((k−1)/(n−1) − ½)·θ2; bed layer k = 1), max |θ2| = ${fmt(max2, 4)} rad`);
  } else {
    legend(el, stops(cyclic, 36), ['0°', '45°', '90°', '135°', '180°'],
      'θ1 per face: mean print direction from +x, counter-clockwise (a line: 0° = 180°, cyclic colours)');
  }
}

// ---- Print paths.
const toolpath = data.toolpath || null;
const layers = toolpath ? toolpath.layers.map((l) => ({
  ...l,
  q: decode(l.points, Uint16Array),
  starts: decode(l.starts, Uint32Array),
})) : [];
viewer.layerCount = layers.length;

const layerCanvas = document.getElementById('layer-canvas');
const layerView = panZoom(layerCanvas, () => drawLayer());
function drawLayer() {
  const { ctx, w, h } = fitCanvas(layerCanvas, layerView);
  const k1 = 1 / layerView.k;  // one screen pixel
  const label = document.getElementById('layer-label');
  if (!layers.length) {
    label.textContent = '';
    return;
  }
  const k = Number(document.getElementById('layer-slider').value) - 1;  // 0 = on the bed
  viewer.layer = k + 1;
  const layer = layers[k];
  const [bx0, by0, bx1, by1] = toolpath.box;
  let box = [bx0, by0, bx1, by1];
  if (plateBox) box = [Math.min(bx0, plateBox[0]), Math.min(by0, plateBox[1]), Math.max(bx1, plateBox[2]), Math.max(by1, plateBox[3])];
  const T = plateTransform(box, w, h);
  if (plate && outline) {
    ctx.strokeStyle = '#999';
    ctx.lineWidth = k1;
    ctx.beginPath();
    for (let i = 0; i < outline.length; i += 2) {
      const a = outline[i], b = outline[i + 1];
      ctx.moveTo(T.x(plate.xy[2 * a]), T.y(plate.xy[2 * a + 1]));
      ctx.lineTo(T.x(plate.xy[2 * b]), T.y(plate.xy[2 * b + 1]));
    }
    ctx.stroke();
  }
  const sx = (bx1 - bx0) / 65535, sy = (by1 - by0) / 65535;
  const X = (i) => T.x(bx0 + layer.q[2 * i] * sx), Y = (i) => T.y(by0 + layer.q[2 * i + 1] * sy);
  const n = layer.starts.length - 1;
  ctx.lineWidth = Math.max(0.6 * k1, layer.width * T.s * 0.8);
  ctx.lineCap = 'round';
  ctx.lineJoin = 'round';
  for (let p = 0; p < n; p++) {
    ctx.strokeStyle = css(viridis(n > 1 ? p / (n - 1) : 0));
    ctx.beginPath();
    for (let i = layer.starts[p]; i < layer.starts[p + 1]; i++) {
      if (i === layer.starts[p]) ctx.moveTo(X(i), Y(i));
      else ctx.lineTo(X(i), Y(i));
    }
    ctx.stroke();
  }
  if (document.getElementById('show-travels').checked) {
    ctx.strokeStyle = 'rgba(220, 30, 30, 0.8)';
    ctx.lineWidth = 0.8 * k1;
    ctx.setLineDash([4 * k1, 3 * k1]);
    ctx.beginPath();
    for (let p = 0; p + 1 < n; p++) {
      const a = layer.starts[p + 1] - 1, b = layer.starts[p + 1];
      ctx.moveTo(X(a), Y(a));
      ctx.lineTo(X(b), Y(b));
    }
    ctx.stroke();
    ctx.setLineDash([]);
  }
  label.textContent = `${k + 1} of ${layers.length} (z = ${fmt(layer.z, 4)} mm${k === 0 ? ', on the bed' : ''})`;
  legend(document.getElementById('legend-layers'), stops(viridis), ['first', 'print order', 'last'],
    `${layer.paths} paths, ${fmt(layer.extruded_mm, 5)} mm printed, ${fmt(layer.travel_mm, 4)} mm of travel` +
    ' (travels: red dashes)');
}

function setupLayers() {
  const slider = document.getElementById('layer-slider');
  if (!layers.length) {
    slider.disabled = true;
    message(document.getElementById('layer-canvas').parentElement,
      'No print paths: the run folder has no plate.gcode (flatmorph toolpaths or design writes it).');
    return;
  }
  slider.max = String(layers.length);
  slider.addEventListener('input', drawLayer);
  document.getElementById('show-travels').addEventListener('change', drawLayer);
}

// ---- 3D: target and predicted shape.
function meshGeometry(mesh) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(decode(mesh.positions, Float32Array), 3));
  g.setIndex(new THREE.BufferAttribute(decode(mesh.indices, Uint32Array), 1));
  g.computeVertexNormals();
  return g;
}

function setup3d() {
  const container = document.getElementById('view3d');
  if (!data.target && !data.predicted) {
    message(container, 'No target.ply or simulated.ply in the run folder.');
    return null;
  }
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    message(container, 'The 3D view needs WebGL, which this browser does not offer. The pictures predicted.png and plate_theta1.png next to this file show the shapes.');
    return null;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setClearColor(0xf4f4f4, 1);
  container.appendChild(renderer.domElement);
  renderer.domElement.id = 'view3d-canvas';

  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1e5);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 1.6));
  const light = new THREE.DirectionalLight(0xffffff, 1.6);
  light.position.set(0.5, 0.3, 1);
  camera.add(light);
  scene.add(camera);

  const box = new THREE.Box3();
  let predicted = null, wire = null;
  if (data.predicted) {
    const g = meshGeometry(data.predicted);
    const dev = decode(data.predicted.deviation_mm, Float32Array);
    const colors = new Float32Array(g.attributes.position.count * 3);
    let max = 0;
    if (dev) for (const d of dev) max = Math.max(max, d);
    for (let v = 0; v < g.attributes.position.count; v++) {
      const c = dev ? viridis(max > 0 ? dev[v] / max : 0) : [0.7, 0.7, 0.7];
      colors.set(c, 3 * v);
    }
    g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    predicted = new THREE.Mesh(g, new THREE.MeshStandardMaterial({
      vertexColors: true, side: THREE.DoubleSide, roughness: 0.8, metalness: 0,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    }));
    scene.add(predicted);
    g.computeBoundingBox();
    box.union(g.boundingBox);
    if (dev) {
      legend(document.getElementById('legend-deviation'), stops(viridis),
        ['0 mm', `${fmt(max / 2)} mm`, `${fmt(max)} mm`],
        'Predicted shape coloured by its distance to the target (per vertex)');
    } else {
      document.getElementById('legend-deviation').textContent =
        'Predicted shape (no deviation_mm in simulated.ply: run flatmorph simulate with --target).';
    }
  }
  let printed = null;
  if (data.gcode_predicted) {
    // The shape predicted from what plate.gcode deposits, in one colour, off until asked for.
    const g = meshGeometry(data.gcode_predicted);
    printed = new THREE.Mesh(g, new THREE.MeshStandardMaterial({
      color: 0xe07b39, side: THREE.DoubleSide, roughness: 0.8, metalness: 0,
      transparent: true, opacity: 0.75,
    }));
    printed.visible = false;
    scene.add(printed);
    document.getElementById('show-gcode-label').hidden = false;
  }
  if (data.target) {
    const g = meshGeometry(data.target);
    wire = new THREE.LineSegments(new THREE.WireframeGeometry(g),
      new THREE.LineBasicMaterial({ color: 0x202020, transparent: true, opacity: 0.25 }));
    scene.add(wire);
    if (!predicted) {
      // No prediction: show the target as a grey surface under its wireframe.
      scene.add(new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: 0xbbbbbb, side: THREE.DoubleSide })));
    }
    g.computeBoundingBox();
    box.union(g.boundingBox);
  }
  const center = box.getCenter(new THREE.Vector3());
  const radius = Math.max(1e-6, box.getSize(new THREE.Vector3()).length() / 2);
  camera.near = radius / 100;
  camera.far = radius * 100;

  const controls = new OrbitControls(camera, renderer.domElement);
  const render = () => renderer.render(scene, camera);
  const resetView = () => {
    const dir = new THREE.Vector3(0.55, -0.75, 0.65).normalize();
    camera.position.copy(center).addScaledVector(dir, radius * 3.2);
    controls.target.copy(center);
    camera.updateProjectionMatrix();
    controls.update();
    render();
  };
  const resize = () => {
    const w = Math.max(1, container.clientWidth), h = Math.max(1, container.clientHeight);
    renderer.setSize(w, h, true);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  };
  controls.addEventListener('change', render);
  document.getElementById('show-predicted').addEventListener('change', (e) => {
    if (predicted) predicted.visible = e.target.checked;
    render();
  });
  document.getElementById('show-gcode').addEventListener('change', (e) => {
    if (printed) printed.visible = e.target.checked;
    render();
  });
  document.getElementById('show-wireframe').addEventListener('change', (e) => {
    if (wire) wire.visible = e.target.checked;
    render();
  });
  document.getElementById('reset-view').addEventListener('click', resetView);
  resize();
  resetView();
  return { resize, render };
}

// ---- Metrics.
function setupMetrics() {
  const root = document.getElementById('metrics');
  for (const section of data.metrics || []) {
    const table = document.createElement('table');
    const caption = document.createElement('caption');
    caption.textContent = section.title;
    table.appendChild(caption);
    for (const [label, value] of section.rows) {
      const tr = document.createElement('tr');
      const a = document.createElement('td'), b = document.createElement('td');
      a.textContent = label;
      b.textContent = value;
      tr.append(a, b);
      table.appendChild(tr);
    }
    root.appendChild(table);
  }
}

// ---- The method's own drawings (origami's nets, the tiles' profiles), as the run wrote them.
function setupDrawings() {
  const list = data.drawings || [];
  if (list.length === 0) return;
  const root = document.getElementById('drawings');
  for (const drawing of list) {
    const figure = document.createElement('figure');
    const img = document.createElement('img');
    img.src = 'data:image/svg+xml;base64,' + drawing.svg;
    img.alt = drawing.name;
    img.style.maxWidth = '100%';
    const caption = document.createElement('figcaption');
    caption.textContent = drawing.name;
    figure.append(img, caption);
    root.appendChild(figure);
  }
  document.getElementById('panel-drawings').hidden = false;
}

// ---- Start.
setupMetrics();
setupDrawings();
setupLayers();
if (!plate) message(document.getElementById('plate-canvas').parentElement, 'No flat.ply in the run folder.');
if (!plate || !plate.theta2) document.getElementById('field-theta2').disabled = true;
if (!plate || !plate.shrinkage) document.getElementById('field-shrinkage').disabled = true;
else document.getElementById('field-shrinkage').checked = true;
for (const radio of document.querySelectorAll('input[name=plate-field]')) radio.addEventListener('change', drawPlate);
drawPlate();
drawLayer();
const view3d = setup3d();
window.addEventListener('resize', () => {
  drawPlate();
  drawLayer();
  if (view3d) view3d.resize();
});
viewer.ready = true;
