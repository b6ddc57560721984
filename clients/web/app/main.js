// polycut viewer: wires the connection (protocol + Clone mirror), the 3D view and the mouse
// tools to the page, and shows the figures. window.polycut exposes the state for scripts and
// the browser test.
import { Connection } from './connection.js';
import { Tools } from './tools.js';
import { View } from './view.js';

const $ = (id) => document.getElementById(id);
const view = new View($('view'));
let frames = 0, lastFpsAt = performance.now(), fps = 0, lastError = '';

function status(text, kind) {
  const el = $('status');
  el.textContent = text;
  el.className = `status ${kind || ''}`;
}

const connection = new Connection(`ws://${location.host}/ws`, {
  onStatus: status,
  onSurface(mirror, header, topologyChanged) {
    const firstOfScene = !view.geometry.getAttribute('position') || header.tick === 0;
    view.setSurface(mirror, topologyChanged);
    if (firstOfScene && topologyChanged) view.frame();
    frames++;
    status('live', 'live');
    show(mirror);
  },
  onScene: showScene,
  onEvent(event) {
    if (event.kind === 'scene') showScene(event.detail.name);
    if (event.kind === 'rejected' || event.kind === 'warning') {
      lastError = `${event.kind}: ${event.detail.reason || event.detail.message || ''}`;
    }
  },
});

/** The current scene's name, also selected in the list when it is there. */
function showScene(name) {
  $('f-scene').textContent = name;
  if ([...$('scenes').options].some((o) => o.value === name)) $('scenes').value = name;
}

function show(m) {
  $('f-tick').textContent = m.tick;
  $('f-time').textContent = `${(m.sim_time ?? 0).toFixed(3)} s`;
  $('f-seq').textContent = m.seq;
  $('f-step').textContent = m.step ? `${m.step.step_ms.toFixed(2)} ms, ${m.step.solver_iterations} it` : '-';
  $('f-surface').textContent = `${m.vertex_count} vertices, ${m.triangle_count} triangles, topology ${m.topology_version}`;
  $('f-resyncs').textContent = connection.resyncs;
  $('f-latency').textContent = connection.latencyMs === null ? '-' : `${connection.latencyMs.toFixed(1)} ms`;
}

setInterval(() => {
  const now = performance.now();
  fps = (frames * 1000) / (now - lastFpsAt);
  frames = 0;
  lastFpsAt = now;
  $('f-fps').textContent = `${fps.toFixed(1)} /s`;
}, 1000);

const settings = {
  depthM: () => Math.min(0.2, Math.max(0.001, Number($('depth').value) / 1000)),
  stiffness: () => Math.min(1e5, Math.max(1, Number($('stiffness').value))),
  report: (text) => { lastError = text; status(text, 'down'); },
};
const tools = new Tools(view, connection, settings);

async function loadSceneList() {
  const res = await fetch('/api/scenes');
  const { scenes } = await res.json();
  $('scenes').replaceChildren(...scenes.map((name) => new Option(name, name)));
}
loadSceneList().then(() => showScene($('f-scene').textContent)).catch(() => {});
$('load').onclick = () => connection.request('load_scene', { name: $('scenes').value })
  .then(({ result }) => showScene(result.name))
  .catch((err) => settings.report(`load: ${err.data ? err.data.reason : err.message}`));
$('reset').onclick = () => connection.request('reset').catch(() => {});

window.polycut = {
  view, connection, tools,
  state: () => ({
    ready: connection.ready,
    seq: connection.mirror ? connection.mirror.seq : null,
    tick: connection.mirror ? connection.mirror.tick : null,
    topology_version: connection.mirror ? connection.mirror.topology_version : null,
    triangle_count: connection.mirror ? connection.mirror.triangle_count : null,
    cut_triangles: connection.mirror ? connection.mirror.tags.reduce((n, t) => n + (t === 2 ? 1 : 0), 0) : 0,
    resyncs: connection.resyncs,
    latency_ms: connection.latencyMs,
    last_error: lastError,
  }),
  pixels: () => view.pixelStats(),
  request: (method, params) => connection.request(method, params).then((r) => r.result),
  /** The page coordinates of a world point [m] (for scripted mouse input). */
  toScreen: (x, y, z) => {
    const v = new view.camera.position.constructor(x, y, z).project(view.camera);
    const r = view.renderer.domElement.getBoundingClientRect();
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  },
};
