// The viewer page: loads a map through the worker, shows it with orbit controls and the
// GPU viewpoint lookup, the vertex-grid view and the picked vertex's viewpoint sphere.
// window.__rtminiReady turns true once the first frame after a load is drawn
// (window.__rtminiError holds the message when a load fails).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { disposeMapTextures, makeBakedMaterial, makeMapTextures } from './baked_material.js';
import { parseViewParams } from './camera_params.js';
import { lookupColor } from './lookup.js';
import { makeViewpointSphere } from './viewpoint_sphere.js';

const kGridPointSize = 6;
const $ = (id) => document.getElementById(id);

let params;
try {
  params = parseViewParams(window.location.search);
} catch (err) {
  params = parseViewParams('');
  queueMicrotask(() => showError(err.message));
}
const canvas = $('view');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
renderer.setClearColor(0x000000, 1);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(params.fov, 1, 0.01, 100);
camera.up.set(...params.up);
const controls = new OrbitControls(camera, canvas);
controls.addEventListener('change', render);

let current = null; // { packed, mesh, points, textures, sphere, radius }

function fixedSize() {
  return params.width !== null && params.height !== null;
}

function resize() {
  const w = fixedSize() ? params.width : window.innerWidth;
  const h = fixedSize() ? params.height : window.innerHeight;
  // Fixed-size captures use exactly w x h pixels, whatever the display's pixel ratio.
  renderer.setPixelRatio(fixedSize() ? 1 : window.devicePixelRatio);
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  render();
}

function render() {
  renderer.render(scene, camera);
}

// Benchmarks (tests/frame_time.mjs): draws n frames while orbiting the camera once around
// the target, each one waited for (a one-pixel readPixels, which cannot return before the
// frame is drawn; gl.finish alone does not block on every driver), and returns the
// milliseconds per frame.
window.__rtminiOrbitFrames = (n) => {
  const gl = renderer.getContext();
  const pixel = new Uint8Array(4);
  const finish = () => gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
  const axis = camera.up.clone().normalize();
  const step = (2 * Math.PI) / n;
  render();
  finish();
  const t0 = performance.now();
  for (let i = 0; i < n; ++i) {
    const offset = camera.position.clone().sub(controls.target).applyAxisAngle(axis, step);
    camera.position.copy(controls.target).add(offset);
    camera.lookAt(controls.target);
    render();
    finish();
  }
  return (performance.now() - t0) / n;
};

function setStatus(text) {
  $('status').textContent = text;
}

function showError(message) {
  $('error').textContent = message;
  $('error').hidden = false;
  $('progress').hidden = true;
  window.__rtminiError = message;
}

function disposeCurrent() {
  if (!current) return;
  for (const obj of [current.mesh, current.points, current.sphere]) {
    if (!obj) continue;
    scene.remove(obj);
    obj.traverse?.((o) => {
      o.geometry?.dispose();
      o.material?.dispose();
    });
  }
  disposeMapTextures(current.textures);
  current = null;
}

function frameCamera(packed) {
  const box = new THREE.Box3().setFromArray(packed.positions);
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const radius = Math.max(sphere.radius, 1e-6);
  const target = params.target ?? sphere.center.toArray();
  const fovRad = THREE.MathUtils.degToRad(params.fov);
  const eye = params.eye ?? [target[0], target[1], target[2] + (1.1 * radius) / Math.sin(fovRad / 2)];
  camera.position.set(...eye);
  controls.target.set(...target);
  camera.lookAt(controls.target);
  const distance = camera.position.distanceTo(sphere.center);
  // Near/far bracket the bounding sphere; inside it, near is 1e-3 of far (depth precision).
  camera.far = distance + 2 * radius;
  camera.near = Math.max(distance - 2 * radius, 1e-3 * camera.far);
  camera.updateProjectionMatrix();
  controls.update();
  return radius;
}

function showMap(packed) {
  disposeCurrent();
  const textures = makeMapTextures(packed, renderer.capabilities.maxTextureSize);
  // Faces: unshared corners, each carrying its triangle's vertex ids (integer attribute,
  // uvec3 in the shader). Vertex grid: one point per vertex, its own id three times.
  const geometry = (positions, triangle) => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    const tri = new THREE.BufferAttribute(triangle, 3);
    tri.gpuType = THREE.IntType;
    g.setAttribute('aTriangle', tri);
    return g;
  };
  const self3 = new Uint32Array(3 * packed.vertexCount).map((_, k) => Math.floor(k / 3));
  const mesh = new THREE.Mesh(geometry(packed.cornerPositions, packed.cornerTriangle), makeBakedMaterial(textures));
  const points = new THREE.Points(
    geometry(packed.positions, self3),
    makeBakedMaterial(textures, { points: true, pointSize: kGridPointSize }),
  );
  scene.add(mesh, points);
  current = { packed, mesh, points, textures, sphere: null, radius: frameCamera(packed) };
  setGrid($('grid').checked);
  const kb = (packed.bytes / 1024).toFixed(1);
  setStatus(
    `${packed.name} (${packed.format}, ${kb} KiB): ${packed.vertexCount} vertices, ` +
      `${packed.faceCount} faces, ${packed.viewpointRecords} viewpoints` +
      `${packed.shared ? ' (one shared direction set)' : ''}, loaded in ${packed.parseMs.toFixed(0)} ms`,
  );
  $('progress').hidden = true;
  render();
  requestAnimationFrame(() => {
    window.__rtminiReady = true;
  });
}

