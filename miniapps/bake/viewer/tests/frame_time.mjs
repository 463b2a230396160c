// Frame time of the viewer for one map: orbits the camera once in N frames, each waited for by
// the GPU, in headless chromium (SwiftShader: software WebGL on the CPU unless RTMINI_CHROMIUM_GPU
// is set, which leaves chromium's own GPU choice).
//   node tests/frame_time.mjs MAP [QUERY] [FRAMES]   ->   one JSON line
import { dirname, basename, resolve } from 'node:path';
import { startServer } from './serve.mjs';

const [map, query = 'w=512&h=512', framesArg = '24'] = process.argv.slice(2);
if (!map) {
  console.error('usage: node tests/frame_time.mjs MAP [QUERY] [FRAMES]');
  process.exit(2);
}
const frames = Number(framesArg);
const { chromium } = await import('playwright-core');
const { server, url } = await startServer({ mounts: { '/maps/': dirname(resolve(map)) } });
const gpuArgs = process.env.RTMINI_CHROMIUM_GPU
  ? []
  : ['--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const browser = await chromium.launch({
  executablePath: process.env.RTMINI_CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', ...gpuArgs, '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run'],
});
let code = 0;
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 1100 } });
  await page.goto(`${url}index.html?map=/maps/${encodeURIComponent(basename(map))}&${query}`);
  await page.waitForFunction(() => window.__rtminiReady === true || !!window.__rtminiError, null, { timeout: 300_000 });
  const error = await page.evaluate(() => window.__rtminiError);
  if (error) {
    console.error(error);
    code = 2;
  } else {
    const ms = await page.evaluate((n) => window.__rtminiOrbitFrames(n), frames);
    const renderer = await page.evaluate(() => {
      const gl = document.createElement('canvas').getContext('webgl2');
      const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
      return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : 'unknown';
    });
    console.log(JSON.stringify({ map: basename(map), query, frames, ms_per_frame: +ms.toFixed(2),
      fps: +(1000 / ms).toFixed(2), webgl: renderer }));
  }
} finally {
  await browser.close();
  server.close();
}
process.exit(code);
