// One map, one camera, rendered by the page and by `bake render`: saves both PNGs and prints
// their agreement (agreement.mjs) as one JSON line. The results/viewer side-by-sides.
//   node tests/compare_render.mjs --bake BAKE --map MAP --out DIR --name NAME
//        --eye x,y,z --target x,y,z [--up 0,1,0] [--fov 45] [--size 512x512]
// Writes DIR/NAME_viewer.png (the page's canvas) and DIR/NAME_bake_render.png.
import { mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, dirname, join, resolve } from 'node:path';
import { bakeRender, cameraQuery, comparePixels, kLevels } from './agreement.mjs';
import { startServer } from './serve.mjs';

const option = (name, fallback) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const vec = (s) => s.split(',').map(Number);
const [bake, map, out, name] = ['--bake', '--map', '--out', '--name'].map((o) => option(o));
if (!bake || !map || !out || !name || !option('--eye') || !option('--target')) {
  console.error('usage: node tests/compare_render.mjs --bake BAKE --map MAP --out DIR --name NAME ' +
    '--eye x,y,z --target x,y,z [--up 0,1,0] [--fov 45] [--size 512x512]');
  process.exit(2);
}
const [width, height] = option('--size', '512x512').split('x').map(Number);
const cam = {
  eye: vec(option('--eye')), target: vec(option('--target')), up: vec(option('--up', '0,1,0')),
  fov: Number(option('--fov', '45')), width, height,
};
mkdirSync(out, { recursive: true });
const work = mkdtempSync(join(tmpdir(), 'rtmini-compare-'));
const render = bakeRender(bake, resolve(map), cam, join(work, 'render.ppm'));
bakeRender(bake, resolve(map), cam, join(out, `${name}_bake_render.png`));

const { chromium } = await import('playwright-core');
const { server, url } = await startServer({ mounts: { '/maps/': dirname(resolve(map)) } });
const browser = await chromium.launch({
  executablePath: process.env.RTMINI_CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
let code = 0;
try {
  const page = await browser.newPage({ viewport: { width: width + 100, height: height + 100 } });
  await page.goto(`${url}index.html?map=/maps/${encodeURIComponent(basename(map))}&${cameraQuery(cam)}`);
  await page.waitForFunction(() => window.__rtminiReady === true || !!window.__rtminiError, null, { timeout: 300_000 });
  const error = await page.evaluate(() => window.__rtminiError);
  if (error) throw new Error(error);
  await page.locator('#view').screenshot({ path: join(out, `${name}_viewer.png`) });
  const pixels = await page.evaluate(() => {
    const c = document.getElementById('view');
    const ctx = Object.assign(document.createElement('canvas'), { width: c.width, height: c.height }).getContext('2d');
    ctx.drawImage(c, 0, 0);
    return Array.from(ctx.getImageData(0, 0, c.width, c.height).data);
  });
  const m = comparePixels(pixels, render);
  console.log(JSON.stringify({ name, map: basename(map), camera: cam, levels: kLevels, ...m }));
} catch (err) {
  console.error(err.message);
  code = 1;
} finally {
  await browser.close();
  server.close();
  rmSync(work, { recursive: true, force: true });
}
process.exit(code);
