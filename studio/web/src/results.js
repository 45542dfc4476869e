// The result viewer: any output folder of tailor. A static result (.vtu) or a frame series
// (.pvd: play, pause, scrub) drawn as its boundary surface, coloured by the chosen field.
import { fetchFile } from './api.js';
import { showColorBar, formatNumber } from './colormap.js';
import { parseVtu, parsePvd, boundarySurface, scalarValues } from './vtu.js';

export class ResultViewer {
  constructor(viewer, files, status) {
    this.viewer = viewer;
    this.status = status;
    this.files = files.map((f) => f.path);
    this.frames = null; // [{time, file}] for a .pvd
    this.cache = new Map();
    this.framesShown = 0;
    this.playing = false;
    this.fileSelect = document.getElementById('file');
    this.fieldSelect = document.getElementById('field');
    document.getElementById('results-controls').hidden = false;
    const shown = this.files.filter((f) => f.endsWith('.vtu') || f.endsWith('.pvd'));
    // Frame series first, then results, then the rest (e.g. each frame's own file).
    const rank = (f) => (f.endsWith('.pvd') ? 0 : f.includes('/') ? 2 : 1);
    shown.sort((a, b) => rank(a) - rank(b) || a.localeCompare(b));
    for (const f of shown) this.fileSelect.add(new Option(f, f));
    this.fileSelect.addEventListener('change', () => this.open(this.fileSelect.value));
    this.fieldSelect.addEventListener('change', () => this.draw());
    document.getElementById('play').addEventListener('click', () => this.togglePlay());
    document.getElementById('frame').addEventListener('input', (e) => this.showFrame(Number(e.target.value)));
    // The plots tailor writes next to its results (convergence, damping decay, E(d) polar
    // curves, ...), as they are.
    const plots = document.getElementById('plots');
    for (const f of this.files.filter((name) => name.endsWith('.png')).sort()) {
      const figure = document.createElement('figure');
      const image = document.createElement('img');
      image.src = 'files/' + f.split('/').map(encodeURIComponent).join('/');
      image.alt = f;
      const caption = document.createElement('figcaption');
      caption.textContent = f;
      figure.append(image, caption);
      plots.append(figure);
    }
    if (!shown.length) status('no .vtu or .pvd file in this folder yet');
  }

  async start() {
    if (this.fileSelect.options.length) await this.open(this.fileSelect.value);
  }

  async grid(path) {
    if (!this.cache.has(path)) {
      const grid = parseVtu(await fetchFile(path));
      grid.surface = boundarySurface(grid);
      this.cache.set(path, grid);
    }
    return this.cache.get(path);
  }

  async open(path) {
    this.stop();
    if (path.endsWith('.pvd')) {
      this.frames = parsePvd(await fetchFile(path), path);
      const slider = document.getElementById('frame');
      slider.max = String(this.frames.length - 1);
      slider.value = '0';
      document.getElementById('frames').hidden = false;
      this.frame = 0;
      this.current = await this.grid(this.frames[0].file);
    } else {
      this.frames = null;
      document.getElementById('frames').hidden = true;
      this.current = await this.grid(path);
    }
    this.fillFields();
    this.fitCamera();
    this.draw();
  }

  fillFields() {
    const previous = this.fieldSelect.value;
    this.fieldSelect.innerHTML = '';
    for (const f of this.current.cellFields) this.fieldSelect.add(new Option(`${f.name} (cell)`, `cell:${f.name}`));
    for (const f of this.current.pointFields) this.fieldSelect.add(new Option(`${f.name} (point)`, `point:${f.name}`));
    const values = [...this.fieldSelect.options].map((o) => o.value);
    // Young's modulus, else the displacement, else the first field, each only if it varies.
    const varies = (value) => {
      const [kind, name] = value.split(/:(.*)/s);
      const f = (kind === 'cell' ? this.current.cellFields : this.current.pointFields).find((x) => x.name === name);
      const v = scalarValues(f);
      return v.some((x) => x !== v[0]);
    };
    const order = ['cell:youngs_modulus', 'point:displacement', ...values].filter((v) => values.includes(v));
    // A frame series is about motion: its displacement (zero in a first frame at rest).
    const motion = this.frames && values.includes('point:displacement') ? 'point:displacement' : undefined;
    const preferred = values.includes(previous) ? previous : motion ?? order.find(varies) ?? values[0];
    if (preferred) this.fieldSelect.value = preferred;
  }

  fitCamera() {
    const p = this.current.positions;
    const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < p.length; i += 3)
      for (let k = 0; k < 3; ++k) {
        min[k] = Math.min(min[k], p[i + k]);
        max[k] = Math.max(max[k], p[i + k]);
      }
    this.viewer.frame(min, max);
  }

  // The chosen field's range over every loaded frame, so that colours compare across frames.
  range(kind, name, values) {
    let lo = Infinity, hi = -Infinity;
    for (const v of values) {
      lo = Math.min(lo, v);
      hi = Math.max(hi, v);
    }
    const key = `${kind}:${name}`;
    if (this.frames) {
      const r = (this.ranges ??= new Map()).get(key) ?? [lo, hi];
      r[0] = Math.min(r[0], lo);
      r[1] = Math.max(r[1], hi);
      this.ranges.set(key, r);
      return r;
    }
    return [lo, hi];
  }

  draw() {
    const grid = this.current;
    const [kind, name] = (this.fieldSelect.value || 'cell:').split(/:(.*)/s);
    const field = (kind === 'cell' ? grid.cellFields : grid.pointFields).find((f) => f.name === name);
    const { triangles, owners } = grid.surface;
    let values, perTriangle;
    if (field) {
      const scalars = scalarValues(field);
      if (kind === 'cell') {
        values = Float64Array.from(owners, (c) => scalars[c]);
        perTriangle = true;
      } else {
        values = scalars;
        perTriangle = false;
      }
    } else {
      values = new Float64Array(owners.length);
      perTriangle = true;
    }
    const [lo, hi] = field ? this.range(kind, name, values) : [0, 1];
    this.viewer.setSurface(grid.positions, triangles, values, perTriangle, lo, hi);
    showColorBar(field ? (field.components > 1 ? `|${name}|` : name) : '', lo, hi);
    this.viewer.render();
    this.framesShown += 1;
    const frameText = this.frames ? `frame ${this.frame + 1} of ${this.frames.length}, t = ${formatNumber(this.frames[this.frame].time)}\n` : '';
    this.status(`${frameText}${triangles.length / 3} surface triangles, ${grid.types.length} cells`);
  }

  async showFrame(i) {
    if (!this.frames) return;
    this.frame = Math.max(0, Math.min(this.frames.length - 1, i));
    document.getElementById('frame').value = String(this.frame);
    document.getElementById('frame-label').textContent = `t = ${formatNumber(this.frames[this.frame].time)}`;
    this.current = await this.grid(this.frames[this.frame].file);
    this.draw();
  }

  togglePlay() {
    if (this.playing) this.stop();
    else this.play();
  }

  async play() {
    if (!this.frames) return;
    this.playing = true;
    document.getElementById('play').textContent = 'pause';
    if (this.frame >= this.frames.length - 1) this.frame = -1;
    while (this.playing && this.frame < this.frames.length - 1) {
      const started = performance.now();
      await this.showFrame(this.frame + 1);
      await new Promise((r) => setTimeout(r, Math.max(0, 80 - (performance.now() - started))));
    }
    this.stop();
  }

  stop() {
    this.playing = false;
    document.getElementById('play').textContent = 'play';
  }
}
