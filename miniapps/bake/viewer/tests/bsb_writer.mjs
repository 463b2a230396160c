// Test-side writer of the binary map (README "Binary form") for maps whose vertices all
// share one direction set and have float32 positions (no uniform compaction).
export function encodeSharedBsb({ positions, dirs, colors, materials, faces, object }) {
  const nv = positions.length / 3;
  const nd = dirs.length / 3;
  const chunks = [];
  let size = 0;
  const put = (typed) => {
    chunks.push(new Uint8Array(typed.buffer, typed.byteOffset, typed.byteLength));
    size += typed.byteLength;
  };
  const pad8 = () => {
    if (size % 8) put(new Uint8Array(8 - (size % 8)));
  };
  const header = new DataView(new ArrayBuffer(64));
  [...'BSB1'].forEach((c, i) => header.setUint8(i, c.charCodeAt(0)));
  header.setUint32(4, 1, true); // shared directions; float32 colours and positions
  [nv, materials.length, faces.length, 1, nd, colors.length / 3].forEach((n, i) =>
    header.setBigUint64(8 + 8 * i, BigInt(n), true),
  );
  put(new Uint8Array(header.buffer));
  for (const section of [
    new Float32Array(positions),
    new Uint32Array(nv).fill(nd),
    new Uint8Array(nv),
    new Float32Array(dirs),
    new Float32Array(colors),
    new Float32Array(materials.flatMap((m) => [...m, 0, 1, 1])), // Ns, Ni, d defaults
    new Int32Array(faces.flatMap((f) => (f.length === 5 ? [...f, 0] : [...f.slice(0, 3), -1, f[3], 0]))),
  ]) {
    put(section);
    pad8();
  }
  const name = new TextEncoder().encode(object);
  put(new Uint32Array([name.length]));
  put(name);
  pad8();
  const bytes = new Uint8Array(size);
  let at = 0;
  for (const c of chunks) {
    bytes.set(c, at);
    at += c.length;
  }
  new DataView(bytes.buffer).setBigUint64(56, BigInt(size), true);
  return bytes;
}
