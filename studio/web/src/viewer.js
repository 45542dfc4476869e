// The 3D view: one triangle surface coloured per triangle or per vertex, a few marker spheres, and
// an orbit camera (drag: rotate about the body's centre, wheel: zoom, shift-drag: pan).
import * as THREE from './three.module.js';
import { colorAt } from './colormap.js';

export class Viewer {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setClearColor(0xf4f4f4);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 2.2));
    const light = new THREE.DirectionalLight(0xffffff, 1.2);
    light.position.set(1, 2, 3);
    this.camera.add(light);
    this.scene.add(this.camera);
    this.geometry = new THREE.BufferGeometry();
    this.material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
    this.mesh = new THREE.Mesh(this.geometry, this.material);
    this.scene.add(this.mesh);
    // Line glyphs (the rods' material frames), coloured per vertex.
    this.lines = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ vertexColors: true }));
    this.scene.add(this.lines);
    this.target = new THREE.Vector3();
    this.orbit = { azimuth: -0.9, elevation: 0.45, distance: 10 };
    this.controlsEnabled = true;
    this.installControls();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  installControls() {
    let last = null;
    this.canvas.addEventListener('pointerdown', (e) => {
      if (!this.controlsEnabled || e.defaultPrevented) return;
      last = { x: e.clientX, y: e.clientY, pan: e.shiftKey };
      this.canvas.setPointerCapture(e.pointerId);
    });
    this.canvas.addEventListener('pointermove', (e) => {
      if (!last) return;
      const dx = e.clientX - last.x, dy = e.clientY - last.y;
      if (last.pan) {
        const s = this.orbit.distance / this.canvas.clientHeight;
        const right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrix, 0);
        const up = new THREE.Vector3().setFromMatrixColumn(this.camera.matrix, 1);
        this.target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
      } else {
        this.orbit.azimuth -= dx * 0.01;
        this.orbit.elevation = Math.max(-1.5, Math.min(1.5, this.orbit.elevation + dy * 0.01));
      }
      last.x = e.clientX;
      last.y = e.clientY;
      this.render();
    });
    this.canvas.addEventListener('pointerup', () => (last = null));
    this.canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.orbit.distance *= Math.exp(e.deltaY * 0.001);
      this.render();
    }, { passive: false });
  }

  // Centres the camera on the box [min, max].
  frame(min, max) {
    const centre = new THREE.Vector3((min[0] + max[0]) / 2, (min[1] + max[1]) / 2, (min[2] + max[2]) / 2);
    const size = Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]) || 1;
    this.target.copy(centre);
    this.orbit.distance = 1.8 * size;
    this.camera.near = size / 1000;
    this.camera.far = size * 100;
    this.camera.updateProjectionMatrix();
  }

  // positions: Float32Array (3 per vertex); triangles: Uint32Array (3 per triangle); values: per
  // triangle (perTriangle) or per vertex, coloured over [min, max].
  setSurface(positions, triangles, values, perTriangle, min, max) {
    const n = triangles.length;
    let p = this.geometry.getAttribute('position');
    let c = this.geometry.getAttribute('color');
    if (!p || p.count !== n) {
      p = new THREE.BufferAttribute(new Float32Array(3 * n), 3);
      c = new THREE.BufferAttribute(new Float32Array(3 * n), 3);
      this.geometry.setAttribute('position', p);
      this.geometry.setAttribute('color', c);
    }
    const span = max > min ? max - min : 1;
    for (let i = 0; i < n; ++i) {
      const v = triangles[i];
      p.array[3 * i] = positions[3 * v];
      p.array[3 * i + 1] = positions[3 * v + 1];
      p.array[3 * i + 2] = positions[3 * v + 2];
      const value = perTriangle ? values[Math.floor(i / 3)] : values[v];
      colorAt((value - min) / span, c.array, 3 * i);
    }
    p.needsUpdate = true;
    c.needsUpdate = true;
    this.geometry.computeVertexNormals();
    this.geometry.computeBoundingSphere();
  }

  // positions, colors: 3 numbers per point, two points per segment (none: no lines).
  setLines(positions, colors) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(positions), 3));
    g.setAttribute('color', new THREE.BufferAttribute(Float32Array.from(colors), 3));
    this.lines.geometry.dispose();
    this.lines.geometry = g;
  }

  // The drawn frame's pixels that differ from the background (for the tests).
  coloredPixels() {
    this.render();
    const copy = document.createElement('canvas');
    copy.width = this.canvas.width;
    copy.height = this.canvas.height;
    const context = copy.getContext('2d');
    context.drawImage(this.canvas, 0, 0);
    const data = context.getImageData(0, 0, copy.width, copy.height).data;
    let count = 0;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - 0xf4) + Math.abs(data[i + 1] - 0xf4) + Math.abs(data[i + 2] - 0xf4) > 12) ++count;
    return count;
  }

  render() {
    const o = this.orbit;
    this.camera.position.set(
      this.target.x + o.distance * Math.cos(o.elevation) * Math.cos(o.azimuth),
      this.target.y + o.distance * Math.cos(o.elevation) * Math.sin(o.azimuth),
      this.target.z + o.distance * Math.sin(o.elevation));
    this.camera.up.set(0, 0, 1);
    this.camera.lookAt(this.target);
    this.camera.updateMatrixWorld();
    this.renderer.render(this.scene, this.camera);
  }

  // The next frame, drawn: resolves after the browser has rendered it.
  renderedFrame() {
    this.render();
    return new Promise((resolve) => requestAnimationFrame(() => resolve(performance.now())));
  }

  // The canvas pixel (CSS px, relative to the page) where the world point lies.
  toScreen(point) {
    const v = new THREE.Vector3(point[0], point[1], point[2]).project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return { x: r.left + ((v.x + 1) / 2) * r.width, y: r.top + ((1 - v.y) / 2) * r.height };
  }

  // The ray through a pointer event's pixel.
  rayAt(event) {
    const r = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, this.camera);
    return raycaster;
  }
}

export { THREE };
