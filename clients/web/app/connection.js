// The viewer's link to polycut-server through polycut-web: JSON-RPC requests as WebSocket text,
// replies and stream messages as frame envelopes (docs/viewer.md "Wire"), and the surface mirror
// kept by the Clone pattern of docs/protocol.md: subscribe (the bridge does, then says "ready"),
// snapshot with get_surface, apply later frames in seq order, and fetch a new snapshot on any
// gap, on a topology change without arrays, or when the server restarted.

const decoder = new TextDecoder();
const REQUEST_TIMEOUT_MS = 3000;
const WATCHDOG_MS = 1500;

/** Splits an envelope (uint32 count, count x uint32 sizes, frames) into ArrayBuffer frames. */
export function unpackFrames(buffer) {
  const view = new DataView(buffer);
  const count = view.getUint32(0, true);
  const frames = [];
  let at = 4 + 4 * count;
  for (let i = 0; i < count; i++) {
    const size = view.getUint32(4 + 4 * i, true);
    frames.push(buffer.slice(at, at + size));
    at += size;
  }
  return frames;
}

/** A binary array of a message: `ref` is {"$frame", "dtype", "shape"}, `frames` counted from
 * the JSON frame (frames[0] is the JSON itself). */
function array(ref, frames) {
  const data = frames[ref.$frame];
  if (ref.dtype === 'float32') return new Float32Array(data);
  if (ref.dtype === 'uint32') return new Uint32Array(data);
  return new Uint8Array(data);
}

export class Connection {
  /**
   * @param {string} url the bridge's WebSocket URL (ws://host:port/ws)
   * @param {object} handlers onStatus(text, kind), onSurface(mirror, frameHeader), onEvent(event)
   */
  constructor(url, handlers) {
    this.url = url;
    this.handlers = handlers;
    this.nextId = 1;
    this.pending = new Map(); // id -> {resolve, reject, timer, sent, method}
    this.awaitingFrame = new Map(); // id -> sent time [ms], for command-to-visible latency
    this.mirror = null; // {positions, triangles, tags, seq, tick, topology_version, ...}
    this.syncing = false;
    this.buffered = [];
    this.lastFrameAt = 0;
    this.resyncs = 0;
    this.latencyMs = null;
    this.latencies = []; // the last 1000 command-to-visible latencies [ms]
    this.ready = false;
    this.open();
    setInterval(() => this.watchdog(), WATCHDOG_MS);
  }

  open() {
    this.ws = new WebSocket(this.url);
    this.ws.binaryType = 'arraybuffer';
    this.ws.onmessage = (e) => this.onMessage(e.data);
    this.ws.onclose = () => {
      this.ready = false;
      this.handlers.onStatus('bridge closed, retrying', 'down');
      this.failPending('connection closed');
      setTimeout(() => this.open(), 500);
    };
  }

