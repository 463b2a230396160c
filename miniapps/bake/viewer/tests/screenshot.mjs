// Saves the viewer's canvas for one map and camera as a PNG (headless chromium).
//   node tests/screenshot.mjs MAP OUT.png ['eye=x,y,z&target=x,y,z&fov=45&w=512&h=512&grid=1']
import { dirname, basename, resolve } from 'node:path';
import { startServer } from './serve.mjs';

const [map, out, query = 'w=512&h=512'] = process.argv.slice(2);
if (!map || !out) {
  console.error('usage: node tests/screenshot.mjs MAP OUT.png [QUERY]');
  process.exit(2);
}
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
  const page = await browser.newPage({ viewport: { width: 1100, height: 1100 } });
  await page.goto(`${url}index.html?map=/maps/${encodeURIComponent(basename(map))}&${query}`);
  await page.waitForFunction(() => window.__rtminiReady === true || !!window.__rtminiError, null, { timeout: 120_000 });
  const error = await page.evaluate(() => window.__rtminiError);
  if (error) {
    console.error(error);
    code = 2;
  } else {
    await page.locator('#view').screenshot({ path: out });
    console.log(`${out}: ${await page.locator('#status').textContent()}`);
  }
} finally {
  await browser.close();
  server.close();
}
process.exit(code);