// Points drawn without the index are the vertices: the paper's grid-of-vertices view.
function setGrid(on) {
  if (!current) return;
  current.mesh.visible = !on;
  current.points.visible = on;
  render();
}

function load(source) {
  window.__rtminiReady = false;
  window.__rtminiError = null;
  $('error').hidden = true;
  $('progress').hidden = false;
  $('progress').value = 0;
  setStatus(`Loading ${source.file ? source.file.name : source.url} ...`);
  const worker = new Worker(new URL('./parse_worker.js', import.meta.url), { type: 'module' });
  worker.onmessage = (event) => {
    const msg = event.data;
    if (msg.type === 'progress') {
      $('progress').value = msg.total ? msg.loaded / msg.total : 0;
      setStatus(`Loading: ${(msg.loaded / 1048576).toFixed(1)} MiB`);
      return;
    }
    worker.terminate();
    if (msg.type === 'error') {
      showError(msg.message);
      setStatus('Load failed.');
      return;
    }
    try {
      showMap(msg.packed);
    } catch (err) {
      showError(err.message);
    }
  };
  worker.onerror = (event) => {
    showError(`worker failed: ${event.message}`);
    worker.terminate();
  };
  worker.postMessage(source);
}

function pick(event) {
  if (!current || !current.mesh.visible) return;
  const rect = canvas.getBoundingClientRect();
  const ndc = new THREE.Vector2(
    ((event.clientX - rect.left) / rect.width) * 2 - 1,
    -((event.clientY - rect.top) / rect.height) * 2 + 1,
  );
  const raycaster = new THREE.Raycaster();
  raycaster.setFromCamera(ndc, camera);
  const hit = raycaster.intersectObject(current.mesh)[0];
  if (!hit) return;
  // The face corner nearest to the hit point is the picked vertex.
  const corners = [hit.face.a, hit.face.b, hit.face.c].map((k) => current.packed.index[k]);
  const pos = current.packed.positions;
  const dist = (v) => hit.point.distanceToSquared(new THREE.Vector3(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]));
  const vertex = corners.reduce((a, b) => (dist(b) < dist(a) ? b : a));
  selectVertex(vertex);
}

function selectVertex(vertex) {
  const { packed } = current;
  if (current.sphere) {
    scene.remove(current.sphere);
    current.sphere.traverse((o) => {
      o.geometry?.dispose();
      o.material?.dispose();
    });
    current.sphere = null;
  }
  const p = Array.from(packed.positions.subarray(3 * vertex, 3 * vertex + 3));
  const [, dirFirst, count, uniform] = packed.view.subarray(4 * vertex, 4 * vertex + 4);
  const hasDirs = packed.dirTex.length >= 4 * (dirFirst + count);
  if (hasDirs) {
    current.sphere = makeViewpointSphere(packed, vertex, 0.15 * current.radius);
    scene.add(current.sphere);
  }
  const into = p.map((x, i) => x - camera.position.getComponent(i));
  const color = lookupColor(packed, vertex, into);
  $('info').hidden = false;
  $('info').textContent =
    `vertex ${vertex} at (${p.map((x) => x.toPrecision(5)).join(', ')})\n` +
    `${hasDirs ? count : 0} viewpoints${uniform ? ', uniform colour' : ''}\n` +
    `colour from this camera: (${color.map((x) => x.toFixed(3)).join(', ')})`;
  window.__rtminiPicked = vertex;
  render();
}

$('file').addEventListener('change', (e) => {
  if (e.target.files[0]) load({ file: e.target.files[0] });
});
$('grid').addEventListener('change', (e) => setGrid(e.target.checked));
window.addEventListener('dragover', (e) => {
  e.preventDefault();
  document.body.classList.add('drag');
});
window.addEventListener('dragleave', () => document.body.classList.remove('drag'));
window.addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('drag');
  if (e.dataTransfer.files[0]) load({ file: e.dataTransfer.files[0] });
});
let downAt = null;
canvas.addEventListener('pointerdown', (e) => {
  downAt = [e.clientX, e.clientY];
});
canvas.addEventListener('pointerup', (e) => {
  // A click, not the end of an orbit drag.
  if (downAt && Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) < 4) pick(e);
});
window.addEventListener('resize', resize);

if (fixedSize()) document.body.classList.add('fixed-size');
$('grid').checked = params.grid;
resize();
if (params.map) load({ url: new URL(params.map, window.location.href).href });
