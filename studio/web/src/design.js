// The interactive material design: the body coloured by Young's modulus, one sphere per handle
// at its target (rest centre + target displacement). Dragging a sphere retargets the reduced
// design (the server designs again and replies with E and the deformed surface); the time from
// release to the redrawn frame is measured here (window.studio.latencies, in ms).
import { send, float32Array } from './api.js';

// The design's large arrays come as base64 little-endian floats (docs/studio.md, "Messages").
export const ARRAYS = 'float32-base64';
import { showColorBar, formatNumber } from './colormap.js';
import { THREE } from './viewer.js';

export class DesignView {
  constructor(viewer, scene, status) {
    this.viewer = viewer;
    this.status = status;
    this.rest = Float32Array.from(scene.positions);
    this.triangles = Uint32Array.from(scene.triangles);
    this.handles = scene.handles;
    this.elements = scene.elements;
    this.targets = scene.targets.map((t) => [...t]);
    this.latencies = [];
    this.releases = []; // the reply to each release: {type, message}
    this.phases = []; // per release, ms: sent, reply (last byte), parse, apply (buffers), frame (drawn)
    this.designs = 0;
    this.inFlight = false;
    this.pending = false;
    this.spheres = [];
    this.lastCheck = '';
    document.getElementById('design-controls').hidden = false;
    this.fitCamera();
    const radius = 0.04 * this.size;
    for (let h = 0; h < this.handles.length; ++h) {
      const sphere = new THREE.Mesh(new THREE.SphereGeometry(radius, 24, 16), new THREE.MeshLambertMaterial({ color: 0xd0402b }));
      sphere.userData.handle = h;
      viewer.scene.add(sphere);
      this.spheres.push(sphere);
    }
    this.placeSpheres();
    this.apply(scene);
    this.installDragging();
    document.getElementById('full-check').addEventListener('click', () => this.fullCheck());
    document.getElementById('save').addEventListener('click', () => this.save());
  }

