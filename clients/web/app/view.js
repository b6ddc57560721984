// The 3D view: the streamed surface (skin and cut triangles in two colours, flat shaded), the
// blade and the grab handles, an orbit camera. Positions are updated in place every frame;
// triangles are re-sorted by tag only when the topology changes.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

export const SKIN_COLOUR = 0xe8b49a; // pale tissue
export const CUT_COLOUR = 0xb0141e; // dark red: the inside of the tissue
export const BACKGROUND = 0x20242a;

export class View {
  constructor(canvas) {
    // preserveDrawingBuffer: the page's pixels can be read back (the browser test does).
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
    this.camera = new THREE.PerspectiveCamera(40, 1, 1e-4, 100);
    this.camera.up.set(0, 0, 1); // the scenes' gravity is -z
    this.camera.position.set(0.25, -0.3, 0.25);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.mouseButtons = { LEFT: THREE.MOUSE.ROTATE, MIDDLE: THREE.MOUSE.PAN, RIGHT: null };
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(1, -1, 2);
    this.camera.add(sun); // light from the viewer's side: every visible face is lit
    this.scene.add(this.camera);

    this.geometry = new THREE.BufferGeometry();
    const materials = [SKIN_COLOUR, CUT_COLOUR].map(
      (c) => new THREE.MeshPhongMaterial({ color: c, flatShading: true, side: THREE.DoubleSide, shininess: 20 }));
    this.mesh = new THREE.Mesh(this.geometry, materials);
    this.mesh.frustumCulled = false;
    this.scene.add(this.mesh);

    const bladeGeometry = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]);
    this.blade = new THREE.Line(bladeGeometry, new THREE.LineBasicMaterial({ color: 0xf2f2f2 }));
    this.blade.visible = false;
    this.scene.add(this.blade);
    this.grabs = new Map(); // id -> {handle, line}
    this.size = 0.1; // tissue diagonal [m], for handle sizes
    this.dirty = true;
    this.onResize();
    window.addEventListener('resize', () => this.onResize());
    this.controls.addEventListener('change', () => { this.dirty = true; });
    const loop = () => {
      if (this.dirty) {
        this.renderer.render(this.scene, this.camera);
        this.dirty = false;
      }
      requestAnimationFrame(loop);
    };
    loop();
  }

  onResize() {
    const w = window.innerWidth, h = window.innerHeight;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  /** Shows a surface: positions (V x 3 float32 [m]), triangles (T x 3 uint32), tags (T uint8). */
  setSurface(mirror, topologyChanged) {
    const g = this.geometry;
    const pos = g.getAttribute('position');
    if (!pos || pos.array.length !== mirror.positions.length) {
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(mirror.positions), 3).setUsage(THREE.DynamicDrawUsage));
      topologyChanged = true;
    } else {
      pos.array.set(mirror.positions);
      pos.needsUpdate = true;
    }
    if (topologyChanged) {
      // Skin triangles first, then cut ones: one draw group per material.
      const t = mirror.triangles, tags = mirror.tags, n = tags.length;
      const index = new Uint32Array(3 * n);
      let at = 0;
      for (const want of [1, 2]) {
        for (let k = 0; k < n; k++) {
          if ((tags[k] === 2 ? 2 : 1) !== want) continue;
          index[at++] = t[3 * k]; index[at++] = t[3 * k + 1]; index[at++] = t[3 * k + 2];
        }
        if (want === 1) this.skinCount = at;
      }
      g.setIndex(new THREE.BufferAttribute(index, 1));
      g.clearGroups();
      g.addGroup(0, this.skinCount, 0);
      g.addGroup(this.skinCount, 3 * n - this.skinCount, 1);
    }
    g.computeBoundingSphere();
    g.computeBoundingBox();
    this.dirty = true;
  }

  /** Points the camera at the surface (after a scene load), looking from `direction` (a world
   * vector from the surface's centre towards the camera). */
  frame(direction = [0.9, -1.2, 0.9]) {
    const box = this.geometry.boundingBox;
    if (!box) return;
    const centre = box.getCenter(new THREE.Vector3());
    this.size = box.getSize(new THREE.Vector3()).length();
    this.controls.target.copy(centre);
    const away = new THREE.Vector3(...direction).normalize().multiplyScalar(1.7 * this.size);
    this.camera.position.copy(centre).add(away);
    this.camera.near = this.size * 0.01;
    this.camera.far = this.size * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.dirty = true;
  }

  /** The blade segment [m], or null to hide it. */
  setBlade(a, b) {
    this.blade.visible = !!a;
    if (a) {
      this.blade.geometry.setFromPoints([a, b]);
      this.blade.geometry.computeBoundingSphere();
    }
    this.dirty = true;
  }

  /** A grab handle at `anchor` pulling material at `point`; null anchor removes it. */
  setGrab(id, point, anchor) {
    let g = this.grabs.get(id);
    if (!anchor) {
      if (g) { this.scene.remove(g.handle, g.line); this.grabs.delete(id); }
      this.dirty = true;
      return;
    }
    if (!g) {
      const handle = new THREE.Mesh(new THREE.SphereGeometry(this.size * 0.012, 12, 8),
        new THREE.MeshBasicMaterial({ color: 0x3fa7ff }));
      const line = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x3fa7ff }));
      g = { handle, line };
      this.grabs.set(id, g);
      this.scene.add(handle, line);
    }
    g.handle.position.copy(anchor);
    g.line.geometry.setFromPoints([point, anchor]);
    this.dirty = true;
  }

  /** The first surface point under the pixel (clientX, clientY), or null. */
  pick(clientX, clientY) {
    const ray = this.ray(clientX, clientY);
    const hit = ray.intersectObject(this.mesh, false)[0];
    return hit ? hit.point : null;
  }

  ray(clientX, clientY) {
    const r = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    const caster = new THREE.Raycaster();
    caster.setFromCamera(ndc, this.camera);
    return caster;
  }

  /** Pixel figures of the canvas for the browser test: pixels unlike the background, pixels of
   * the cut colour's hue, and a 32 x 24 grid of mean luminance. */
  pixelStats() {
    const src = this.renderer.domElement;
    const c = document.createElement('canvas');
    c.width = src.width; c.height = src.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(src, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    // The background's sRGB bytes (a THREE.Color would hold it in linear space).
    const [br, bgc, bb] = [(BACKGROUND >> 16) & 255, (BACKGROUND >> 8) & 255, BACKGROUND & 255];
    let tissue = 0, cut = 0;
    const gw = 32, gh = 24, grid = new Float64Array(gw * gh), count = new Float64Array(gw * gh);
    for (let y = 0; y < c.height; y++) {
      for (let x = 0; x < c.width; x++) {
        const i = 4 * (y * c.width + x), r = d[i], g = d[i + 1], b = d[i + 2];
        if (Math.abs(r - br) + Math.abs(g - bgc) + Math.abs(b - bb) > 30) tissue++;
        if (r > 60 && g < 0.45 * r && b < 0.45 * r) cut++;
        const cell = Math.floor((y * gh) / c.height) * gw + Math.floor((x * gw) / c.width);
        grid[cell] += 0.299 * r + 0.587 * g + 0.114 * b;
        count[cell]++;
      }
    }
    return { width: c.width, height: c.height, tissue, cut, grid: Array.from(grid, (v, k) => v / count[k]) };
  }
}
