// The browser viewer in headless Chromium (issue 16 item 1), driven by playwright-core:
//   node browser_test.js POLYCUT_SERVER POLYCUT_WEB DIR_WITH_sag.json
// 1. the page connects through polycut-web and shows a non-empty canvas;
// 2. its pixels change when the tissue sags (paused server: reset, then 30 steps);
// 3. a right drag grabs (the server counts one grab while the button is held, none after);
// 4. a scripted left drag across the slab cuts: the server's topology_version grows, the mirror
//    holds cut triangles and the page shows cut-coloured pixels;
// 5. a killed and restarted server is reconnected: frames flow again and the new (uncut)
//    surface is shown.
// Prints "N passed, M failed"; exit status 1 on any failure.
'use strict';
const { spawn } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const readline = require('readline');

const [serverExe, webExe, assetDir] = process.argv.slice(2);
const { chromium } = require(path.join(process.env.POLYCUT_NODE_MODULES, 'playwright-core'));

let passed = 0, failed = 0;
function check(ok, what, detail = '') {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ': ' + detail : ''}`);
}

/** Starts a process and resolves with it and its first stdout line parsed as JSON. */
function start(exe, args) {
  const child = spawn(exe, args, { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    const lines = readline.createInterface({ input: child.stdout });
    const timer = setTimeout(() => reject(new Error(`${exe}: no first line in 60 s`)), 60000);
    lines.once('line', (line) => { clearTimeout(timer); resolve({ child, info: JSON.parse(line) }); });
    child.once('exit', (code) => reject(new Error(`${exe} exited with ${code}`)));
  });
}

async function until(what, fn, timeoutMs = 20000) {
  const t0 = Date.now();
  for (;;) {
    const v = await fn();
    if (v) return v;
    if (Date.now() - t0 > timeoutMs) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 100));
  }
}

async function main() {
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'polycut-browser-'));
  const sceneDir = path.join(tmp, 'scenes');
  fs.mkdirSync(sceneDir);
  fs.copyFileSync(path.join(assetDir, 'sag.json'), path.join(sceneDir, 'sag.json'));
  const serverArgs = (control, stream) => ['--scene', path.join(sceneDir, 'sag.json'), '--scene-dir', sceneDir,
    '--control', control, '--stream', stream, '--quiet'];
  let server = await start(serverExe, serverArgs('tcp://127.0.0.1:*', 'tcp://127.0.0.1:*'));
  const { control, stream } = server.info;
  const web = await start(webExe, ['--server', control, '--http', '127.0.0.1:0', '--scene-dir', sceneDir, '--quiet']);
  const context = await chromium.launchPersistentContext(path.join(tmp, 'profile'), {
    executablePath: '/usr/bin/chromium',
    headless: true,
    viewport: { width: 800, height: 600 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = context.pages()[0] || await context.newPage();
  page.on('pageerror', (e) => console.log('page error:', e.message));
  try {
    await page.goto(web.info.url);
    const state = () => page.evaluate(() => window.polycut && window.polycut.state());
    const pixels = () => page.evaluate(() => window.polycut.pixels());
    const request = (method, params = {}) => page.evaluate(([m, p]) => window.polycut.request(m, p), [method, params]);

    // 1. Connected, a surface, a non-empty canvas.
    await until('the first surface', async () => { const s = await state(); return s && s.ready && s.seq !== null; });
    const scenes = await page.evaluate(() => Array.from(document.querySelectorAll('#scenes option'), (o) => o.value));
    check(scenes.includes('sag'), 'the scene list comes from the server\'s scene directory', scenes.join(','));

    // 2. Sagging: paused at rest, then 30 ticks.
    await request('pause');
    await request('reset');
    await until('the rest pose', async () => (await state()).tick === 0);
    await new Promise((r) => setTimeout(r, 300)); // a render after the frame
    const rest = await pixels();
    if (process.env.POLYCUT_SCREENSHOT_DIR) {
      await page.screenshot({ path: path.join(process.env.POLYCUT_SCREENSHOT_DIR, 'browser_rest.png') });
    }
    check(rest.tissue > 0.02 * rest.width * rest.height, 'non-empty canvas',
      `${rest.tissue} of ${rest.width * rest.height} pixels show tissue`);
    await request('step', { ticks: 30 });
    await until('tick 30', async () => (await state()).tick === 30);
    await new Promise((r) => setTimeout(r, 300));
    const sagged = await pixels();
    const change = sagged.grid.reduce((s, v, k) => s + Math.abs(v - rest.grid[k]), 0) / rest.grid.length;
    check(change > 1.0, 'the pixels change as the tissue sags', `mean |luminance change| ${change.toFixed(2)} of 255 over a 32 x 24 grid`);
    await request('resume');

    // 3. Grab: right drag on the slab's free end.
    await page.evaluate(() => window.polycut.view.frame());
    await new Promise((r) => setTimeout(r, 300));
    const bbox = await page.evaluate(() => {
      const b = window.polycut.view.geometry.boundingBox;
      return { min: b.min.toArray(), max: b.max.toArray() };
    });
    const screen = (p) => page.evaluate(([x, y, z]) => window.polycut.toScreen(x, y, z), p);
    // The slab's top near its free end, wherever the sag put it: the first point down from the
    // bounding box's top that the mouse would hit.
    const tip = await page.evaluate(([x, zTop, zBottom]) => {
      for (let k = 0; k <= 50; k++) {
        const p = window.polycut.toScreen(x, 0, zTop - ((zTop - zBottom) * k) / 50);
        if (window.polycut.view.pick(p.x, p.y)) return p;
      }
      return null;
    }, [0.8 * bbox.max[0], bbox.max[2], bbox.min[2]]);
    check(tip !== null, 'the slab\'s free end is under the mouse');
    await page.mouse.move(tip.x, tip.y);
    await page.mouse.down({ button: 'right' });
    for (let k = 1; k <= 5; k++) await page.mouse.move(tip.x, tip.y - 8 * k);
    const held = await until('the grab', async () => (await request('get_stats')).grabs === 1 || null, 5000).catch(() => false);
    check(held, 'a right drag grabs the tissue (server: 1 grab)');
    await page.mouse.up({ button: 'right' });
    const released = await until('the release', async () => (await request('get_stats')).grabs === 0, 5000).catch(() => false);
    check(released, 'releasing the button releases the grab (server: 0 grabs)');

    // 4. Cut: seen from above, a left drag across the slab at 40 % of its length with the blade
    //    15 mm deep into the 20 mm slab: the sagging cantilever's top is in tension, so the cut
    //    opens and its faces show from above.
    await page.fill('#depth', '15');
    await page.evaluate(() => window.polycut.view.frame([0, -0.05, 1]));
    await new Promise((r) => setTimeout(r, 300));
    const before = await request('get_stats');
    const top = await page.evaluate(() => {
      const b = window.polycut.view.geometry.boundingBox;
      return { min: b.min.toArray(), max: b.max.toArray() };
    });
    const x = top.min[0] + 0.4 * (top.max[0] - top.min[0]);
    const width = top.max[1] - top.min[1];
    const from = await screen([x, top.min[1] + 0.05 * width, top.max[2]]);
    const to = await screen([x, top.max[1] + 0.3 * width, top.max[2]]);
    const onTissue = await page.evaluate(([px, py]) => !!window.polycut.view.pick(px, py), [from.x, from.y]);
    check(onTissue, 'the drag starts on the tissue');
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    for (let k = 1; k <= 30; k++) {
      await page.mouse.move(from.x + ((to.x - from.x) * k) / 30, from.y + ((to.y - from.y) * k) / 30);
      await new Promise((r) => setTimeout(r, 16)); // the mouse's rate, about 60 Hz
    }
    await page.mouse.up();
    const after = await until('the cut', async () => {
      const s = await request('get_stats');
      return s.topology_version > before.topology_version ? s : null;
    }, 10000).catch(() => null);
    // Let the stroke finish (end_stroke, deferred triangles): the topology stops changing.
    let settled = after ? after.topology_version : 0;
    for (let quiet = 0; quiet < 5;) {
      await new Promise((r) => setTimeout(r, 200));
      const v = (await request('get_stats')).topology_version;
      quiet = v === settled ? quiet + 1 : 0;
      settled = v;
    }
    const final = await request('get_stats');
    check(after !== null, 'the drag changes the server\'s topology',
      after ? `topology_version ${before.topology_version} -> ${final.topology_version}, ${before.triangle_count} -> ${final.triangle_count} triangles` : 'unchanged');
    const mirrored = await until('cut triangles in the mirror', async () => (await state()).cut_triangles > 0, 5000).catch(() => false);
    check(mirrored, 'the page\'s mirror holds cut triangles', JSON.stringify(await state()));
    await page.evaluate(() => window.polycut.view.frame([0.35, -0.6, 1]));
    await new Promise((r) => setTimeout(r, 400));
    const cutPixels = await pixels();
    check(cutPixels.cut > 200 && cutPixels.cut > 5 * rest.cut, 'cut-coloured pixels on the page',
      `${cutPixels.cut} (before the cut ${rest.cut})`);
    if (process.env.POLYCUT_SCREENSHOT_DIR) {
      await page.screenshot({ path: path.join(process.env.POLYCUT_SCREENSHOT_DIR, 'browser_cut.png') });
    }

    // 5. Kill the server, start it again on the same endpoints: the page follows.
    server.child.kill('SIGKILL');
    await new Promise((r) => setTimeout(r, 1500));
    const seqBefore = (await state()).seq;
    server = await start(serverExe, serverArgs(control, stream));
    const back = await until('frames from the restarted server', async () => {
      const s = await state();
      return s.ready && s.seq !== seqBefore && s.cut_triangles === 0 && s.tick !== null ? s : null;
    }, 30000).catch(() => null);
    check(back !== null, 'a killed and restarted server is reconnected', back ? `resyncs ${back.resyncs}, seq ${seqBefore} -> ${back.seq}` : JSON.stringify(await state()));
    await new Promise((r) => setTimeout(r, 400));
    const again = await pixels();
    check(again.tissue > 0.02 * again.width * again.height && again.cut < cutPixels.cut / 5,
      'the restarted server\'s uncut surface is shown', `${again.tissue} tissue, ${again.cut} cut pixels`);
    if (process.env.POLYCUT_SCREENSHOT_DIR) {
      await page.screenshot({ path: path.join(process.env.POLYCUT_SCREENSHOT_DIR, 'browser_restarted.png') });
    }
  } catch (e) {
    check(false, 'the test ran to the end', e.message);
  } finally {
    await context.close();
    web.child.kill('SIGTERM');
    server.child.kill('SIGTERM');
    fs.rmSync(tmp, { recursive: true, force: true });
  }
  console.log(`${passed} passed, ${failed} failed`);
  process.exit(failed ? 1 : 0);
}

main().catch((e) => { console.log('FAIL', e.message); console.log(`${passed} passed, ${failed + 1} failed`); process.exit(1); });
