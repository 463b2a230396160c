// View-dependent colour on the GPU, by the baker's own rule (README "Lookup rule"): every
// fragment is a camera ray; its direction is looked up among the viewpoints (neighbours within
// r = sqrt(32/N), weights (1 - (theta/theta_r)^2)^2, nearest-point fallback) and each of the
// triangle's three vertex colours is read with those weights, then mixed barycentrically:
// MapReader::read (miniapps/bake/map_reader.hpp), which `bake render` calls per pixel.
// lookup.js is the CPU copy. The shared direction set (the baker's maps) is searched through
// its heap-laid KD-tree, other maps by brute force over each vertex's own directions.
import * as THREE from 'three';
import { kTexWidth } from './pack_map.js';
import { kKdStackSize, kMaxViewNeighbors } from './lookup.js';

const vertexShader = /* glsl */ `
precision highp float;
precision highp int;
in uvec3 aTriangle; // the three vertex ids of this corner's triangle
uniform bool uPoints; // vertex-grid view: one point per vertex, looked up as itself
uniform float uPointSize;
flat out uvec3 vTriangle;
out vec3 vBary;
out vec3 vWorld;

void main() {
  vec4 world = modelMatrix * vec4(position, 1.0);
  vWorld = world.xyz;
  vTriangle = aTriangle;
  // Corner k of an unshared triangle is vertex gl_VertexID; its barycentric is the unit vector k.
  int corner = uPoints ? 0 : gl_VertexID % 3;
  vBary = vec3(corner == 0, corner == 1, corner == 2);
  gl_Position = projectionMatrix * viewMatrix * world;
  gl_PointSize = uPointSize;
}
`;

const fragmentShader = /* glsl */ `
precision highp float;
precision highp int;
precision highp usampler2D;
flat in uvec3 vTriangle;
in vec3 vBary;
in vec3 vWorld;
uniform highp usampler2D uView; // per vertex: first colour texel, first direction texel, N, uniform
uniform highp sampler2D uDirs;
uniform highp sampler2D uColors;
uniform highp sampler2D uKdTree; // shared set: node point xyz, w = 4 * index + split axis
uniform int uSharedCount;        // N of the shared direction set, 0 when there is none
layout(location = 0) out vec4 outColor;

const int kMaxNeighbors = ${kMaxViewNeighbors};
const int kStackSize = ${kKdStackSize};

ivec2 texel(int k) { return ivec2(k % ${kTexWidth}, k / ${kTexWidth}); }

// The neighbour list of the current ray: detail::NeighborCollector, then finish_neighbors.
int nbCount;
int nbIndex[kMaxNeighbors];
float nbD2[kMaxNeighbors];
float nbWeight[kMaxNeighbors];

// Keeps the kMaxNeighbors closest, ordered by (d2, index).
void nbAdd(int i, float d2) {
  int pos = nbCount;
  while (pos > 0 && (nbD2[pos - 1] > d2 || (nbD2[pos - 1] == d2 && nbIndex[pos - 1] > i))) --pos;
  if (pos >= kMaxNeighbors) return;
  for (int k = min(nbCount, kMaxNeighbors - 1); k > pos; --k) {
    nbIndex[k] = nbIndex[k - 1];
    nbD2[k] = nbD2[k - 1];
  }
  nbIndex[pos] = i;
  nbD2[pos] = d2;
  if (nbCount < kMaxNeighbors) ++nbCount;
}

// Weights (1 - (theta/theta_r)^2)^2 in the angular distance, normalised; nothing strictly
// inside the cap: the nearest point alone.
void nbFinish(float radius, int nearest) {
  float thetaR = 2.0 * asin(min(1.0, 0.5 * radius));
  float sum = 0.0;
  int kept = 0;
  for (int k = 0; k < nbCount; ++k) {
    float x = 2.0 * asin(min(1.0, 0.5 * sqrt(max(0.0, nbD2[k])))) / thetaR;
    float w = x < 1.0 ? (1.0 - x * x) * (1.0 - x * x) : 0.0;
    if (w <= 0.0) continue;
    nbIndex[kept] = nbIndex[k];
    nbWeight[kept] = w;
    sum += w;
    ++kept;
  }
  nbCount = kept;
  if (kept == 0) {
    nbCount = 1;
    nbIndex[0] = nearest;
    nbWeight[0] = 1.0;
    return;
  }
  for (int k = 0; k < kept; ++k) nbWeight[k] /= sum;
}

float dist2(vec3 a, vec3 b) {
  vec3 d = a - b;
  return dot(d, d);
}

// FibonacciKdTree::neighbors: radius query that also finds the nearest point.
void kdNeighbors(vec3 q, float radius) {
  nbCount = 0;
  float r2 = radius * radius;
  int stack[kStackSize];
  int sp = 0;
  stack[sp++] = 0;
  int best = -1;
  float bestD2 = 1e30;
  while (sp > 0) {
    int i = stack[--sp];
    if (i >= uSharedCount) continue;
    vec4 node = texelFetch(uKdTree, texel(i), 0);
    int id = int(node.w) >> 2, axis = int(node.w) & 3;
    float d2 = dist2(node.xyz, q);
    if (d2 <= r2) nbAdd(id, d2);
    if (d2 < bestD2 || (d2 == bestD2 && id < best)) {
      bestD2 = d2;
      best = id;
    }
    float diff = q[axis] - node[axis];
    int nearChild = diff < 0.0 ? 2 * i + 1 : 2 * i + 2;
    int farChild = diff < 0.0 ? 2 * i + 2 : 2 * i + 1;
    if (diff * diff <= max(r2, bestD2)) stack[sp++] = farChild;
    stack[sp++] = nearChild;
  }
  nbFinish(radius, best);
}

// brute_force_neighbors over one vertex's own directions (maps without a shared set).
void bruteNeighbors(int first, int count, vec3 q, float radius) {
  nbCount = 0;
  float r2 = radius * radius;
  int best = 0;
  float bestD2 = dist2(texelFetch(uDirs, texel(first), 0).xyz, q);
  for (int k = 0; k < count; ++k) {
    float d2 = dist2(texelFetch(uDirs, texel(first + k), 0).xyz, q);
    if (d2 <= r2) nbAdd(k, d2);
    if (d2 < bestD2) {
      bestD2 = d2;
      best = k;
    }
  }
  nbFinish(radius, best);
}

vec3 colorTexel(int k) { return texelFetch(uColors, texel(k), 0).rgb; }

vec3 srgbEncode(vec3 linear) {
  vec3 x = clamp(linear, 0.0, 1.0);
  return mix(1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, 12.92 * x, vec3(lessThanEqual(x, vec3(0.0031308))));
}

void main() {
  // The camera ray into the surface, as the .bs viewpoint directions are defined.
  vec3 dir = normalize(vWorld - cameraPosition);
  bool haveShared = false;
  vec3 sum = vec3(0.0);
  for (int k = 0; k < 3; ++k) {
    uvec4 info = texelFetch(uView, texel(int(vTriangle[k])), 0);
    int first = int(info.x);
    if (info.w == 1u) {
      sum += colorTexel(first) * vBary[k];
      continue;
    }
    if (uSharedCount > 0) {
      // One lookup per ray serves all three vertices (they share the direction set).
      if (!haveShared) kdNeighbors(dir, sqrt(32.0 / float(uSharedCount)));
      haveShared = true;
    } else {
      bruteNeighbors(int(info.y), int(info.z), dir, sqrt(32.0 / float(info.z)));
    }
    vec3 c = vec3(0.0);
    for (int j = 0; j < nbCount; ++j) c += colorTexel(first + nbIndex[j]) * nbWeight[j];
    sum += c * vBary[k];
  }
  outColor = vec4(srgbEncode(sum), 1.0);
}
`;

