// The viewpoint lookup rule (README "Lookup rule"), on the CPU: the shader in
// baked_material.js computes the same; the info panel and the tests use this copy.
export function lookupColor(packed, vertex, viewDir) {
  const { view, dirTex, colorTex } = packed;
  const [first, dirFirst, count, uniform] = view.subarray(4 * vertex, 4 * vertex + 4);
  const color = (k) => Array.from(colorTex.subarray(4 * (first + k), 4 * (first + k) + 3));
  if (uniform) return color(0);
  const len = Math.hypot(...viewDir);
  const v = viewDir.map((x) => x / len);
  const radius = Math.sqrt(32 / count);
  const sum = [0, 0, 0];
  let wsum = 0;
  let best = -2;
  let bestK = 0;
  for (let k = 0; k < count; ++k) {
    const d = dirTex.subarray(4 * (dirFirst + k), 4 * (dirFirst + k) + 3);
    const c = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
    if (c > best) {
      best = c;
      bestK = k;
    }
    const w = Math.max(0, 1 - Math.acos(Math.min(1, Math.max(-1, c))) / radius);
    if (w > 0) {
      const col = color(k);
      for (let i = 0; i < 3; ++i) sum[i] += w * col[i];
      wsum += w;
    }
  }
  return wsum > 0 ? sum.map((x) => x / wsum) : color(bestK);
}

// IEC 61966-2-1, as common/include/rtmini/io/srgb.hpp.
export function srgbEncode(linear) {
  const x = Math.min(1, Math.max(0, linear));
  return x <= 0.0031308 ? 12.92 * x : 1.055 * x ** (1 / 2.4) - 0.055;
}