  fitCamera() {
    const p = this.rest;
    const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < p.length; i += 3)
      for (let k = 0; k < 3; ++k) {
        min[k] = Math.min(min[k], p[i + k]);
        max[k] = Math.max(max[k], p[i + k]);
      }
    this.size = Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]);
    this.viewer.frame(min, max);
  }

  targetPosition(h) {
    const c = this.handles[h].rest_centre;
    return [c[0] + this.targets[h][0], c[1] + this.targets[h][1], c[2] + this.targets[h][2]];
  }

  placeSpheres() {
    for (let h = 0; h < this.spheres.length; ++h) this.spheres[h].position.set(...this.targetPosition(h));
  }

  // Draws a design reply: the deformed surface coloured by E.
  apply(reply) {
    reply.displacement = float32Array(reply.displacement);
    reply.youngs_modulus = float32Array(reply.youngs_modulus);
    const deformed = new Float32Array(this.rest.length);
    for (let i = 0; i < deformed.length; ++i) deformed[i] = this.rest[i] + reply.displacement[i];
    const [lo, hi] = reply.youngs_modulus_range;
    this.range = [lo, hi];
    this.reducedErrors = reply.reduced_errors;
    this.viewer.setSurface(deformed, this.triangles, reply.youngs_modulus, true, lo, hi);
    showColorBar("Young's modulus E", lo, hi);
    this.lastReply = reply;
    this.showStatus();
  }

  showStatus(extra = '') {
    const r = this.lastReply;
    const lines = [
      `${this.elements} tets, ${this.handles.length} handle(s)`,
      `E in [${formatNumber(this.range[0])}, ${formatNumber(this.range[1])}]`,
      `reduced handle error: ${(r.reduced_errors || []).map(formatNumber).join(', ') || '-'}`,
      `design: ${r.status}, ${r.iterations} iterations, ${(1e3 * r.seconds).toFixed(1)} ms on the server`,
    ];
    if (this.latencies.length) lines.push(`release to redraw: ${this.latencies[this.latencies.length - 1].toFixed(1)} ms`);
    if (this.lastCheck) lines.push(this.lastCheck);
    if (extra) lines.push(extra);
    this.status(lines.join('\n'));
  }

  installDragging() {
    const canvas = this.viewer.canvas;
    let drag = null;
    canvas.addEventListener('pointerdown', (e) => {
      const hit = this.viewer.rayAt(e).intersectObjects(this.spheres)[0];
      if (!hit) return;
      e.preventDefault();
      this.viewer.controlsEnabled = false;
      canvas.setPointerCapture(e.pointerId);
      const normal = new THREE.Vector3();
      this.viewer.camera.getWorldDirection(normal);
      drag = { handle: hit.object.userData.handle, plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.object.position) };
    }, { capture: true });
    canvas.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const point = new THREE.Vector3();
      if (!this.viewer.rayAt(e).ray.intersectPlane(drag.plane, point)) return;
      const c = this.handles[drag.handle].rest_centre;
      this.targets[drag.handle] = [point.x - c[0], point.y - c[1], point.z - c[2]];
      this.placeSpheres();
      this.viewer.render();
      this.retarget(null); // live while dragging, one request at a time
    });
    canvas.addEventListener('pointerup', () => {
      if (!drag) return;
      drag = null;
      this.viewer.controlsEnabled = true;
      this.pending = false; // the release's request is the last of the drag
      this.retarget(performance.now(), true);
    });
  }

  // Sends the targets; `released` (a time) measures release -> redraw. A drag's intermediate
  // moves are sent one at a time; the release always goes out (the server stops an older run).
  async retarget(released, force = false) {
    if (this.inFlight && !force) {
      this.pending = true;
      return;
    }
    this.inFlight = true;
    if (released === null) this.pending = false;
    try {
      this.sequence = (this.sequence || 0) + 1; // orders the requests on the server
      const sent = performance.now();
      const timing = {};
      const reply = await send({ type: 'retarget', targets: this.targets, sequence: this.sequence, arrays: ARRAYS }, undefined, timing);
      if (released !== null) this.releases.push({ type: reply.type, message: reply.message, reply_ms: performance.now() - released });
      if (reply.type === 'design') {
        const applying = performance.now();
        this.apply(reply);
        const applied = performance.now();
        const drawn = await this.viewer.renderedFrame();
        this.designs += 1;
        if (released !== null) {
          this.latencies.push(drawn - released);
          this.phases.push({ wait_ms: sent - released, queued_ms: 1e3 * reply.queued_seconds, server_ms: 1e3 * reply.seconds, headers_ms: timing.headers,
            body_ms: timing.body, parse_ms: timing.parse_ms, bytes: timing.bytes, apply_ms: applied - applying,
            frame_ms: drawn - applied });
          this.showStatus();
        }
      } else if (reply.type === 'error') {
        this.showStatus(`error: ${reply.message}`);
      }
    } catch (error) {
      if (released !== null) this.releases.push({ type: 'error', message: error.message });
      this.showStatus(`error: ${error.message}`);
    } finally {
      this.inFlight = false;
    }
    if (this.pending && released === null) this.retarget(null);
  }

  async fullCheck() {
    this.showStatus('full-space check running...');
    const reply = await send({ type: 'full_check' });
    this.lastCheck = reply.type === 'full_check'
      ? `full-space handle error: ${reply.full_errors.map(formatNumber).join(', ')} (reduced ${reply.reduced_errors.map(formatNumber).join(', ')}), ${reply.seconds.toFixed(2)} s`
      : `full-space check: ${reply.message}`;
    this.showStatus();
    return reply;
  }

  async save() {
    this.showStatus('saving: designing as tailor run does...');
    const reply = await send({ type: 'save' });
    this.showStatus(reply.type === 'saved' ? `saved ${reply.report} and ${reply.vtu}` : `save: ${reply.message}`);
    return reply;
  }
}