function dataTexture(data, width, height, format, type) {
  const tex = new THREE.DataTexture(data, width, height, format, type);
  tex.minFilter = THREE.NearestFilter;
  tex.magFilter = THREE.NearestFilter;
  tex.generateMipmaps = false;
  tex.needsUpdate = true;
  return tex;
}

// A texture of RGBA texels (k at (k % kTexWidth, k / kTexWidth)) from a typed array of 4 per texel.
function texelTexture(rgba, ArrayType, format, type) {
  const texels = Math.max(1, (rgba?.length ?? 0) / 4);
  const height = Math.ceil(texels / kTexWidth);
  const data = new ArrayType(4 * kTexWidth * height);
  if (rgba) data.set(rgba);
  const tex = dataTexture(data, kTexWidth, height, format, type);
  if (format === THREE.RGBAIntegerFormat) tex.internalFormat = 'RGBA32UI';
  return tex;
}

// Textures of a packed map; throws when they exceed the GPU's texture size.
export function makeMapTextures(packed, maxTextureSize) {
  const longest = Math.max(packed.colorTex.length, packed.dirTex.length, packed.view.length);
  const rows = Math.ceil(longest / 4 / kTexWidth);
  if (rows > maxTextureSize)
    throw new Error(`${packed.name}: map needs ${rows} texture rows, this GPU allows ${maxTextureSize}`);
  const float = (a) => texelTexture(a, Float32Array, THREE.RGBAFormat, THREE.FloatType);
  return {
    view: texelTexture(packed.view, Uint32Array, THREE.RGBAIntegerFormat, THREE.UnsignedIntType),
    dirs: float(packed.dirTex),
    colors: float(packed.colorTex),
    kdTree: float(packed.kdNodes),
    sharedCount: packed.sharedCount,
  };
}

export function disposeMapTextures(textures) {
  for (const key of ['view', 'dirs', 'colors', 'kdTree']) textures[key].dispose();
}

// points: the vertex-grid view (each vertex drawn as a point of pointSize pixels).
export function makeBakedMaterial(textures, { points = false, pointSize = 1 } = {}) {
  return new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3,
    vertexShader,
    fragmentShader,
    side: THREE.DoubleSide,
    uniforms: {
      uView: { value: textures.view },
      uDirs: { value: textures.dirs },
      uColors: { value: textures.colors },
      uKdTree: { value: textures.kdTree },
      uSharedCount: { value: textures.sharedCount },
      uPoints: { value: points },
      uPointSize: { value: pointSize },
    },
  });
}
