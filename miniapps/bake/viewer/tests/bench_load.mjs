// Load-time measurement of a large synthetic map, text (.bs) against binary (.bsb), in
// headless chromium: wall time until the first frame and the longest main-thread stall
// (largest gap between animation frames) while loading, which shows whether parsing in
// the worker keeps the page responsive.
//   node tests/bench_load.mjs [--grid 100] [--viewpoints 100] [--out FILE.json]
import { mkdtempSync, rmSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { encodeSharedBsb } from './bsb_writer.mjs';
import { startServer } from './serve.mjs';

const arg = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const grid = Number(arg('--grid', 100));
const n = Number(arg('--viewpoints', 100));
const out = arg('--out', null);
const kChromium = process.env.RTMINI_CHROMIUM ?? '/usr/bin/chromium';

// A grid x grid vertex sheet; colours vary smoothly with position and direction.
const golden = (1 + Math.sqrt(5)) / 2;
const dirs = [];
for (let i = 0; i < n; ++i) {
  const z = 1 - (2 * i + 1) / n;
  const r = Math.sqrt(1 - z * z);
  const phi = 2 * Math.PI * ((i / golden) % 1);
  dirs.push(...[r * Math.cos(phi), r * Math.sin(phi), z].map(Math.fround));
}
const positions = [];
const colors = [];
for (let j = 0; j < grid; ++j) {
  for (let i = 0; i < grid; ++i) {
    const p = [i / (grid - 1) - 0.5, j / (grid - 1) - 0.5, 0];
    positions.push(...p);
    for (let k = 0; k < n; ++k) colors.push(...[0.5 + p[0], 0.5 + p[1], dirs[3 * k + 2] < 0 ? 0.2 : 0.8].map(Math.fround));
  }
}
const faces = [];
for (let j = 0; j + 1 < grid; ++j)
  for (let i = 0; i + 1 < grid; ++i) faces.push([j * grid + i, j * grid + i + 1, (j + 1) * grid + i + 1, (j + 1) * grid + i, 0]);

const dir = mkdtempSync(join(tmpdir(), 'rtmini_viewer_bench_'));
const lines = [];
for (let v = 0; v < grid * grid; ++v) {
  lines.push(positions.slice(3 * v, 3 * v + 3).join(' '));
  for (let k = 0; k < n; ++k)
    lines.push(`| ${dirs.slice(3 * k, 3 * k + 3).join(' ')} ${colors.slice(3 * (v * n + k), 3 * (v * n + k) + 3).join(' ')}`);
}
writeFileSync(join(dir, 'sheet.bs'), `${lines.join('\n')}\n\n: 0.8 0.8 0.8 0 0 0 0 0 0\n\n${faces.map((f) => f.join(' ')).join('\n')}\n!\n`);
writeFileSync(join(dir, 'sheet.bsb'), encodeSharedBsb({ positions, dirs, colors, materials: [[0.8, 0.8, 0.8, 0, 0, 0, 0, 0, 0]], faces, object: 'sheet' }));

const { chromium } = await import('playwright-core');
const { server, url } = await startServer({ mounts: { '/bench/': dir } });
const browser = await chromium.launch({
  executablePath: kChromium,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const results = { vertices: grid * grid, viewpoints: n, faces: faces.length, backend: 'chromium headless, SwiftShader WebGL', runs: [] };
try {
  const page = await browser.newPage();
  for (const file of ['sheet.bs', 'sheet.bsb', 'sheet.bs', 'sheet.bsb']) {
    await page.goto(`${url}index.html?w=512&h=512`);
    const r = await page.evaluate(async (mapUrl) => {
      let maxGap = 0;
      let last = performance.now();
      let done = false;
      const tick = () => {
        const now = performance.now();
        maxGap = Math.max(maxGap, now - last);
        last = now;
        if (!done) requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
      const t0 = performance.now();
      const input = document.getElementById('file');
      const blob = await (await fetch(mapUrl)).blob();
      const dt = new DataTransfer();
      dt.items.add(new File([blob], mapUrl.split('/').pop()));
      input.files = dt.files;
      input.dispatchEvent(new Event('change'));
      await new Promise((resolve) => {
        const poll = () => (window.__rtminiReady || window.__rtminiError ? resolve() : setTimeout(poll, 5));
        poll();
      });
      done = true;
      return { ms: performance.now() - t0, maxFrameGapMs: maxGap, error: window.__rtminiError, status: document.getElementById('status').textContent };
    }, `${url}bench/${file}`);
    results.runs.push({ file, bytes: statSync(join(dir, file)).size, ...r });
    console.log(`${file}: ${statSync(join(dir, file)).size} bytes, ready in ${r.ms.toFixed(0)} ms, longest frame gap ${r.maxFrameGapMs.toFixed(0)} ms ${r.error ?? ''}`);
  }
} finally {
  await browser.close();
  server.close();
  rmSync(dir, { recursive: true, force: true });
}
if (out) writeFileSync(out, `${JSON.stringify(results, null, 2)}\n`);
