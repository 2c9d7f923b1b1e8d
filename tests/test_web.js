// test_web.js - the preview page and lucent.js in real headless Chromium (Debian's chromium, driven by
// playwright-core) against a test lucentd: renders, presets, sliders, uploads, errors, links, layout at 360 px.
// Usage: node test_web.js PATH/TO/lucentd ARTIFACT_DIR NODE_MODULES_DIR. Screenshots go to ARTIFACT_DIR.
'use strict';

const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const zlib = require('zlib');

const [lucentd, artifacts, nodeModules] = process.argv.slice(2);
if (!lucentd || !artifacts || !nodeModules) {
  console.error('usage: node test_web.js PATH/TO/lucentd ARTIFACT_DIR NODE_MODULES_DIR');
  process.exit(2);
}
const { chromium } = require(path.resolve(nodeModules, 'playwright-core'));

const SIZE = 96;
const WAIT_MS = 30000;
// The page's debounce (client/web/app.js): control changes closer together than this make one request.
const DEBOUNCE_MS = 250;
const TRIES = 3;
// Light from behind (skim milk, the protrusion): at least this share of the covered pixels at this 8-bit level
// or brighter (measured: 99.5%, median 22/255; with the five camera views only: none).
const GLOW_LEVEL = 8;
const GLOW_SHARE = 0.5;
let passed = 0;
let failed = 0;

