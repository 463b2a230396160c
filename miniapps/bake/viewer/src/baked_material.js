// View-dependent colour on the GPU: each vertex looks its camera-ray direction up among
// its baked viewpoints (README "Lookup rule"; lookup.js is the CPU copy) and the colour
// is interpolated across the triangle, perspective-correct, then sRGB-encoded.
import * as THREE from 'three';
import { kTexWidth } from './pack_map.js';

const vertexShader = /* glsl */ `
precision highp float;
precision highp int;
precision highp usampler2D;
in uvec4 aView; // first colour texel, first direction texel, count, uniform
uniform highp sampler2D uDirs;
uniform highp sampler2D uColors;
uniform float uPointSize;
out vec3 vColor;

ivec2 texel(uint k) { return ivec2(int(k % ${kTexWidth}u), int(k / ${kTexWidth}u)); }

vec3 lookup(vec3 v) {
  if (aView.w == 1u) return texelFetch(uColors, texel(aView.x), 0).rgb;
  float radius = sqrt(32.0 / float(aView.z));
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  float best = -2.0;
  uint bestK = 0u;
  for (uint k = 0u; k < aView.z; ++k) {
    float c = dot(v, texelFetch(uDirs, texel(aView.y + k), 0).xyz);
    if (c > best) { best = c; bestK = k; }
    float w = max(0.0, 1.0 - acos(clamp(c, -1.0, 1.0)) / radius);
    if (w > 0.0) {
      sum += w * texelFetch(uColors, texel(aView.x + k), 0).rgb;
      wsum += w;
    }
  }
  return wsum > 0.0 ? sum / wsum : texelFetch(uColors, texel(aView.x + bestK), 0).rgb;
}

void main() {
  vec4 world = modelMatrix * vec4(position, 1.0);
  // The camera ray into the vertex, as the .bs viewpoint directions are defined.
  vColor = lookup(normalize(world.xyz - cameraPosition));
  gl_Position = projectionMatrix * viewMatrix * world;
  gl_PointSize = uPointSize;
}
`;

const fragmentShader = /* glsl */ `
precision highp float;
in vec3 vColor;
layout(location = 0) out vec4 outColor;
vec3 srgbEncode(vec3 linear) {
  vec3 x = clamp(linear, 0.0, 1.0);
  return mix(1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, 12.92 * x, vec3(lessThanEqual(x, vec3(0.0031308))));
}
void main() { outColor = vec4(srgbEncode(vColor), 1.0); }
`;

function dataTexture(rgba) {
  const texels = Math.max(1, rgba.length / 4);
  const height = Math.ceil(texels / kTexWidth);
  const data = new Float32Array(4 * kTexWidth * height);
  data.set(rgba);
  const tex = new THREE.DataTexture(data, kTexWidth, height, THREE.RGBAFormat, THREE.FloatType);
  tex.minFilter = THREE.NearestFilter;
  tex.magFilter = THREE.NearestFilter;
  tex.generateMipmaps = false;
  tex.needsUpdate = true;
  return tex;
}

// Textures of a packed map; throws when they exceed the GPU's texture size.
export function makeMapTextures(packed, maxTextureSize) {
  const rows = Math.ceil(Math.max(packed.colorTex.length, packed.dirTex.length) / 4 / kTexWidth);
  if (rows > maxTextureSize)
    throw new Error(`${packed.name}: map needs ${rows} texture rows, this GPU allows ${maxTextureSize}`);
  return { dirs: dataTexture(packed.dirTex), colors: dataTexture(packed.colorTex) };
}

export function makeBakedMaterial(textures, pointSize = 1) {
  return new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3,
    vertexShader,
    fragmentShader,
    side: THREE.DoubleSide,
    uniforms: {
      uDirs: { value: textures.dirs },
      uColors: { value: textures.colors },
      uPointSize: { value: pointSize },
    },
  });
}