  /** Sends a request; resolves with its result, rejects with its error object. */
  request(method, params = {}) {
    const id = this.nextId++;
    const sent = performance.now();
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => {
        this.pending.delete(id);
        reject({ code: 'timeout', message: `${method}: no reply in ${REQUEST_TIMEOUT_MS} ms` });
      }, REQUEST_TIMEOUT_MS);
      this.pending.set(id, { resolve, reject, timer, sent, method });
      if (method !== 'get_surface' && method !== 'get_stats' && method !== 'hello') {
        this.awaitingFrame.set(id, sent);
      }
      this.send({ jsonrpc: '2.0', id, method, params });
    });
  }

  /** Sends a notification (no reply), e.g. scalpel samples at the mouse's rate. */
  notify(method, params) {
    this.send({ jsonrpc: '2.0', method, params });
  }

  send(message) {
    if (this.ws.readyState === WebSocket.OPEN) this.ws.send(JSON.stringify(message));
  }

  failPending(reason) {
    for (const [id, p] of this.pending) {
      clearTimeout(p.timer);
      p.reject({ code: 'closed', message: reason });
    }
    this.pending.clear();
  }

  onMessage(data) {
    if (typeof data === 'string') return this.onBridgeStatus(JSON.parse(data));
    const frames = unpackFrames(data);
    const first = decoder.decode(frames[0]);
    if (first === 'surface') return this.onSurfaceFrame(JSON.parse(decoder.decode(frames[1])), frames.slice(1));
    if (first === 'event') return this.handlers.onEvent(JSON.parse(decoder.decode(frames[1])));
    this.onReply(JSON.parse(first), frames);
  }

  onBridgeStatus(status) {
    if (status.bridge === 'ready') {
      this.ready = true;
      this.handlers.onStatus('live', 'live');
      if (status.scene && this.handlers.onScene) this.handlers.onScene(status.scene);
      this.resync();
    } else if (status.bridge === 'waiting') {
      this.handlers.onStatus('waiting for the server', 'down');
    } else {
      this.handlers.onStatus(`bridge: ${status.reason || status.bridge}`, 'down');
    }
  }

  onReply(reply, frames) {
    const p = this.pending.get(reply.id);
    if (!p) return;
    clearTimeout(p.timer);
    this.pending.delete(reply.id);
    if (reply.error) {
      this.awaitingFrame.delete(reply.id);
      p.reject(reply.error);
    } else {
      p.resolve({ result: reply.result, frames });
    }
  }

  /** Clone pattern, step 2-3: snapshot, then the buffered frames after it. */
  async resync() {
    if (this.syncing) return;
    this.syncing = true;
    this.buffered = [];
    this.resyncs++;
    for (;;) {
      try {
        const { result, frames } = await this.request('get_surface');
        const mirror = {
          ...result,
          positions: array(result.positions, frames),
          triangles: array(result.triangles, frames),
          tags: array(result.tags, frames),
        };
        this.mirror = mirror;
        this.handlers.onSurface(mirror, result, true);
        const later = this.buffered.filter((f) => f.header.seq > mirror.seq);
        this.buffered = [];
        this.syncing = false;
        for (const f of later) this.apply(f.header, f.frames);
        return;
      } catch (e) {
        if (!this.ready) { this.syncing = false; return; }
        await new Promise((r) => setTimeout(r, 300));
      }
    }
  }

  onSurfaceFrame(header, frames) {
    this.lastFrameAt = performance.now();
    for (const id of header.applied || []) {
      const sent = this.awaitingFrame.get(id);
      if (sent !== undefined) {
        this.latencyMs = this.lastFrameAt - sent;
        this.latencies.push(this.latencyMs);
        if (this.latencies.length > 1000) this.latencies.shift();
        this.awaitingFrame.delete(id);
      }
    }
    if (this.syncing || !this.mirror) {
      this.buffered.push({ header, frames });
      if (!this.syncing && this.ready) this.resync();
      return;
    }
    this.apply(header, frames);
  }

  /** Clone pattern, step 4: a frame must follow the last one and carry any new topology. */
  apply(header, frames) {
    const m = this.mirror;
    const continuous = header.seq === m.seq + 1;
    const topologyKnown = header.has_topology || header.topology_version === m.topology_version;
    if (!continuous || !topologyKnown) {
      this.buffered.push({ header, frames });
      this.resync();
      return;
    }
    m.positions = array(header.positions, frames);
    if (header.has_topology) {
      m.triangles = array(header.triangles, frames);
      m.tags = array(header.tags, frames);
    }
    for (const k of ['seq', 'tick', 'sim_time', 'topology_version', 'vertex_count', 'triangle_count', 'step', 'cut_deferred']) {
      m[k] = header[k];
    }
    this.handlers.onSurface(m, header, header.has_topology);
  }

  /** No frame for a while: a paused server, or one that restarted (its seq starts over). */
  async watchdog() {
    if (!this.ready || this.syncing) return;
    if (performance.now() - this.lastFrameAt < WATCHDOG_MS) return;
    try {
      const { result } = await this.request('get_stats');
      if (!this.mirror || result.seq !== this.mirror.seq) this.resync();
    } catch (e) {
      this.handlers.onStatus('server not answering', 'down');
    }
  }
}
