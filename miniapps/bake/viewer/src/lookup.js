// The baker's viewpoint lookup (README "Lookup rule"), on the CPU: a line-by-line port of
// common/include/rtmini/sampling/fibonacci_lookup.hpp (neighbours within the seed's radius,
// weights, nearest-point fallback) and of MapReader::read (miniapps/bake/map_reader.hpp),
// which `bake render` calls per camera ray. The fragment shader in baked_material.js is the
// GPU copy; the info panel and the tests use this one.

export const kMaxViewNeighbors = 32; // rtmini::kMaxViewNeighbors
export const kKdStackSize = 64; // rtmini::kKdStackSize

// The seed's sample radius, a chord length on the unit sphere: r = sqrt(32 / N).
export function fibonacciRadius(n) {
  return Math.sqrt(32 / n);
}

const dist2 = (p, q) => (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2;

// Keeps the kMaxViewNeighbors closest candidates ordered by (d2, index) (detail::NeighborCollector).
class NeighborCollector {
  constructor() {
    this.index = [];
    this.d2 = [];
  }

  add(i, d2) {
    let pos = this.index.length;
    while (pos > 0 && (this.d2[pos - 1] > d2 || (this.d2[pos - 1] === d2 && this.index[pos - 1] > i))) --pos;
    if (pos >= kMaxViewNeighbors) return;
    this.index.splice(pos, 0, i);
    this.d2.splice(pos, 0, d2);
    if (this.index.length > kMaxViewNeighbors) {
      this.index.pop();
      this.d2.pop();
    }
  }

  // Weights (1 - (theta / theta_r)^2)^2 in the angular distance theta, normalised; nothing
  // strictly inside the cap: the nearest point alone (detail::finish_neighbors).
  finish(radius, nearest) {
    const thetaR = 2 * Math.asin(Math.min(1, 0.5 * radius));
    const out = { index: [], weight: [] };
    let sum = 0;
    this.index.forEach((i, k) => {
      const chord = Math.sqrt(Math.max(0, this.d2[k]));
      const x = (2 * Math.asin(Math.min(1, 0.5 * chord))) / thetaR;
      const w = x < 1 ? (1 - x * x) * (1 - x * x) : 0;
      if (w <= 0) return;
      out.index.push(i);
      out.weight.push(w);
      sum += w;
    });
    if (out.index.length === 0) return { index: [nearest], weight: [1] };
    out.weight = out.weight.map((w) => w / sum);
    return out;
  }
}

// Exhaustive neighbours of unit direction q among points(k), k < n (rtmini::brute_force_neighbors).
export function bruteForceNeighbors(point, n, q, radius) {
  const c = new NeighborCollector();
  const r2 = radius * radius;
  let best = 0;
  let bestD2 = dist2(point(0), q);
  for (let i = 0; i < n; ++i) {
    const d2 = dist2(point(i), q);
    if (d2 <= r2) c.add(i, d2);
    if (d2 < bestD2) {
      bestD2 = d2;
      best = i;
    }
  }
  return c.finish(radius, best);
}

// Size of the left subtree of a left-balanced complete binary tree of m nodes.
function leftSubtreeSize(m) {
  if (m <= 1) return 0;
  let h = 0;
  while ((2 << h) - 1 < m) ++h;
  const last = m - ((1 << h) - 1);
  const half = 1 << (h - 1);
  return half - 1 + Math.min(last, half);
}

// The heap-laid KD-tree of rtmini::build_fibonacci_kdtree over n unit directions (flat xyz):
// median splits along the widest axis; node i's children are 2i+1, 2i+2. Returns
// Float32Array 4n: node point xyz and 4 * (direction index) + split axis.
export function buildKdTree(dirs, n) {
  const pts = Array.from({ length: n }, (_, i) => [dirs[3 * i], dirs[3 * i + 1], dirs[3 * i + 2]]);
  const ids = Array.from({ length: n }, (_, i) => i);
  const nodes = new Float32Array(4 * n);
  const work = [[0, 0, n]];
  while (work.length) {
    const [node, begin, end] = work.pop();
    if (begin >= end) continue;
    const lo = [Infinity, Infinity, Infinity];
    const hi = [-Infinity, -Infinity, -Infinity];
    for (let k = begin; k < end; ++k) {
      for (let a = 0; a < 3; ++a) {
        lo[a] = Math.min(lo[a], pts[ids[k]][a]);
        hi[a] = Math.max(hi[a], pts[ids[k]][a]);
      }
    }
    const ext = [0, 1, 2].map((a) => hi[a] - lo[a]);
    const axis = ext[0] > ext[1] ? (ext[0] > ext[2] ? 0 : 2) : ext[1] > ext[2] ? 1 : 2; // max_dimension
    const mid = begin + leftSubtreeSize(end - begin);
    const range = ids.slice(begin, end).sort((a, b) => pts[a][axis] - pts[b][axis] || a - b);
    ids.splice(begin, end - begin, ...range);
    nodes.set([...pts[ids[mid]], 4 * ids[mid] + axis], 4 * node);
    work.push([2 * node + 1, begin, mid], [2 * node + 2, mid + 1, end]);
  }
  return nodes;
}

// Radius query with the nearest point (FibonacciKdTree::neighbors): the same answer as
// bruteForceNeighbors, in O(log N).
export function kdNeighbors(nodes, n, q, radius) {
  const c = new NeighborCollector();
  const r2 = radius * radius;
  const stack = [0];
  let best = -1;
  let bestD2 = 1e30;
  while (stack.length) {
    const i = stack.pop();
    if (i >= n) continue;
    const p = nodes.subarray(4 * i, 4 * i + 3);
    const id = nodes[4 * i + 3] >> 2;
    const axis = nodes[4 * i + 3] & 3;
    const d2 = dist2(p, q);
    if (d2 <= r2) c.add(id, d2);
    if (d2 < bestD2 || (d2 === bestD2 && id < best)) {
      bestD2 = d2;
      best = id;
    }
    const diff = q[axis] - p[axis];
    const near = diff < 0 ? 2 * i + 1 : 2 * i + 2;
    const far = diff < 0 ? 2 * i + 2 : 2 * i + 1;
    if (diff * diff <= Math.max(r2, bestD2)) stack.push(far);
    stack.push(near);
  }
  return c.finish(radius, best);
}

const normalize = (v) => {
  const len = Math.hypot(...v);
  return v.map((x) => x / len);
};

function texelRgb(tex, k) {
  return [tex[4 * k], tex[4 * k + 1], tex[4 * k + 2]];
}

// Neighbours and weights of direction `dir` for a view-dependent vertex: the shared set's
// KD-tree (the baker's maps), or the vertex's own set by brute force (other maps).
function neighborsOf(packed, vertex, dir) {
  if (packed.kdNodes) return kdNeighbors(packed.kdNodes, packed.sharedCount, dir, fibonacciRadius(packed.sharedCount));
  const [, dirFirst, count] = packed.view.subarray(4 * vertex, 4 * vertex + 4);
  return bruteForceNeighbors((k) => texelRgb(packed.dirTex, dirFirst + k), count, dir, fibonacciRadius(count));
}

// Colour of one vertex looked up along the camera-ray direction `viewDir` (into the vertex).
export function lookupColor(packed, vertex, viewDir) {
  const [first, , , uniform] = packed.view.subarray(4 * vertex, 4 * vertex + 4);
  if (uniform) return texelRgb(packed.colorTex, first);
  const nb = neighborsOf(packed, vertex, normalize(viewDir));
  const sum = [0, 0, 0];
  nb.index.forEach((j, k) => {
    const c = texelRgb(packed.colorTex, first + j);
    for (let i = 0; i < 3; ++i) sum[i] += c[i] * nb.weight[k];
  });
  return sum;
}

// Colour of a ray hit on triangle (a, b, c) at barycentrics (1 - u - v, u, v): each corner's
// colour looked up along the ray direction, mixed barycentrically (MapReader::read).
export function shadeHit(packed, corners, u, v, rayDir) {
  const w = [1 - u - v, u, v];
  const sum = [0, 0, 0];
  corners.forEach((vertex, k) => {
    const c = lookupColor(packed, vertex, rayDir);
    for (let i = 0; i < 3; ++i) sum[i] += c[i] * w[k];
  });
  return sum;
}

// IEC 61966-2-1, as common/include/rtmini/io/srgb.hpp.
export function srgbEncode(linear) {
  const x = Math.min(1, Math.max(0, linear));
  return x <= 0.0031308 ? 12.92 * x : 1.055 * x ** (1 / 2.4) - 0.055;
}
