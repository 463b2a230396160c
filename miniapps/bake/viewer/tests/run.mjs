// End-to-end test of the viewer: a localhost server, Debian's chromium driven headless by
// playwright-core with SwiftShader WebGL, the bundled test maps. Exit 0 pass, 1 fail,
// 77 skipped (node_modules or chromium missing).
//   node tests/run.mjs [--screenshots DIR] [--bake PATH/TO/bake] [--checks page,agreement]
// --checks picks the groups (default both): `page` = checks 1-6 on the bundled test maps,
// `agreement` = check 7, the page and `bake render` (--bake, passed by ctest) on one freshly
// baked map for the same cameras (agreement.mjs). ctest runs the groups as two tests.
import { spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { bakeRender, cameraQuery, comparePixels, kLevels } from './agreement.mjs';
import { startServer, viewerRoot } from './serve.mjs';

const kSkip = 77;
const kTimeLimitMs = 150_000;
const kChromium = process.env.RTMINI_CHROMIUM ?? '/usr/bin/chromium';
const kSize = 256;
const kTolerance = 3; // 8-bit sRGB codes

for (const dep of ['node_modules/three/build/three.module.js', 'node_modules/playwright-core/package.json']) {
  if (!existsSync(join(viewerRoot, dep))) {
    console.log(`SKIP: ${dep} missing (run: npm ci --prefix miniapps/bake/viewer)`);
    process.exit(kSkip);
  }
}
if (!existsSync(kChromium)) {
  console.log(`SKIP: ${kChromium} missing (apt-get install chromium, or set RTMINI_CHROMIUM)`);
  process.exit(kSkip);
}
const option = (name) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : null;
};
const shotDir = option('--screenshots');
if (shotDir) mkdirSync(shotDir, { recursive: true });
const groups = (option('--checks') ?? 'page,agreement').split(',');
const bake = option('--bake');
if (bake && !existsSync(bake)) {
  console.error(`FAIL: --bake ${bake} does not exist`);
  process.exit(1);
}
const workDir = mkdtempSync(join(tmpdir(), 'rtmini-viewer-'));

setTimeout(() => {
  console.error(`FAIL: time limit of ${kTimeLimitMs / 1000} s reached`);
  process.exit(1);
}, kTimeLimitMs).unref();

const { chromium } = await import('playwright-core');
const THREE = await import(join(viewerRoot, 'node_modules/three/build/three.module.js'));
const { srgbEncode } = await import('../src/lookup.js');

let failures = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures++;
}

const { server, url } = await startServer({ mounts: { '/maps/': workDir } });
const browser = await chromium.launch({
  executablePath: kChromium,
  headless: true,
  timeout: 60_000,
  args: [
    '--no-sandbox',
    '--disable-gpu',
    '--use-angle=swiftshader',
    '--enable-unsafe-swiftshader',
    '--disable-background-networking',
    '--disable-component-update',
    '--disable-sync',
    '--no-first-run',
  ],
});

