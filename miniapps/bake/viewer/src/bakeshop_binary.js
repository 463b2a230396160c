// Reader of the compact binary map (.bsb); byte layout in README.md "Binary form" and
// common/include/rtmini/io/bakeshop_binary.hpp. Sections are 8-byte aligned, so they
// are viewed in place as typed arrays (little-endian hosts, i.e. every browser platform).
import { BakeshopError } from './bakeshop_text.js';

const kShared = 1;
const kHalfColor = 2;
const kPos64 = 4;

export function isBakeshopBinary(bytes) {
  return bytes.length >= 4 && bytes[0] === 0x42 && bytes[1] === 0x53 && bytes[2] === 0x42 && bytes[3] === 0x31;
}

function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const e = (h >> 10) & 0x1f;
  const m = h & 0x3ff;
  if (e === 0) return sign * m * 2 ** -24;
  if (e === 31) return Infinity;
  return sign * (1 + m / 1024) * 2 ** (e - 15);
}

export function parseBakeshopBinary(name, buffer) {
  const bytes = new Uint8Array(buffer);
  let pos = 0;
  const fail = (reason) => {
    throw new BakeshopError(name, 0, `${reason} (at byte ${pos})`);
  };
  if (bytes.length < 64 || !isBakeshopBinary(bytes))
    fail('not a binary Bake Shop map (expected magic "BSB1" and a 64-byte header)');
  if (new Uint8Array(new Uint16Array([1]).buffer)[0] !== 1) fail('big-endian hosts are not supported');
  const view = new DataView(buffer);
  const flags = view.getUint32(4, true);
  // Bit 3: a hemisphere map (bake --directions hemisphere), directions in each vertex's frame.
  if (flags & 8) fail('a hemisphere map (bake --directions hemisphere): this viewer reads full-sphere maps only');
  if (flags & ~7) fail(`unknown flags ${flags}`);
  const [nv, nm, nf, nd, nc, size] = [8, 16, 24, 40, 48, 56].map((o) => Number(view.getBigUint64(o, true)));
  if (size !== bytes.length)
    fail(`file is ${bytes.length} bytes but its header says ${size} (truncated or corrupt)`);
  pos = 64;
  const section = (Type, count) => {
    pos = Math.ceil(pos / 8) * 8;
    if (count * Type.BYTES_PER_ELEMENT > bytes.length - pos) fail('file truncated');
    const out = new Type(buffer, pos, count);
    pos += count * Type.BYTES_PER_ELEMENT;
    return out;
  };
  const checkFinite = (array, what) => {
    for (let i = 0; i < array.length; ++i) if (!Number.isFinite(array[i])) fail(`non-finite value in ${what}`);
  };

  const positions = Float32Array.from(section(flags & kPos64 ? Float64Array : Float32Array, 3 * nv));
  checkFinite(positions, 'a position');
  const counts = section(Uint32Array, nv).slice();
  const uniform = section(Uint8Array, nv).slice();
  const dirs = section(Float32Array, 3 * nd).slice();
  checkFinite(dirs, 'a direction');
  const rawColors = section(flags & kHalfColor ? Uint16Array : Float32Array, 3 * nc);
  const colors = flags & kHalfColor ? Float32Array.from(rawColors, halfToFloat) : rawColors.slice();
  checkFinite(colors, 'a colour');
  const rawMaterials = section(Float32Array, 12 * nm);
  checkFinite(rawMaterials, 'a material');
  const rawFaces = section(Int32Array, 6 * nf);

  const shared = (flags & kShared) !== 0;
  const dirOffset = new Uint32Array(nv);
  const colorOffset = new Uint32Array(nv);
  let d = 0;
  let c = 0;
  for (let i = 0; i < nv; ++i) {
    const n = counts[i];
    if (uniform[i] > 1 || (uniform[i] === 1 && n === 0)) fail(`vertex ${i}: invalid uniform flag`);
    if (shared && n !== 0 && n !== nd) fail(`vertex ${i} has ${n} viewpoints but the shared set has ${nd}`);
    dirOffset[i] = shared ? 0 : d;
    colorOffset[i] = c;
    d += n;
    c += n === 0 ? 0 : uniform[i] ? 1 : n;
  }
  if (!shared && d !== nd) fail(`header says ${nd} directions, the vertex counts sum to ${d}`);
  if (c !== nc) fail(`header says ${nc} colours, the vertex counts need ${c}`);

  const materials = new Float32Array(9 * nm);
  for (let m = 0; m < nm; ++m) materials.set(rawMaterials.subarray(12 * m, 12 * m + 9), 9 * m);
  const faces = new Int32Array(5 * nf);
  for (let f = 0; f < nf; ++f) {
    const count = rawFaces[6 * f + 3] === -1 ? 3 : 4;
    for (let k = 0; k < 4; ++k) {
      const v = rawFaces[6 * f + k];
      if (k < count && (v < 0 || v >= nv)) fail(`face ${f}: vertex index ${v} out of range [0, ${nv})`);
      faces[5 * f + k] = v;
    }
    const material = rawFaces[6 * f + 4];
    if (material < -1 || material >= nm) fail(`face ${f}: material index ${material} out of range [-1, ${nm})`);
    faces[5 * f + 4] = material;
  }
  return {
    vertexCount: nv,
    positions,
    counts,
    uniform,
    shared,
    dirs,
    dirOffset,
    colorOffset,
    colors,
    materials,
    faces,
  };
}
