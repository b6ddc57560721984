// Latency through the browser viewer (docs/perf.md "Browser and Slicer bridges"): starts
// polycut-server and polycut-web, opens the viewer in headless Chromium, sends N apply_force
// requests at RATE Hz from the page and measures, in the page, request -> the first stream frame
// listing its id in `applied` (command to visible) and N get_stats round trips; then runs
// polycut-bench (direct ZeroMQ) against the same server for the same figures. Prints JSON.
//   POLYCUT_NODE_MODULES=build/release/clients/web/npm/node_modules \
//     node scripts/web_latency.js build/release [N] [RATE]
'use strict';
const { spawn, execFileSync } = require('child_process');
const fs = require('fs');
const os = require('os');
const path = require('path');
const readline = require('readline');

const [build, nArg, rateArg] = process.argv.slice(2);
const N = Number(nArg || 200), RATE = Number(rateArg || 20);
const { chromium } = require(path.join(process.env.POLYCUT_NODE_MODULES, 'playwright-core'));

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

(async () => {
  const root = path.resolve(__dirname, '..');
  const scene = path.join(root, 'assets', 'scenes', 'default.json');
  const server = await start(path.join(build, 'server', 'polycut-server'),
    ['--scene', scene, '--control', 'tcp://127.0.0.1:*', '--stream', 'tcp://127.0.0.1:*', '--quiet']);
  const web = await start(path.join(build, 'clients', 'web', 'polycut-web'),
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
  web.child.kill('SIGTERM');
  const bench = JSON.parse(execFileSync(path.join(build, 'clients', 'bench', 'polycut-bench'),
    ['--server', server.info.control, '--duration', String(N / RATE), '--rate', String(RATE), '--quiet']).toString());
  server.child.kill('SIGTERM');
  fs.rmSync(tmp, { recursive: true, force: true });
  console.log(JSON.stringify({
    requests: N, rate_hz: RATE,
    browser_command_to_visible_ms: summary(browser.visible), browser_get_stats_rtt_ms: summary(browser.rtt),
    zmq_command_to_visible_ms: bench.command_to_visible_ms, zmq_control_rtt_ms: bench.control_rtt_ms,
    load_average_1min: bench.machine.load_average_1min,
  }, null, 1));
})();
