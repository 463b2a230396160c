// Turns a parsed map into GPU-ready arrays (done in the worker):
//   view      Uint32Array 4V   per vertex: first colour texel, first direction texel,
//                             viewpoint count, uniform flag (1: one colour texel)
//   dirTex    Float32Array 4D  unit directions (rgb), alpha unused
//   colorTex  Float32Array 4C  linear colours (rgb), alpha unused
//   kdNodes   Float32Array 4N  KD-tree of the shared direction set (lookup.js buildKdTree), or null
//   index     Uint32Array 3T   triangles, a quad (a,b,c,d) as (a,b,c) (a,c,d) like triangulate()
//   cornerPositions Float32Array 9T, cornerTriangle Uint32Array 9T: the triangles unshared
//             (corner by corner), each corner carrying its triangle's three vertex ids, so the
//             fragment shader can look all three up along its own ray (README "Lookup rule")
// Texel k of any texture is at (k % kTexWidth, floor(k / kTexWidth)).
import { buildKdTree } from './lookup.js';

export const kTexWidth = 2048;
const kNoMaterialGrey = 0.5;
const kUnitTolerance = 1e-6;

function padRgba(rgb, extra = 0) {
  const n = rgb.length / 3;
  const out = new Float32Array(4 * (n + extra));
  for (let i = 0; i < n; ++i) {
    out[4 * i] = rgb[3 * i];
    out[4 * i + 1] = rgb[3 * i + 1];
    out[4 * i + 2] = rgb[3 * i + 2];
  }
  return out;
}

export function packMap(map) {
  const nv = map.vertexCount;
  const faces = map.faces;
  const nf = faces.length / 5;

  // A vertex without viewpoints (a raw map) shows the mean diffuse colour of its faces.
  const missing = [];
  for (let i = 0; i < nv; ++i) if (map.counts[i] === 0) missing.push(i);
  const fallback = new Float32Array(4 * nv);
  if (missing.length) {
    for (let f = 0; f < nf; ++f) {
      const m = faces[5 * f + 4];
      const count = faces[5 * f + 3] === -1 ? 3 : 4;
      for (let k = 0; k < count; ++k) {
        const v = faces[5 * f + k];
        for (let c = 0; c < 3; ++c) fallback[4 * v + c] += m >= 0 ? map.materials[9 * m + c] : kNoMaterialGrey;
        fallback[4 * v + 3] += 1;
      }
    }
  }

  const ncolors = map.colors.length / 3;
  const colorTex = padRgba(map.colors, missing.length);
  const view = new Uint32Array(4 * nv);
  for (let i = 0; i < nv; ++i) {
    view[4 * i] = map.colorOffset[i];
    view[4 * i + 1] = map.dirOffset[i];
    view[4 * i + 2] = map.counts[i];
    view[4 * i + 3] = map.uniform[i];
  }
  missing.forEach((v, j) => {
    const t = ncolors + j;
    const w = fallback[4 * v + 3];
    for (let c = 0; c < 3; ++c) colorTex[4 * t + c] = w > 0 ? fallback[4 * v + c] / w : kNoMaterialGrey;
    view.set([t, 0, 1, 1], 4 * v);
  });

  // Directions are used normalised; unit ones (the baker's float Fibonacci points) are kept
  // bit for bit, as `bake render` uses them.
  const dirTex = padRgba(map.dirs);
  for (let k = 0; k < dirTex.length; k += 4) {
    const len = Math.hypot(dirTex[k], dirTex[k + 1], dirTex[k + 2]);
    if (len > 0 && Math.abs(len - 1) > kUnitTolerance) for (let c = 0; c < 3; ++c) dirTex[k + c] /= len;
  }
  const sharedCount = map.shared ? map.dirs.length / 3 : 0;
  const kdNodes = sharedCount > 0 ? buildKdTree(dirTex.filter((_, i) => i % 4 !== 3), sharedCount) : null;

  let triangles = 0;
  for (let f = 0; f < nf; ++f) triangles += faces[5 * f + 3] === -1 ? 1 : 2;
  const index = new Uint32Array(3 * triangles);
  let t = 0;
  for (let f = 0; f < nf; ++f) {
    const [a, b, c, d] = faces.subarray(5 * f, 5 * f + 4);
    index.set([a, b, c], t);
    t += 3;
    if (d !== -1) {
      index.set([a, c, d], t);
      t += 3;
    }
  }

  const cornerPositions = new Float32Array(3 * index.length);
  const cornerTriangle = new Uint32Array(3 * index.length);
  for (let k = 0; k < index.length; ++k) {
    const v = index[k];
    cornerPositions.set(map.positions.subarray(3 * v, 3 * v + 3), 3 * k);
    const tri = k - (k % 3);
    cornerTriangle.set(index.subarray(tri, tri + 3), 3 * k);
  }

  return {
    vertexCount: nv,
    faceCount: nf,
    positions: map.positions,
    view,
    dirTex,
    colorTex,
    index,
    cornerPositions,
    cornerTriangle,
    kdNodes,
    sharedCount,
    shared: map.shared,
    viewpointRecords: map.counts.reduce((s, n) => s + n, 0),
  };
}

export function packedTransferables(p) {
  return [p.positions, p.view, p.dirTex, p.colorTex, p.index, p.cornerPositions, p.cornerTriangle, p.kdNodes]
    .filter((a) => a)
    .map((a) => a.buffer);
}
