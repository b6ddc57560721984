// Latency through the browser viewer (docs/perf.md "Browser and Slicer bridges"): starts
// polycut-server and polycut-web, opens the viewer in headless Chromium, sends N apply_force
// requests at RATE Hz from the page and measures, in the page, request -> the first stream frame
// listing its id in `applied` (command to visible) and N get_stats round trips; then runs
// polycut-bench (direct ZeroMQ) against the same server for the same figures; and, when Node has
// a WebSocket client (Node 22, or Node 20 with --experimental-websocket), N get_stats round trips
// through the bridge without a browser. Prints JSON.
//   POLYCUT_NODE_MODULES=build/release/clients/web/npm/node_modules \
//     node --experimental-websocket scripts/web_latency.js build/release [N] [RATE]
'use strict';
const { spawn, execFileSync } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const readline = require('readline');

const [build, nArg, rateArg] = process.argv.slice(2);
const N = Number(nArg || 200), RATE = Number(rateArg || 20);
const { chromium } = require(path.resolve(process.env.POLYCUT_NODE_MODULES, 'playwright-core'));

function start(exe, args) {
  const child = spawn(exe, args, { stdio: ['ignore', 'pipe', 'ignore'] });
  return new Promise((resolve) => {
    readline.createInterface({ input: child.stdout }).once('line', (l) => resolve({ child, info: JSON.parse(l) }));
  });
}

function summary(v) {
  const s = [...v].sort((a, b) => a - b);
  const q = (p) => s[Math.min(s.length - 1, Math.floor(p * (s.length - 1) + 0.5))];
  return { count: s.length, p50: +q(0.5).toFixed(2), p99: +q(0.99).toFixed(2), max: +s[s.length - 1].toFixed(2) };
}

/** get_stats round trips through the bridge from Node (no browser, no rendering) [ms]. */
function bridgeRtt(port, n, rate) {
  return new Promise((resolve) => {
    const ws = new WebSocket(`ws://127.0.0.1:${port}/ws`);
    ws.binaryType = 'arraybuffer';
    const rtt = [];
    let t0 = 0, id = 0;
    const send = () => { t0 = performance.now(); ws.send(JSON.stringify({ jsonrpc: '2.0', id: ++id, method: 'get_stats' })); };
    ws.onmessage = (e) => {
      if (typeof e.data === 'string') { if (JSON.parse(e.data).bridge === 'ready') send(); return; }
      const v = new DataView(e.data);
      const first = new TextDecoder().decode(new Uint8Array(e.data, 4 + 4 * v.getUint32(0, true), v.getUint32(4, true)));
      if (first === 'surface' || first === 'event') return;
      rtt.push(performance.now() - t0);
      if (rtt.length < n) setTimeout(send, 1000 / rate); else { ws.close(); resolve(rtt); }
    };
  });
}

(async () => {
  const root = path.resolve(__dirname, '..');
  const scene = path.join(root, 'assets', 'scenes', 'default.json');
  const server = await start(path.resolve(build, 'server', 'polycut-server'),
    ['--scene', scene, '--control', 'tcp://127.0.0.1:*', '--stream', 'tcp://127.0.0.1:*', '--quiet']);
  const web = await start(path.resolve(build, 'clients', 'web', 'polycut-web'),
    ['--server', server.info.control, '--http', '127.0.0.1:0', '--quiet']);
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'polycut-latency-'));
  const context = await chromium.launchPersistentContext(path.join(tmp, 'profile'), {
    executablePath: '/usr/bin/chromium', headless: true, viewport: { width: 800, height: 600 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = context.pages()[0] || await context.newPage();
  await page.goto(web.info.url);
  await page.waitForFunction(() => window.polycut && window.polycut.state().seq !== null, null, { timeout: 30000 });
  const browser = await page.evaluate(async ([n, rate]) => {
    const c = window.polycut.connection;
    c.latencies = [];
    const rtt = [];
    for (let k = 0; k < n; k++) {
      c.request('apply_force', { point: [0, 0, 0.05], force: [0, 0, -0.02], radius: 0.01, duration: 0.1 }).catch(() => {});
      const t0 = performance.now();
      await c.request('get_stats');
      rtt.push(performance.now() - t0);
      await new Promise((r) => setTimeout(r, 1000 / rate));
    }
    await new Promise((r) => setTimeout(r, 500));
    return { visible: c.latencies, rtt };
  }, [N, RATE]);
  await context.close();
  const bridge = typeof WebSocket === 'undefined' ? null : await bridgeRtt(web.info.port, N, RATE);
  web.child.kill('SIGTERM');
  const bench = JSON.parse(execFileSync(path.resolve(build, 'clients', 'bench', 'polycut-bench'),
    ['--server', server.info.control, '--duration', String(N / RATE), '--rate', String(RATE), '--quiet']).toString());
  server.child.kill('SIGTERM');
  fs.rmSync(tmp, { recursive: true, force: true });
  console.log(JSON.stringify({
    requests: N, rate_hz: RATE,
    browser_command_to_visible_ms: summary(browser.visible), browser_get_stats_rtt_ms: summary(browser.rtt),
    bridge_get_stats_rtt_ms: bridge ? summary(bridge) : 'needs a WebSocket client in Node',
    zmq_command_to_visible_ms: bench.command_to_visible_ms, zmq_control_rtt_ms: bench.control_rtt_ms,
    load_average_1min: bench.machine.load_average_1min,
  }, null, 1));
})();
