// The page against `bake render`: the same map, camera and resolution rendered by both, and the
// 8-bit sRGB pixels compared. Used by run.mjs (the ctest) and compare_render.mjs (results).
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';

// Binary PPM (P6, maxval 255), as `bake render -o X.ppm` writes it: RGB bytes, top row first.
export function readPpm(path) {
  const bytes = readFileSync(path);
  const fields = [];
  let at = 0;
  while (fields.length < 4) {
    while (/\s/.test(String.fromCharCode(bytes[at]))) ++at;
    if (bytes[at] === 0x23) {
      while (bytes[at] !== 0x0a) ++at; // comment line
      continue;
    }
    let token = '';
    while (!/\s/.test(String.fromCharCode(bytes[at]))) token += String.fromCharCode(bytes[at++]);
    fields.push(token);
  }
  const [magic, width, height, maxval] = [fields[0], Number(fields[1]), Number(fields[2]), Number(fields[3])];
  if (magic !== 'P6' || maxval !== 255) throw new Error(`${path}: not an 8-bit binary PPM`);
  return { width, height, rgb: bytes.subarray(at + 1, at + 1 + 3 * width * height) };
}

// `bake render` of map for a camera {eye, target, up, fov, width, height}, pixel centres (spp 1,
// what the rasteriser samples), to out (.ppm: read back and returned; .png: written only).
// Throws with bake's output when it fails.
export function bakeRender(bake, map, cam, out) {
  const args = ['render', map, '--camera-pos', cam.eye.join(','), '--look-at', cam.target.join(','),
    '--up', cam.up.join(','), '--fov', String(cam.fov), '--width', String(cam.width),
    '--height', String(cam.height), '--spp', '1', '-o', out];
  const run = spawnSync(bake, args, { encoding: 'utf8', env: { OMP_NUM_THREADS: '2', ...process.env } });
  if (run.status !== 0) throw new Error(`${bake} ${args.join(' ')} failed (${run.status}):\n${run.stdout}${run.stderr}`);
  return out.endsWith('.ppm') ? readPpm(out) : null;
}

// The page's URL query for the same camera.
export function cameraQuery(cam) {
  return `eye=${cam.eye.join(',')}&target=${cam.target.join(',')}&up=${cam.up.join(',')}` +
    `&fov=${cam.fov}&w=${cam.width}&h=${cam.height}`;
}

// Page pixels (RGBA, from the canvas) against bake render's (RGB). Per pixel d = the largest
// channel difference in 8-bit codes. Rasterisation and ray casting may pick different faces on
// a shared edge or silhouette, so the measure is robust: the mean of d over all pixels and the
// fraction of pixels with d > kLevels; `interiorMean` leaves out pixels next to a geometric
// edge of either image (a neighbour whose own d is large is not an edge; an edge is where the
// image itself jumps by more than kEdgeJump).
export const kLevels = 8;
const kEdgeJump = 24;

export function comparePixels(pageRgba, render) {
  const { width, height, rgb } = render;
  const d = new Float64Array(width * height);
  for (let p = 0; p < width * height; ++p) {
    let m = 0;
    for (let c = 0; c < 3; ++c) m = Math.max(m, Math.abs(pageRgba[4 * p + c] - rgb[3 * p + c]));
    d[p] = m;
  }
  const jump = (img, stride, p, q) => {
    let m = 0;
    for (let c = 0; c < 3; ++c) m = Math.max(m, Math.abs(img[stride * p + c] - img[stride * q + c]));
    return m;
  };
  let sum = 0;
  let over = 0;
  let interiorSum = 0;
  let interior = 0;
  let hits = 0;
  for (let y = 0; y < height; ++y) {
    for (let x = 0; x < width; ++x) {
      const p = y * width + x;
      sum += d[p];
      if (d[p] > kLevels) ++over;
      if (rgb[3 * p] || rgb[3 * p + 1] || rgb[3 * p + 2]) ++hits;
      let edge = x === 0 || y === 0 || x === width - 1 || y === height - 1;
      for (const q of [p - 1, p + 1, p - width, p + width]) {
        if (edge) break;
        edge = jump(rgb, 3, p, q) > kEdgeJump || jump(pageRgba, 4, p, q) > kEdgeJump;
      }
      if (!edge) {
        interiorSum += d[p];
        ++interior;
      }
    }
  }
  const n = width * height;
  return {
    pixels: n,
    mapPixels: hits,
    meanAbs: sum / n,
    fractionOver: over / n,
    interiorPixels: interior,
    interiorMeanAbs: interior ? interiorSum / interior : 0,
    maxDiff: d.reduce((a, b) => Math.max(a, b), 0),
  };
}
