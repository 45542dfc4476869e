// The result viewer: any output folder of tailor. Static results (.vtu), frame series (a .pvd, or
// the numbered files of rigid bodies and tori: play, pause, scrub), every body of a frame at once:
// tets and triangles as their boundary surface, rods as tubes with their material frames
// (rods.js), coloured by the field chosen in the menu, with a colour bar; and the plots of the
// folder's report.json (plots.js) above the PNG plots tailor wrote.
import { fetchFile } from './api.js';
import { showColorBar } from './colormap.js';
import { parseVtu, boundarySurface, scalarValues } from './vtu.js';
import { pvdFrames, numberedSeries } from './series.js';
import { lineSegments, countRods, tubeRadius, appendTubes } from './rods.js';
import { reportPlots } from './plots.js';

const BODY = 'cell:#body'; // the colour-by-body choice: each file's index

export class ResultViewer {
  constructor(viewer, files, status) {
    this.viewer = viewer;
    this.status = status;
    this.files = files.map((f) => f.path);
    this.frames = null; // [{ time, label, files }] of a frame series
    this.cache = new Map();
    this.framesShown = 0;
    this.playing = false;
    this.plots = [];
    this.fileSelect = document.getElementById('file');
    this.fieldSelect = document.getElementById('field');
    document.getElementById('results-controls').hidden = false;
    // Frame series first (.pvd, then numbered files), then the other results; a numbered
    // series' own files are not listed one by one.
    this.series = new Map(numberedSeries(this.files).map((s) => [`series:${s.name}`, s]));
    const members = new Set([...this.series.values()].flatMap((s) => [...s.members]));
    const pvd = this.files.filter((f) => f.endsWith('.pvd')).sort();
    const vtu = this.files.filter((f) => f.endsWith('.vtu') && !members.has(f));
    vtu.sort((a, b) => Number(a.includes('/')) - Number(b.includes('/')) || a.localeCompare(b));
    for (const f of pvd) this.fileSelect.add(new Option(f, f));
    for (const [key, s] of this.series) this.fileSelect.add(new Option(s.name, key));
    for (const f of vtu) this.fileSelect.add(new Option(f, f));
    this.fileSelect.addEventListener('change', () => this.open(this.fileSelect.value));
    this.fieldSelect.addEventListener('change', () => this.draw());
    document.getElementById('play').addEventListener('click', () => this.togglePlay());
    document.getElementById('frame').addEventListener('input', (e) => this.showFrame(Number(e.target.value)));
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
    if (!this.fileSelect.options.length) status('no .vtu or .pvd file in this folder yet');
  }

  async start() {
    if (this.files.includes('report.json')) await this.showReportPlots();
    if (this.fileSelect.options.length) await this.open(this.fileSelect.value);
  }

  async showReportPlots() {
    let report;
    try {
      report = JSON.parse(await fetchFile('report.json'));
    } catch {
      return; // a report being written, or not JSON: the PNGs remain
    }
    this.plots = reportPlots(report);
    const box = document.getElementById('plots');
    for (const p of [...this.plots].reverse()) {
      const figure = document.createElement('figure');
      figure.className = `report-plot ${p.kind}`;
      figure.append(p.svg);
      box.prepend(figure);
    }
  }

  async grid(path) {
    if (!this.cache.has(path)) {
      const grid = parseVtu(await fetchFile(path));
      grid.path = path;
      grid.surface = boundarySurface(grid);
      grid.lines = lineSegments(grid);
      this.cache.set(path, grid);
    }
    return this.cache.get(path);
  }

  async load(files) {
    return Promise.all(files.map((f) => this.grid(f)));
  }

  async open(key) {
    this.stop();
    this.ranges = new Map();
    if (key.endsWith('.pvd')) this.frames = pvdFrames(await fetchFile(key), key);
    else if (this.series.has(key)) this.frames = this.series.get(key).frames;
    else this.frames = null;
    const slider = document.getElementById('frame');
    document.getElementById('frames').hidden = !this.frames;
    if (this.frames) {
      slider.max = String(this.frames.length - 1);
      slider.value = '0';
      this.frame = 0;
      document.getElementById('frame-label').textContent = this.frames[0].label;
    }
    this.current = await this.load(this.frames ? this.frames[0].files : [key]);
    this.fillFields();
    this.fitCamera();
    this.draw();
  }

  fields(kind) {
    const seen = new Map();
    for (const grid of this.current)
      for (const f of kind === 'cell' ? grid.cellFields : grid.pointFields) if (!seen.has(f.name)) seen.set(f.name, f);
    return [...seen.values()];
  }

