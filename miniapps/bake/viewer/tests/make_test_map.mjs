// Generates the viewer's bundled test maps (run once; the outputs are committed):
//   data/quad_zsplit.bs   a 2x2 quad in z = 0 baked with a camera-independent rule:
//                          viewpoints with d.z < 0 (seen from +z) are red on the x = -1 edge
//                          and blue on the x = +1 edge; all others (seen from -z) are green.
//   data/quad_zsplit.bsb  the same map in the binary form (layout: README "Binary form"),
//                          written by tests/bsb_writer.mjs independently of the C++ writer; the C++ unit test
//                          rtmini_unit_bsb checks both files hold the same mesh.
//   data/bad_face.bs      a face with a vertex index out of range on line 9.
import { writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { encodeSharedBsb } from './bsb_writer.mjs';

const here = join(dirname(fileURLToPath(import.meta.url)), 'data');
const kViewpoints = 64;
const kGolden = (1 + Math.sqrt(5)) / 2;

// The Fibonacci sphere of the baking paper (section 3.4), rounded to float32.
function fibonacci(i, n) {
  const z = 1 - (2 * i + 1) / n;
  const r = Math.sqrt(Math.max(0, 1 - z * z));
  const f = i / kGolden;
  const phi = 2 * Math.PI * (f - Math.floor(f));
  return [r * Math.cos(phi), r * Math.sin(phi), z].map(Math.fround);
}

const positions = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]];
const dirs = Array.from({ length: kViewpoints }, (_, i) => fibonacci(i, kViewpoints));
const colorOf = (p, d) => (d[2] < 0 ? (p[0] < 0 ? [1, 0, 0] : [0, 0, 1]) : [0, 1, 0]);
const material = [0.8, 0.8, 0.8, 0, 0, 0, 0, 0, 0];
const face = [0, 1, 2, 3, 0];

let text = '';
for (const p of positions) {
  text += `${p.join(' ')}\n`;
  for (const d of dirs) text += `| ${d.join(' ')} ${colorOf(p, d).join(' ')}\n`;
}
text += `\n: ${material.join(' ')}\n\n${face.join(' ')}\n!\n`;
writeFileSync(join(here, 'quad_zsplit.bs'), text);

writeFileSync(
  join(here, 'quad_zsplit.bsb'),
  encodeSharedBsb({
    positions: positions.flat(),
    dirs: dirs.flat(),
    colors: positions.flatMap((p) => dirs.flatMap((d) => colorOf(p, d))),
    materials: [material],
    faces: [face],
    object: 'quad_zsplit',
  }),
);

// Line 9 is the face line: vertex index 7 of 4.
writeFileSync(join(here, 'bad_face.bs'), '0 0 0\n1 0 0\n1 1 0\n0 1 0\n\n: 1 1 1  0 0 0  0 0 0\n\n0 1 2 -1\n0 1 7 0\n!\n');