function check(name, ok, measured) {
  if (ok) passed++;
  else failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${name}: ${measured}`);
}

// Runs one step; an exception (a wait that timed out) fails the step and the run goes on.
async function step(name, fn) {
  try {
    await fn();
  } catch (e) {
    check(name, false, `threw ${String(e.message).split('\n')[0]}`);
  }
}

// The PNG signature and the IHDR size, or null.
function pngSize(buf) {
  const signature = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
  if (buf.length < 24 || !buf.subarray(0, 8).equals(signature) || buf.toString('latin1', 12, 16) !== 'IHDR') return null;
  return { w: buf.readUInt32BE(16), h: buf.readUInt32BE(20) };
}
// RGBA pixels of one of lucentd's PNGs: 8-bit RGBA, written without row filters (filter byte 0 on every row).
function decodePng(buf) {
  const { w, h } = pngSize(buf);
  const idat = [];
  for (let at = 8; at < buf.length;) {
    const len = buf.readUInt32BE(at);
    if (buf.toString('latin1', at + 4, at + 8) === 'IDAT') idat.push(buf.subarray(at + 8, at + 8 + len));
    at += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const data = Buffer.alloc(w * h * 4);
  for (let y = 0; y < h; y++) {
    if (raw[y * (w * 4 + 1)] !== 0) throw new Error(`row ${y} uses PNG filter ${raw[y * (w * 4 + 1)]}`);
    raw.copy(data, y * w * 4, y * (w * 4 + 1) + 1, (y + 1) * (w * 4 + 1));
  }
  return data;
}

// The page's measure, written again: rel L2 over R, G, B composited over black.
function relL2(image, ref) {
  let num = 0, den = 0;
  for (let i = 0; i < ref.length; i += 4) {
    for (let c = 0; c < 3; c++) {
      const x = (image[i + c] * image[i + 3]) / 255, r = (ref[i + c] * ref[i + 3]) / 255;
      num += (x - r) ** 2;
      den += r * r;
    }
  }
  return Math.sqrt(num / den);
}
const sizeText = (s) => (s ? `PNG ${s.w}x${s.h}` : 'not a PNG');

// Starts lucentd on a free port (as tests/test_lucentd.sh does): the port from its log, then /readyz.
async function startDaemon(work, name, extra) {
  const logPath = path.join(work, `${name}.log`);
  const log = fs.openSync(logPath, 'w');
  const child = spawn(lucentd, ['--port', '0', '--log-level', 'info', '--store-dir', path.join(work, 'store'), ...extra],
    { stdio: ['ignore', 'ignore', log] });
  for (let i = 0; i < 300; i++) {
    const m = fs.readFileSync(logPath, 'utf8').match(/listening on (http:\/\/127\.0\.0\.1:\d+)/);
    if (m) {
      const ready = await fetch(`${m[1]}/readyz`).then((r) => r.status, () => 0);
      if (ready === 200) return { child, base: m[1], logPath };
    }
    await new Promise((r) => setTimeout(r, 100));
  }
  child.kill('SIGKILL');
  throw new Error(`lucentd did not become ready:\n${fs.readFileSync(logPath, 'utf8')}`);
}

async function stopDaemon(child) {
  const exited = new Promise((resolve) => child.once('exit', (code) => resolve(code)));
  child.kill('SIGTERM');
  return exited;
}

// The static routes over plain HTTP: types, caching headers, 304, methods.
async function checkStaticRoutes(base) {
  const types = { '/': 'text/html', '/app.js': 'text/javascript', '/style.css': 'text/css',
    '/lucent.js': 'text/javascript', '/embed-example.html': 'text/html' };
  for (const [p, type] of Object.entries(types)) {
    const r = await fetch(base + p);
    const body = await r.text();
    const ct = r.headers.get('content-type') || '';
    check(`GET ${p}`, r.status === 200 && ct.startsWith(type) && body.length > 100 && r.headers.get('etag') &&
      r.headers.get('cache-control') === 'no-cache',
    `${r.status}, ${ct}, ${body.length} bytes, ETag ${r.headers.get('etag')}, Cache-Control ${r.headers.get('cache-control')}`);
  }
  const first = await fetch(`${base}/`);
  const again = await fetch(`${base}/`, { headers: { 'If-None-Match': first.headers.get('etag') } });
  check('GET / with If-None-Match answers 304', again.status === 304, `${again.status}`);
  const head = await fetch(`${base}/lucent.js`, { method: 'HEAD' });
  check('HEAD /lucent.js', head.status === 200 && (await head.text()) === '', `${head.status}`);
  const post = await fetch(`${base}/`, { method: 'POST', body: 'x' });
  check('POST / is 405 with Allow', post.status === 405 && /GET, HEAD/.test(post.headers.get('allow')),
    `${post.status}, Allow: ${post.headers.get('allow')}`);
  const missing = await fetch(`${base}/missing.html`);
  check('GET /missing.html is 404', missing.status === 404, `${missing.status}`);
  const csp = first.headers.get('content-security-policy') || '';
  check('the page forbids other origins (CSP)', csp.includes("default-src 'self'"), csp);
}

// Bytes of the image an <img> shows (a blob: URL or a daemon URL), fetched inside the page.
async function imageBytes(page, selector) {
  const bytes = await page.evaluate(async (sel) => {
    const r = await fetch(document.querySelector(sel).src);
    return Array.from(new Uint8Array(await r.arrayBuffer()));
  }, selector);
  return Buffer.from(bytes);
}

const renders = (page, figure) => page.evaluate((id) => Number(document.getElementById(id).dataset.renders || 0), figure);
async function waitRenders(page, figure, atLeast) {
  await page.waitForFunction(([id, n]) => Number(document.getElementById(id).dataset.renders || 0) >= n,
    [figure, atLeast], { timeout: WAIT_MS });
}

// Checks the image of #image-a after a render: decodes at SIZE, is a PNG of SIZE, differs from `before`.
async function checkImage(page, name, before) {
  const natural = await page.$eval('#image-a', (img) => [img.naturalWidth, img.naturalHeight]);
  const bytes = await imageBytes(page, '#image-a');
  const png = pngSize(bytes);
  const changed = !before || !bytes.equals(before);
  check(name, natural[0] === SIZE && natural[1] === SIZE && png && png.w === SIZE && png.h === SIZE && changed,
    `naturalWidth/Height ${natural.join('x')}, ${sizeText(png)}, ${bytes.length} bytes` +
    (before ? `, ${changed ? 'differs from' : 'SAME AS'} the previous image` : ''));
  return bytes;
}

// Observers the test adds to the page (they change nothing it does): the page time of each input event on the
// azimuth slider; each fetch() for /v1/render as the page makes it, with when and how it ended ("response"
// once the headers are in, or the error's name); and each text of the first image's status line, with its time.
async function observePage(page) {
  await page.evaluate(() => {
    const seen = { inputs: [], renders: [], statuses: [] };
    window.lucentTest = seen;
    document.getElementById('azimuth').addEventListener('input', () => seen.inputs.push(performance.now()));
    const realFetch = window.fetch;
    window.fetch = (url, options) => {
      const answer = realFetch(url, options);
      if (String(url).includes('/v1/render?')) {
        const call = { url: String(url), start: performance.now(), end: 0, outcome: '' };
        seen.renders.push(call);
        answer.then(() => Object.assign(call, { end: performance.now(), outcome: 'response' }),
          (e) => Object.assign(call, { end: performance.now(), outcome: e.name }));
      }
      return answer;
    };
    new MutationObserver((records) => {
      const t = performance.now();
      for (const r of records) for (const node of r.addedNodes) seen.statuses.push({ t, text: node.textContent });
    }).observe(document.getElementById('status-a'), { childList: true });
  });
}

// Presses ArrowLeft `presses` times on the azimuth slider. Resolves once every request those presses cause has
// been fetched: a page timer set after the last input event with twice the debounce runs after any debounce
// timer the presses set (timers run in the order they are due), and the page fetches within that timer's task.
// Returns the gaps between the input events (page time) and the number of fetches.
async function pressAzimuth(page, presses) {
  const from = await page.evaluate(() => {
    window.lucentTest.inputs = [];
    return window.lucentTest.renders.length;
  });
  await page.focus('#azimuth');
  for (let i = 0; i < presses; i++) await page.keyboard.press('ArrowLeft');
  await page.waitForFunction((n) => window.lucentTest.inputs.length >= n, presses, { timeout: WAIT_MS });
  return page.evaluate(([ms, i]) => new Promise((resolve) => setTimeout(() => {
    const t = window.lucentTest.inputs;
    resolve({ gaps: t.slice(1).map((x, k) => Math.round(x - t[k])), fetches: window.lucentTest.renders.length - i });
  }, ms)), [2 * DEBOUNCE_MS, from]);
}

// Waits until the first image shows a finished render of `method` and no request for it is running.
async function waitShown(page, method) {
  await page.waitForFunction((m) => document.getElementById('status-a').textContent.startsWith(`${m}, `) &&
    !document.getElementById('figure-a').hasAttribute('aria-busy'), method, { timeout: WAIT_MS });
}

// lucentd_renders_in_flight from the daemon's /metrics.
async function inFlight(base) {
  const text = await (await fetch(`${base}/metrics`)).text();
  return Number(text.match(/^lucentd_renders_in_flight (\d+)$/m)[1]);
}

const CUBE_OBJ = `# a unit cube
v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5
v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6
`;

async function main() {
  const work = fs.mkdtempSync(path.join(os.tmpdir(), 'lucent-web-'));
  const daemon = await startDaemon(work, 'lucentd', []);
  const { base } = daemon;
  console.log(`started lucentd at ${base}`);
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox'] });
  const external = [];
  const pageErrors = [];
  const watch = (page) => {
    page.on('request', (r) => {
      if (!r.url().startsWith('http://127.0.0.1:') && !/^(blob|data):/.test(r.url())) external.push(r.url());
    });
    page.on('pageerror', (e) => pageErrors.push(e.message));
  };
  try {
    await step('static routes', () => checkStaticRoutes(base));

    const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
    await context.grantPermissions(['clipboard-read', 'clipboard-write'], { origin: base });
    const page = await context.newPage();
    watch(page);
    let last = null;

    await step('first image', async () => {
      await page.goto(`${base}/?size=${SIZE}&mesh=protrusion&preset=skin1`);
      await waitRenders(page, 'figure-a', 1);
      last = await checkImage(page, 'first image', null);
      const status = await page.textContent('#status-a');
      check('render time shown beside the image', /rendered in [0-9.]+ ms/.test(status), status);
      const modelled = JSON.parse(await page.textContent('#modelled-a'));
      check('what was modelled shown (Lucent-Modelled)', modelled.method === 'five' && modelled.views === 5,
        `method ${modelled.method}, views ${modelled.views}`);
    });

    await step('preset change', async () => {
      const n = await renders(page, 'figure-a');
      await page.selectOption('#preset', 'ketchup');
      await waitRenders(page, 'figure-a', n + 1);
      last = await checkImage(page, 'preset ketchup: new image', last);
      const link = await page.inputValue('#link');
      check('link names the preset', link.includes('preset=ketchup'), link);
    });

    await step('slider by keyboard', async () => {
      const n = await renders(page, 'figure-a');
      await page.focus('#sigma_a-1');
      await page.keyboard.press('End');
      await waitRenders(page, 'figure-a', n + 1);
      last = await checkImage(page, 'sigma_a green slider (keyboard End): new image', last);
      const link = await page.inputValue('#link');
      const preset = await page.inputValue('#preset');
      check('moving a slider switches to coefficients', preset === '' && !link.includes('preset=') &&
        /sigma_a=0\.061,10,1\.45&/.test(link), `preset "${preset}", link ${link}`);
    });

    await step('light from behind', async () => {
      // Azimuth 180 (the slider's end): the light comes from behind the object, which must glow with the light
      // through it (a light view), not stay a black silhouette. Skim milk: light crosses the 50 mm protrusion.
      await page.selectOption('#preset', 'skimmilk');
      await waitRenders(page, 'figure-a', await renders(page, 'figure-a') + 1);
      const n = await renders(page, 'figure-a');
      await page.focus('#azimuth');
      await page.keyboard.press('End');
      await waitRenders(page, 'figure-a', n + 1);
      last = await checkImage(page, 'azimuth 180, light from behind: new image', last);
      const modelled = JSON.parse(await page.textContent('#modelled-a'));
      const px = decodePng(last);
      let covered = 0, glowing = 0;
      for (let i = 0; i < px.length; i += 4) {
        if (px[i + 3] === 0) continue;
        covered++;
        if (Math.max(px[i], px[i + 1], px[i + 2]) >= GLOW_LEVEL) glowing++;
      }
      check('light from behind glows through the object', (modelled.transmission || []).includes('light view') &&
        glowing >= GLOW_SHARE * covered, `transmission ${JSON.stringify(modelled.transmission)}, ${glowing} of ` +
        `${covered} covered pixels at ${GLOW_LEVEL}/255 or brighter (want ${GLOW_SHARE * 100}%)`);
    });

    await step('orbit by dragging', async () => {
      // The default view is the daemon's three-quarter one; dragging the image 60 px left turns the camera
      // 30 degrees (0.5 a pixel) around the object: the link's camera_dir follows, a new image comes, and the
      // light, given relative to the camera, turns with it.
      const before = new URL(await page.inputValue('#link')).searchParams;
      const n = await renders(page, 'figure-a');
      const box = await page.locator('#image-a').boundingBox();
      const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
      await page.mouse.move(x, y);
      await page.mouse.down();
      for (let i = 1; i <= 6; i++) await page.mouse.move(x - 10 * i, y);
      await page.mouse.up();
      await waitRenders(page, 'figure-a', n + 1);
      const after = new URL(await page.inputValue('#link')).searchParams;
      const vec = (q, k) => (q.get(k) || '').split(',').map(Number);
      const angle = (a, b) => Math.acos(Math.min(1, a.reduce((s, x, i) => s + x * b[i], 0))) * 180 / Math.PI;
      const turned = angle(vec(before, 'camera_dir'), vec(after, 'camera_dir'));
      const lightTurned = angle(vec(before, 'light_dir'), vec(after, 'light_dir'));
      const azimuth = await page.inputValue('#view_azimuth');
      check('dragging orbits the camera', Math.abs(turned - 30 * Math.cos(25 * Math.PI / 180)) < 3 &&
        lightTurned > 10, `camera_dir ${before.get('camera_dir')} -> ${after.get('camera_dir')} (${turned.toFixed(1)} ` +
        `degrees), light_dir turned ${lightTurned.toFixed(1)} degrees, view azimuth slider ${azimuth}`);
      last = await checkImage(page, 'image after orbiting', last);
    });

    await step('mesh upload', async () => {
      const n = await renders(page, 'figure-a');
      await page.setInputFiles('#mesh-file', { name: 'cube.obj', mimeType: 'text/plain', buffer: Buffer.from(CUBE_OBJ) });
      await page.waitForFunction(() => /^[0-9a-f]{64}$/.test(document.getElementById('mesh').value), null,
        { timeout: WAIT_MS });
      await waitRenders(page, 'figure-a', n + 1);
      const id = await page.inputValue('#mesh');
      const status = await page.textContent('#mesh-status');
      check('uploaded mesh selected', status.includes('12 triangles'), `id ${id.slice(0, 12)}..., "${status}"`);
      const link = await page.inputValue('#link');
      check('link renders the uploaded mesh by id', link.includes(`mesh=${id}`), link.slice(0, 120));
      last = await checkImage(page, 'image of the uploaded cube', last);
    });

    await step('glTF upload with the buffer it names', async () => {
      const n = await renders(page, 'figure-a');
      const dir = '/usr/share/assimp/models/glTF2/BoxTextured-glTF';
      await page.setInputFiles('#mesh-file', ['BoxTextured.gltf', 'BoxTextured0.bin'].map((f) => path.join(dir, f)));
      await page.waitForFunction(() => /and 1 more file\(s\): 12 triangles/.test(
        document.getElementById('mesh-status').textContent), null, { timeout: WAIT_MS });
      await waitRenders(page, 'figure-a', n + 1);
      const status = await page.textContent('#mesh-status');
      const option = await page.textContent('#mesh option:checked');
      check('the glTF and its buffer went as one upload, its mesh selected', option.startsWith('BoxTextured.gltf'),
        `"${status}", option "${option}"`);
      last = await checkImage(page, 'image of the uploaded glTF', last);
    });

    await step('two methods side by side', async () => {
      const n = await renders(page, 'figure-a');
      await page.check('#compare');
      await page.selectOption('#method2', 'reference');
      await waitRenders(page, 'figure-a', n + 1);
      await waitRenders(page, 'figure-b', 1);
      const b = pngSize(await imageBytes(page, '#image-b'));
      check('second image (reference) beside the first', b && b.w === SIZE, sizeText(b));
      const accuracy = await page.textContent('#accuracy');
      const m = accuracy.match(/five against reference: relative L2 error ([0-9]+\.[0-9]+)/);
      const expected = relL2(decodePng(await imageBytes(page, '#image-a')), decodePng(await imageBytes(page, '#image-b')));
      check('error against reference shown, as computed here from the PNGs', m && accuracy.includes('8-bit sRGB') &&
        Math.abs(Number(m[1]) - expected) <= 0.02 * expected + 1e-3,
      `page: "${accuracy}"; from the decoded PNGs: ${expected.toFixed(4)}`);
      const shot = path.join(artifacts, 'web_desktop.png');
      await page.screenshot({ path: shot, fullPage: true });
      console.log(`screenshot (desktop, 1280 px): ${shot}`);
      await page.uncheck('#compare');
    });

    await step('path beside reference, with a profile and an exposure', async () => {
      await page.selectOption('#profile', 'asymptotic_dipole');
      await page.fill('#exposure', '1');
      await page.selectOption('#method', 'path');
      await page.check('#compare');
      await page.selectOption('#method2', 'reference');
      await waitShown(page, 'path');
      await page.waitForFunction(() => document.getElementById('status-b').textContent.startsWith('reference, ') &&
        !document.getElementById('figure-b').hasAttribute('aria-busy') &&
        document.getElementById('accuracy').textContent.includes('reference against path'), null, { timeout: WAIT_MS });
      const query = new URL(await page.inputValue('#link')).searchParams;
      check('the link asks for method path with a time budget, the profile and the exposure',
        query.get('method') === 'path' && query.get('path_time_s') === '20' &&
        query.get('profile') === 'asymptotic_dipole' && query.get('exposure') === '1', query.toString());
      const status = await page.textContent('#status-a');
      const modelled = JSON.parse(await page.textContent('#modelled-a'));
      check('path\'s walks and noise shown beside its image', /[0-9]+ walks a pixel, noise [0-9.]+/.test(status) &&
        modelled.method === 'path', status);
      const accuracy = await page.textContent('#accuracy');
      const m = accuracy.match(/reference against path: relative L2 error ([0-9]+\.[0-9]+)/);
      const expected = relL2(decodePng(await imageBytes(page, '#image-b')), decodePng(await imageBytes(page, '#image-a')));
      check('the model (reference) against the walks (path), as computed here from the PNGs',
        m && Math.abs(Number(m[1]) - expected) <= 0.02 * expected + 1e-3,
        `page: "${accuracy}"; from the decoded PNGs: ${expected.toFixed(4)}`);
      await page.uncheck('#compare');
      await page.selectOption('#profile', '');
      await page.fill('#exposure', '0');
      await page.selectOption('#method', 'five');
      await waitShown(page, 'five');
    });

    await step('copy link', async () => {
      await page.click('#copy-link');
      await page.waitForFunction(() => document.getElementById('copy-status').textContent !== '', null,
        { timeout: WAIT_MS });
      const link = await page.inputValue('#link');
      const copyStatus = await page.textContent('#copy-status');
      const viaGet = Buffer.from(await (await fetch(link)).arrayBuffer());
      const shown = await imageBytes(page, '#image-a');
      check('copy-link URL renders the same image by GET', link.startsWith(`${base}/v1/render?`) && viaGet.equals(shown),
        `${copyStatus.trim()} ${viaGet.length} vs ${shown.length} bytes, ${viaGet.equals(shown) ? 'identical' : 'DIFFERENT'}`);
    });

    await step('server error shown', async () => {
      await page.fill('#size', '3000');
      await page.waitForSelector('#error:not([hidden])', { timeout: WAIT_MS });
      const text = await page.textContent('#error');
      const field = await page.textContent('#error .field');
      const invalid = await page.getAttribute('#size', 'aria-invalid');
      check('size 3000: the 413 and its field shown in the page', text.includes('413') && field === 'w' &&
        invalid === 'true', `"${text.trim()}", size aria-invalid=${invalid}`);
      const n = await renders(page, 'figure-a');
      await page.fill('#size', String(SIZE));
      await waitRenders(page, 'figure-a', n + 1);
      check('error cleared by the next good render', await page.isHidden('#error'), `hidden ${await page.isHidden('#error')}`);
    });

    await step('debounce', async () => {
      await observePage(page);
      // Five presses must all land within the debounce to be one request; on a busy machine they may not, and
      // such a try proves nothing, so it is repeated.
      let shown = null;
      for (let attempt = 1; attempt <= TRIES && !shown; attempt++) {
        const n = await renders(page, 'figure-a');
        const before = Number(await page.inputValue('#azimuth'));
        const { gaps, fetches } = await pressAzimuth(page, 5);
        await waitShown(page, 'five');
        const slowest = Math.max(...gaps);
        const measured = `presses ${gaps.join(', ')} ms apart, ${fetches} render request(s), ` +
          `${await renders(page, 'figure-a') - n} image(s) shown`;
        if (slowest < DEBOUNCE_MS) shown = { before, measured, fetches };
        else console.log(`     try ${attempt}: ${measured}; a gap over the ${DEBOUNCE_MS} ms debounce, trying again`);
      }
      if (!shown) throw new Error(`in ${TRIES} tries five key presses never came within ${DEBOUNCE_MS} ms of each other`);
      // The direction the light travels, given relative to the camera: -(sin az right + cos az back) for
      // elevation 0, where back = -camera_dir and right = +Y x back (head-on: -(sin az, 0, cos az)).
      const azimuth = Number(await page.inputValue('#azimuth'));
      const link = await page.inputValue('#link');
      const query = new URL(link).searchParams;
      const back = query.get('camera_dir').split(',').map((x) => -Number(x));
      const right = [back[2], 0, -back[0]].map((x, _, v) => x / Math.hypot(...v));
      const a = (azimuth * Math.PI) / 180;
      const want = [0, 1, 2].map((i) => -(Math.sin(a) * right[i] + Math.cos(a) * back[i]));
      const got = query.get('light_dir').split(',').map(Number);
      const off = Math.max(...want.map((w, i) => Math.abs(w - got[i])));
      check('five quick azimuth steps (keyboard) within the debounce make one request', shown.fetches === 1 &&
        azimuth === shown.before - 5 && off < 2e-3,
      `${shown.measured}; azimuth ${shown.before} -> ${azimuth}, light_dir=${got} (want ` +
      `${want.map((w) => w.toFixed(4))}, off by ${off.toFixed(5)})`);
    });

    await step('supersede', async () => {
      // "five", chosen while a reference render runs, starts a debounce later and must abort it. Whether the
      // reference was still running then is read from the page: its fetch had no response yet when the status
      // line turned to "five: rendering". A reference answered first proves nothing; then the try is repeated
      // on a new scene (so that no cache answers it) with the daemon's one renderer first kept busy by a large
      // render of the test's own, so that the page's reference waits in the queue.
      let verdict = null;
      for (let attempt = 1; attempt <= TRIES && !verdict; attempt++) {
        let blocker = null;
        if (attempt > 1) {
          await pressAzimuth(page, 1);
          await waitShown(page, 'five');
          let answered = 0;
          blocker = fetch(`${base}/v1/render?mesh=protrusion&method=reference&w=256&h=256&light_dir=-1,0,0` +
            `&light_intensity=${attempt}`).then((r) => { answered = r.status; return r.arrayBuffer(); });
          const t0 = Date.now();
          while (await inFlight(base) < 1) {
            if (answered || Date.now() - t0 > WAIT_MS) throw new Error(`the blocking render never ran (status ${answered})`);
            await new Promise((r) => setTimeout(r, 10));
          }
        }
        const n = await renders(page, 'figure-a');
        const from = await page.evaluate(() => [window.lucentTest.renders.length, window.lucentTest.statuses.length]);
        await page.selectOption('#method', 'reference');
        await page.waitForFunction(() => document.getElementById('status-a').textContent.startsWith('reference: '),
          null, { timeout: WAIT_MS });
        await page.selectOption('#method', 'five');
        await waitShown(page, 'five');
        await page.waitForFunction((i) => window.lucentTest.renders.slice(i).every((c) => c.outcome), from[0],
          { timeout: WAIT_MS });
        if (blocker) await blocker;
        const { calls, statuses } = await page.evaluate(([r, st]) => ({
          calls: window.lucentTest.renders.slice(r), statuses: window.lucentTest.statuses.slice(st) }), from);
        const reference = calls.filter((c) => c.url.includes('method=reference')).pop();
        const fiveStarted = statuses.find((x) => x.text.startsWith('five: rendering'));
        const referenceShown = statuses.some((x) => x.text.startsWith('reference, '));
        const shown = await renders(page, 'figure-a') - n;
        const measured = `reference fetch: ${reference.outcome} after ${Math.round(reference.end - reference.start)} ms, ` +
          `five started after ${Math.round(fiveStarted.t - reference.start)} ms; status lines: ` +
          `${statuses.map((x) => x.text.split(':')[0]).join(' | ')}; ${shown} image(s) shown` +
          (blocker ? '; the daemon was busy with a 256x256 reference of the test\'s own' : '');
        if (reference.outcome === 'response' && reference.end < fiveStarted.t) {
          console.log(`     try ${attempt}: ${measured}; answered before five started, trying again`);
        } else {
          verdict = { ok: reference.outcome === 'AbortError' && !referenceShown && shown === 1, measured };
        }
      }
      if (!verdict) throw new Error(`in ${TRIES} tries the reference was always answered before five superseded it`);
      check('a newer request aborts the running one, whose image is never shown', verdict.ok, verdict.measured);
    });

    await step('labels', async () => {
      const unlabelled = await page.$$eval('input, select, button', (els) =>
        els.filter((e) => !(e.labels && e.labels.length) && !e.getAttribute('aria-label') && !e.textContent.trim())
          .map((e) => e.id || e.outerHTML.slice(0, 40)));
      check('every control is labelled', unlabelled.length === 0, unlabelled.length ? unlabelled.join(', ') : 'all labelled');
    });

    await step('embedding with lucent.js', async () => {
      const embed = await context.newPage();
      watch(embed);
      await embed.goto(`${base}/embed-example.html`);
      await embed.waitForFunction(() => [...document.querySelectorAll('img[data-lucent-mesh]')]
        .every((img) => img.complete && (img.naturalWidth > 0 || img.hasAttribute('data-lucent-error'))), null,
      { timeout: WAIT_MS });
      const imgs = await embed.$$eval('img[data-lucent-mesh]', (els) => els.map((e) => [e.src, e.naturalWidth, e.naturalHeight]));
      const good = imgs.filter(([src, w, h]) => src.startsWith(`${base}/v1/render?`) && w === 128 && h === 128);
      check('embed-example.html: every lucent.js image loads', imgs.length === 3 && good.length === 3,
        `${good.length} of ${imgs.length} at 128x128 from ${base}/v1/render`);
      const first = imgs[0][0];
      check('lucent.js builds the README query', first === `${base}/v1/render?mesh=protrusion&preset=skin1&light_dir=-1,0,0` +
        '&light_intensity=4&w=128&h=128', first);
      await embed.close();
    });

    await step('layout at 360 px', async () => {
      const narrow = await browser.newContext({ viewport: { width: 360, height: 740 } });
      const small = await narrow.newPage();
      watch(small);
      await small.goto(`${base}/?size=${SIZE}&compare=single`);
      await waitRenders(small, 'figure-a', 1);
      await waitRenders(small, 'figure-b', 1);
      const overflow = await small.evaluate(() => ({
        scroll: document.documentElement.scrollWidth,
        inner: window.innerWidth,
        wide: [...document.querySelectorAll('body *')].filter((e) => e.getBoundingClientRect().right > window.innerWidth + 0.5)
          .map((e) => e.id || e.tagName).slice(0, 5),
      }));
      check('no horizontal overflow at 360 px', overflow.scroll <= overflow.inner && overflow.wide.length === 0,
        `scrollWidth ${overflow.scroll}, innerWidth ${overflow.inner}, too wide: ${overflow.wide.join(', ') || 'none'}`);
      const shot = path.join(artifacts, 'web_360.png');
      await small.screenshot({ path: shot, fullPage: true });
      console.log(`screenshot (360 px): ${shot}`);
      await narrow.close();
    });

    await step('token', async () => {
      const tokenPath = path.join(work, 'token');
      fs.writeFileSync(tokenPath, 'web-test-token-1234567890');
      const guarded = await startDaemon(work, 'lucentd-token', ['--token-file', tokenPath]);
      try {
        const api = await fetch(`${guarded.base}/v1/materials`);
        const pageResp = await fetch(`${guarded.base}/`);
        check('with --token-file: the page is open, the API is not', pageResp.status === 200 && api.status === 401,
          `GET / ${pageResp.status}, GET /v1/materials ${api.status}`);
        const tokenPage = await context.newPage();
        watch(tokenPage);
        await tokenPage.goto(`${guarded.base}/?size=${SIZE}`);
        await tokenPage.waitForSelector('#error:not([hidden])', { timeout: WAIT_MS });
        const text = await tokenPage.textContent('#error');
        const open = await tokenPage.$eval('#token-box', (d) => d.open);
        check('without the token the 401 is shown and the token field opened', text.includes('401') && open,
          `"${text.trim().slice(0, 120)}...", token box open ${open}`);
        await tokenPage.fill('#token', 'web-test-token-1234567890');
        await tokenPage.press('#token', 'Tab');
        await waitRenders(tokenPage, 'figure-a', 1);
        const natural = await tokenPage.$eval('#image-a', (img) => img.naturalWidth);
        const presets = await tokenPage.$$eval('#preset option', (o) => o.length);
        check('with the token typed in, presets load and the image renders', natural === SIZE && presets > 10,
          `naturalWidth ${natural}, ${presets} preset options, error hidden ${await tokenPage.isHidden('#error')}`);
        await tokenPage.close();
      } finally {
        const code = await stopDaemon(guarded.child);
        check('token lucentd stopped cleanly', code === 0, `exit ${code}`);
      }
    });

    check('no request left the daemon', external.length === 0, external.length ? external.join(', ') : 'none');
    check('no uncaught script errors', pageErrors.length === 0, pageErrors.length ? pageErrors.join('; ') : 'none');
  } finally {
    await browser.close();
    const code = await stopDaemon(daemon.child);
    check('lucentd stopped cleanly', code === 0, `exit ${code}`);
    if (failed) console.log(fs.readFileSync(daemon.logPath, 'utf8').split('\n').slice(-30).join('\n'));
    fs.rmSync(work, { recursive: true, force: true });
  }
}

main().then(() => {
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}, (e) => {
  console.log(`FAIL ${e.stack || e}`);
  console.log(`${passed} passed, ${failed + 1} failed`);
  process.exit(1);
});