try {
  const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
  page.on('console', (m) => {
    if (m.type() === 'error') console.log(`  page console: ${m.text()}`);
  });
  page.on('pageerror', (e) => console.log(`  page error: ${e.message}`));

  const camera = (eye, up) => `eye=${eye.join(',')}&target=0,0,0&up=${up.join(',')}&fov=45&w=${kSize}&h=${kSize}`;
  async function open(map, eye, extra = '', up = [0, 1, 0]) {
    await page.goto(`${url}index.html?map=${map}&${camera(eye, up)}${extra}`);
    await page.waitForFunction(() => window.__rtminiReady === true || !!window.__rtminiError, null, {
      timeout: 60_000,
    });
    return page.evaluate(() => window.__rtminiError);
  }
  // The canvas's pixels, top row first, read from the preserved drawing buffer.
  async function pixels() {
    return page.evaluate(() => {
      const c = document.getElementById('view');
      const ctx = Object.assign(document.createElement('canvas'), { width: c.width, height: c.height }).getContext('2d');
      ctx.drawImage(c, 0, 0);
      return Array.from(ctx.getImageData(0, 0, c.width, c.height).data);
    });
  }
  const at = (px, x, y) => px.slice(4 * (y * kSize + x), 4 * (y * kSize + x) + 3);
  const close = (a, b) => a.length === 3 && a.every((v, i) => Math.abs(v - b[i]) <= kTolerance);
  const code = (linear) => linear.map((v) => Math.round(255 * srgbEncode(v)));
  async function shot(name) {
    if (shotDir) await page.locator('#view').screenshot({ path: join(shotDir, name) });
  }

  // Pixel centre (x, y) of world point p for the URL camera, as the page's three.js sets it up.
  function project(eye, p, up = [0, 1, 0]) {
    const cam = new THREE.PerspectiveCamera(45, 1, 0.1, 100);
    cam.position.set(...eye);
    cam.up.set(...up);
    cam.lookAt(0, 0, 0);
    cam.updateMatrixWorld();
    const v = new THREE.Vector3(...p).project(cam);
    return [Math.floor(((v.x + 1) / 2) * kSize), Math.floor(((1 - v.y) / 2) * kSize)];
  }

  // Check 0 (no page): lookup.js's KD-tree query returns the brute-force neighbours and
  // weights (the shader walks the same tree), on Fibonacci sets and random directions.
  if (groups.includes('page')) {
    const { buildKdTree, kdNeighbors, bruteForceNeighbors, fibonacciRadius } = await import('../src/lookup.js');
    let worst = 0;
    let mismatches = 0;
    let seed = 12345;
    const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
    for (const n of [7, 20, 64, 100, 1000]) {
      const dirs = new Float32Array(3 * n);
      for (let i = 0; i < n; ++i) {
        const z = 1 - (2 * i + 1) / n;
        const r = Math.sqrt(1 - z * z);
        const phi = 2 * Math.PI * ((i / ((1 + Math.sqrt(5)) / 2)) % 1);
        dirs.set([r * Math.cos(phi), r * Math.sin(phi), z], 3 * i);
      }
      const tree = buildKdTree(dirs, n);
      for (let t = 0; t < 300; ++t) {
        const zq = 2 * random() - 1;
        const a = 2 * Math.PI * random();
        const q = [Math.sqrt(1 - zq * zq) * Math.cos(a), Math.sqrt(1 - zq * zq) * Math.sin(a), zq];
        const kd = kdNeighbors(tree, n, q, fibonacciRadius(n));
        const bf = bruteForceNeighbors((k) => dirs.subarray(3 * k, 3 * k + 3), n, q, fibonacciRadius(n));
        if (kd.index.join() !== bf.index.join()) ++mismatches;
        kd.weight.forEach((w, k) => (worst = Math.max(worst, Math.abs(w - (bf.weight[k] ?? 0)))));
      }
    }
    check(mismatches === 0 && worst < 1e-12, `KD-tree lookup = brute force (${mismatches} mismatches, max weight diff ${worst})`);
  }

  // Checks 1-6: the bundled test maps.
  if (groups.includes('page')) await pageChecks();
  async function pageChecks() {
    // 1. From +z every viewpoint looked up has d.z < 0: red at x = -1 blending to blue at
    //    x = +1, screen-linear (the quad is parallel to the image plane).
    const top = [0, 0, 3];
    let err = await open('tests/data/quad_zsplit.bs', top);
    check(!err, `text map loads (${err ?? 'no error'})`);
    const textPx = await pixels();
    await shot('quad_zsplit_top.png');
    for (const x of [-0.75, -0.5, 0, 0.5, 0.75]) {
      for (const y of [-0.6, 0.4]) {
        const [px, py] = project(top, [x, y, 0]);
        const s = (x + 1) / 2;
        const want = code([1 - s, 0, s]);
        const got = at(textPx, px, py);
        check(close(got, want), `from +z, world (${x}, ${y}) pixel (${px}, ${py}): ${got} ~ ${want}`);
      }
    }
    const [cx, cy] = project(top, [-1.2, 1.2, 0]);
    check(close(at(textPx, cx, cy), [0, 0, 0]), `outside the quad is background: ${at(textPx, cx, cy)}`);

    // 2. The binary form renders the same pixels.
    err = await open('tests/data/quad_zsplit.bsb', top);
    check(!err, `binary map loads (${err ?? 'no error'})`);
    const binPx = await pixels();
    let maxDiff = 0;
    for (let i = 0; i < textPx.length; ++i) maxDiff = Math.max(maxDiff, Math.abs(textPx[i] - binPx[i]));
    check(maxDiff === 0, `binary and text forms render identical pixels (max difference ${maxDiff})`);

    // 3. From -z every camera ray has d.z > 0: green everywhere on the quad.
    const below = [0, 0, -3];
    await open('tests/data/quad_zsplit.bs', below);
    const belowPx = await pixels();
    await shot('quad_zsplit_below.png');
    for (const x of [-0.75, 0, 0.75]) {
      const [px, py] = project(below, [x, 0.3, 0]);
      check(close(at(belowPx, px, py), [0, 255, 0]), `from -z, world (${x}, 0.3): ${at(belowPx, px, py)} green`);
    }

    // 4. Grazing camera in the grid-of-vertices view: each vertex's point shows the blend
    //    of red/blue and green viewpoints given by the lookup rule (lookup.js), and the
    //    quad's interior is background.
    const grazing = [0.6, -5, 0.4];
    await open('tests/data/quad_zsplit.bs', grazing, '&grid=1', [0, 0, 1]);
    const gridPx = await pixels();
    await shot('quad_zsplit_grid_grazing.png');
    const expectGrid = await page.evaluate(async (eye) => {
      const { lookupColor } = await import('./src/lookup.js');
      const res = await fetch('tests/data/quad_zsplit.bsb');
      const { parseBakeshopBinary } = await import('./src/bakeshop_binary.js');
      const { packMap } = await import('./src/pack_map.js');
      const p = packMap(parseBakeshopBinary('quad_zsplit.bsb', await res.arrayBuffer()));
      return [0, 1, 2, 3].map((v) => lookupColor(p, v, [0, 1, 2].map((i) => p.positions[3 * v + i] - eye[i])));
    }, grazing);
    const corners = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]];
    corners.forEach((p, v) => {
      const [px, py] = project(grazing, p, [0, 0, 1]);
      const want = code(expectGrid[v]);
      const got = at(gridPx, px, py);
      const mixed = want[1] > 20 && (want[0] > 20 || want[2] > 20);
      check(close(got, want), `grid view vertex ${v} pixel (${px}, ${py}): ${got} ~ ${want}${mixed ? ' (blend)' : ''}`);
    });
    const [mx, my] = project(grazing, [0, 0, 0], [0, 0, 1]);
    check(close(at(gridPx, mx, my), [0, 0, 0]), `grid view shows no faces: ${at(gridPx, mx, my)}`);

    // 5. Picking a vertex shows its viewpoint sphere.
    await open('tests/data/quad_zsplit.bs', [1.5, 1.5, 3]);
    const [vx, vy] = project([1.5, 1.5, 3], [0.95, 0.95, 0]);
    const box = await page.locator('#view').boundingBox();
    await page.mouse.click(box.x + vx + 0.5, box.y + vy + 0.5);
    const picked = await page.evaluate(() => window.__rtminiPicked);
    check(picked === 2, `click near vertex 2 picks it (${picked})`);
    check((await page.locator('#info').textContent()).includes('64 viewpoints'), 'info panel lists 64 viewpoints');
    await shot('quad_zsplit_picked.png');

    // 6. A malformed map names the file, the line and the problem (the C++ reader's words;
    //    tests/unit/viewer_format checks the C++ side says the same).
    err = await open('tests/data/bad_face.bs', top);
    const shown = await page.locator('#error').textContent();
    const want = 'bad_face.bs:9: vertex index 7 out of range [0, 4)';
    check(err === want && shown === want && (await page.locator('#error').isVisible()), `malformed map message "${shown}"`);
  }

  // 7. The page and `bake render` agree. The bundled Cornell box (mirror boxes, Kr 0.725, so
  //    strongly view dependent) is baked with N = 100, K = 2 and rendered by both for two
  //    cameras at 256 x 256. Tolerances: mean |difference| <= kMeanLevels 8-bit codes over all
  //    pixels, at most kFractionOver of the pixels off by more than kLevels (edges and
  //    silhouettes, where rasteriser and ray caster may pick different faces), and mean
  //    <= kInteriorMeanLevels away from edges. Measured: README "Tests".
  if (groups.includes('agreement') && bake) {
    const kMeanLevels = 0.5;
    const kInteriorMeanLevels = 0.05;
    const kFractionOver = 0.003;
    const scene = join(viewerRoot, '../../../inputs/cornell/cornell_box.bs');
    const map = join(workDir, 'cornell_box_n100_k2.bsb');
    const bakeRun = spawnSync(
      bake, [scene, '--viewpoints', '100', '--iterations', '2', '-o', map],
      { encoding: 'utf8', env: { OMP_NUM_THREADS: '2', ...process.env } });
    check(bakeRun.status === 0, `bake ${scene} -n 100 -k 2 -o ${map} (${bakeRun.status})`);
    const cameras = [
      { name: 'front', eye: [0, 1, 3.9], target: [0, 1, 0], up: [0, 1, 0], fov: 45, width: kSize, height: kSize },
      { name: 'boxes', eye: [0.9, 1.1, 2.4], target: [-0.1, 0.7, -0.2], up: [0, 1, 0], fov: 45, width: kSize, height: kSize },
    ];
    for (const cam of cameras) {
      if (bakeRun.status !== 0) break;
      const render = bakeRender(bake, map, cam, join(workDir, `${cam.name}.ppm`));
      await page.goto(`${url}index.html?map=/maps/cornell_box_n100_k2.bsb&${cameraQuery(cam)}`);
      await page.waitForFunction(() => window.__rtminiReady === true || !!window.__rtminiError, null, { timeout: 60_000 });
      const pageError = await page.evaluate(() => window.__rtminiError);
      check(!pageError, `page loads the baked map (${pageError ?? 'no error'})`);
      await shot(`agreement_${cam.name}.png`);
      const m = comparePixels(await pixels(), render);
      const f = (x, n = 3) => x.toFixed(n);
      check(m.mapPixels > 0.2 * m.pixels, `${cam.name}: the map covers ${m.mapPixels} of ${m.pixels} pixels`);
      check(
        m.meanAbs <= kMeanLevels && m.fractionOver <= kFractionOver && m.interiorMeanAbs <= kInteriorMeanLevels,
        `${cam.name}: page vs bake render: mean |d| ${f(m.meanAbs)} (<= ${kMeanLevels}), ` +
          `${f(100 * m.fractionOver)} % of pixels > ${kLevels} levels (<= ${100 * kFractionOver} %), ` +
          `interior mean ${f(m.interiorMeanAbs)} over ${m.interiorPixels} px (<= ${kInteriorMeanLevels}), max ${m.maxDiff}`,
      );
    }
  } else if (groups.includes('agreement')) {
    console.log('note: no --bake given, page vs bake render agreement not checked');
  }
} finally {
  await browser.close();
  server.close();
  rmSync(workDir, { recursive: true, force: true });
}
console.log(failures ? `${failures} check(s) failed` : 'all viewer checks passed');
process.exit(failures ? 1 : 0);
