// The mouse as a scalpel and a hand. Left drag starting on the tissue is a scalpel stroke: the
// blade is the segment of the view ray through the mouse, from 5 mm in front of the surface
// under the mouse to the blade depth behind it (off the tissue, at the last surface distance
// along the ray); every pointer move sends a `scalpel` sample (a notification, at the mouse's
// rate) and the release an `end_stroke`. Right drag starting on the tissue grabs it (`grab`), moves the anchor
// over that plane (`move_grab`) and lets go on release (`release`). Drags elsewhere orbit.
import * as THREE from 'three';

const ABOVE_M = 0.005; // blade start in front of the surface [m]

export class Tools {
  constructor(view, connection, settings) {
    this.view = view;
    this.connection = connection;
    this.settings = settings; // {depthM(), stiffness()}
    this.nextStroke = 1;
    this.active = null; // {kind: 'cut'|'grab', plane, ...}
    const el = view.renderer.domElement;
    // Capture phase: decide before OrbitControls sees the press.
    el.addEventListener('pointerdown', (e) => this.down(e), { capture: true });
    el.addEventListener('pointermove', (e) => this.move(e));
    el.addEventListener('pointerup', (e) => this.up(e));
    el.addEventListener('contextmenu', (e) => e.preventDefault());
  }

  /** The plane through `point` facing the camera. */
  facingPlane(point) {
    const normal = new THREE.Vector3();
    this.view.camera.getWorldDirection(normal);
    return new THREE.Plane().setFromNormalAndCoplanarPoint(normal, point);
  }

  /** Where the ray under the pointer meets the drag plane, and the ray's direction. */
  onPlane(e) {
    const ray = this.view.ray(e.clientX, e.clientY).ray;
    const p = ray.intersectPlane(this.active.plane, new THREE.Vector3());
    return p ? { point: p, dir: ray.direction.clone() } : null;
  }

  down(e) {
    if (this.active || (e.button !== 0 && e.button !== 2)) return;
    const hit = this.view.pick(e.clientX, e.clientY);
    if (!hit) return; // orbit
    e.stopImmediatePropagation();
    e.preventDefault();
    this.view.controls.enabled = false;
    this.view.renderer.domElement.setPointerCapture(e.pointerId);
    const plane = this.facingPlane(hit);
    if (e.button === 0) {
      this.active = { kind: 'cut', plane, stroke: this.nextStroke++ };
      this.sample(e);
    } else {
      this.active = { kind: 'grab', plane, point: hit.clone(), id: null, target: hit.clone() };
      const grab = this.active;
      this.connection.request('grab', { point: hit.toArray(), stiffness: this.settings.stiffness() })
        .then(({ result }) => {
          grab.id = result.id;
          this.view.setGrab(grab.id, grab.point, grab.target);
          if (this.active !== grab) this.connection.request('release', { id: grab.id }).catch(() => {});
          else this.sendTarget();
        })
        .catch((err) => this.settings.report(`grab: ${err.data ? err.data.reason : err.message}`));
    }
  }

  move(e) {
    if (!this.active) return;
    if (this.active.kind === 'cut') return this.sample(e);
    const on = this.onPlane(e);
    if (!on) return;
    this.active.target = on.point;
    this.sendTarget();
  }

  sendTarget() {
    const g = this.active;
    if (!g || g.id === null) return;
    this.view.setGrab(g.id, g.point, g.target);
    this.connection.request('move_grab', { id: g.id, target: g.target.toArray() }).catch(() => {});
  }

  /** One scalpel sample: the blade along the view ray through the pointer, starting just in
   * front of the surface it meets (so the blade follows the surface as the mouse moves). */
  sample(e) {
    const caster = this.view.ray(e.clientX, e.clientY);
    const hit = caster.intersectObject(this.view.mesh, false)[0];
    if (hit) this.active.distance = hit.distance;
    if (this.active.distance === undefined) return;
    const dir = caster.ray.direction.clone();
    const point = caster.ray.at(this.active.distance, new THREE.Vector3());
    const a = point.clone().addScaledVector(dir, -ABOVE_M);
    const b = point.clone().addScaledVector(dir, this.settings.depthM());
    this.view.setBlade(a, b);
    this.connection.notify('scalpel', { stroke: this.active.stroke, a: a.toArray(), b: b.toArray() });
  }

  up(e) {
    const done = this.active;
    if (!done) return;
    this.active = null;
    this.view.controls.enabled = true;
    if (done.kind === 'cut') {
      this.view.setBlade(null);
      this.connection.request('end_stroke', { stroke: done.stroke })
        .catch((err) => this.settings.report(`cut: ${err.data ? err.data.reason : err.message}`));
    } else if (done.id !== null) {
      this.view.setGrab(done.id, null, null);
      this.connection.request('release', { id: done.id }).catch(() => {});
    }
  }
}