  fillFields() {
    const previous = this.fieldSelect.value;
    this.fieldSelect.innerHTML = '';
    // Several bodies (rigid bodies, tori, parts) can be told apart by colour.
    if (this.current.length > 1) this.fieldSelect.add(new Option('body (which file)', BODY));
    for (const f of this.fields('cell')) this.fieldSelect.add(new Option(`${f.name} (cell)`, `cell:${f.name}`));
    for (const f of this.fields('point')) this.fieldSelect.add(new Option(`${f.name} (point)`, `point:${f.name}`));
    const values = [...this.fieldSelect.options].map((o) => o.value);
    const varies = (value) => {
      const [kind, name] = value.split(/:(.*)/s);
      return this.current.some((grid) => {
        const f = (kind === 'cell' ? grid.cellFields : grid.pointFields).find((x) => x.name === name);
        const v = f ? scalarValues(f) : [];
        return v.some((x) => x !== v[0]);
      });
    };
    // Young's modulus, the displacement, a rod's curvature or strain, then any other field, each
    // first where it varies; a rod's frame vectors (unit length everywhere) last.
    const frameVector = (v) => v === 'cell:m1' || v === 'cell:m2';
    const order = ['cell:youngs_modulus', 'point:displacement', 'point:kappa', 'cell:axial_strain',
                   ...values.filter((v) => !frameVector(v) && v !== BODY)].filter((v) => values.includes(v));
    // A frame series is about motion: its displacement (zero in a first frame at rest).
    const motion = this.frames && values.includes('point:displacement') ? 'point:displacement' : undefined;
    const preferred = values.includes(previous) ? previous
      : motion ?? order.find(varies) ?? (values.includes(BODY) ? BODY : undefined) ?? order[0] ?? values[0];
    if (preferred) this.fieldSelect.value = preferred;
  }

  fitCamera() {
    const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
    for (const { positions: p } of this.current)
      for (let i = 0; i < p.length; i += 3)
        for (let k = 0; k < 3; ++k) {
          min[k] = Math.min(min[k], p[i + k]);
          max[k] = Math.max(max[k], p[i + k]);
        }
    this.size = Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]) || 1;
    this.viewer.frame(min, max);
  }

  // The chosen field's range over every frame shown so far, so that colours compare across frames.
  range(key, values) {
    let lo = Infinity, hi = -Infinity;
    for (const v of values)
      if (Number.isFinite(v)) {
        lo = Math.min(lo, v);
        hi = Math.max(hi, v);
      }
    if (!(hi >= lo)) return [0, 1];
    const r = this.ranges.get(key) ?? [lo, hi];
    r[0] = Math.min(r[0], lo);
    r[1] = Math.max(r[1], hi);
    this.ranges.set(key, r);
    return r;
  }

  // Every body of the current frame in one surface: boundary triangles and rod tubes.
  draw() {
    const [kind, name] = (this.fieldSelect.value || 'cell:').split(/:(.*)/s);
    const perTriangle = kind === 'cell';
    const out = { positions: [], triangles: [], values: [] };
    const glyphs = { positions: [], colors: [] };
    let components = 1, found = false, surfaceTriangles = 0, segments = 0, rods = 0;
    for (const [body, grid] of this.current.entries()) {
      const field = this.fieldSelect.value === BODY ? { name, components: 1, values: new Float64Array(grid.types.length).fill(body) }
        : (perTriangle ? grid.cellFields : grid.pointFields).find((f) => f.name === name);
      const scalars = field ? scalarValues(field) : null;
      if (field) (found = true), (components = field.components);
      const base = out.positions.length / 3;
      const { triangles, owners } = grid.surface;
      for (const x of grid.positions) out.positions.push(x);
      if (!perTriangle) for (let v = 0; v < grid.positions.length / 3; ++v) out.values.push(scalars ? scalars[v] : NaN);
      for (let t = 0; t < owners.length; ++t) {
        out.triangles.push(base + triangles[3 * t], base + triangles[3 * t + 1], base + triangles[3 * t + 2]);
        if (perTriangle) out.values.push(scalars ? scalars[owners[t]] : NaN);
      }
      surfaceTriangles += owners.length;
      if (grid.lines.owners.length) {
        const radius = tubeRadius(grid.positions, grid.lines.segments, this.size);
        const g = appendTubes(grid, grid.lines, radius, out, perTriangle ? scalars ?? new Float64Array(grid.types.length).fill(NaN) : null,
          perTriangle ? null : scalars);
        glyphs.positions.push(...g.positions);
        glyphs.colors.push(...g.colors);
        segments += grid.lines.owners.length;
        rods += countRods(grid.lines.segments);
      }
    }
    const values = Float64Array.from(out.values);
    const [lo, hi] = found ? this.range(`${kind}:${name}`, values) : [0, 1];
    this.viewer.setSurface(Float32Array.from(out.positions), Uint32Array.from(out.triangles), values, perTriangle, lo, hi);
    this.viewer.setLines(glyphs.positions, glyphs.colors);
    const barName = this.fieldSelect.value === BODY ? 'body' : components > 1 ? `|${name}|` : name;
    showColorBar(found ? barName : '', lo, hi);
    this.viewer.render();
    this.framesShown += 1;
    this.drawn = { bodies: this.current.length, surfaceTriangles, rodSegments: segments, rods, frameGlyphs: glyphs.positions.length / 6 };
    const frameText = this.frames ? `frame ${this.frame + 1} of ${this.frames.length}, ${this.frames[this.frame].label}\n` : '';
    const rodText = segments ? `, ${rods} rod(s) of ${segments} segments` : '';
    const cells = this.current.reduce((n, g) => n + g.types.length, 0);
    this.status(`${frameText}${this.current.length} bod${this.current.length > 1 ? 'ies' : 'y'}: ${surfaceTriangles} surface triangles${rodText}, ${cells} cells`);
  }

  async showFrame(i) {
    if (!this.frames) return;
    this.frame = Math.max(0, Math.min(this.frames.length - 1, i));
    document.getElementById('frame').value = String(this.frame);
    document.getElementById('frame-label').textContent = this.frames[this.frame].label;
    this.current = await this.load(this.frames[this.frame].files);
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

