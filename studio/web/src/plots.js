// The plots of an output folder's report.json, drawn as SVG from its numbers (so they can be read
// off, unlike the PNGs tailor writes beside them): an inverse run's convergence (objective and
// gradient norm per iteration), a periodic cell's E(d) polar curves (one per plane), a damping
// study's decay envelopes exp(-sigma t) per mode (designed, target, plain Rayleigh, from the rates
// the study measured) and its amplitude-dependent cycle loss, a dynamic run's energies over time.
import { formatNumber } from './colormap.js';

const SVG = 'http://www.w3.org/2000/svg';
const W = 290, H = 190, M = { left: 54, right: 8, top: 22, bottom: 30 };
const COLORS = ['#1f5fa8', '#d0402b', '#2a9d4b', '#8a4fb0', '#c98a16', '#444'];

function element(name, attributes, parent) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, String(v));
  if (parent) parent.append(e);
  return e;
}

function text(parent, x, y, content, attributes = {}) {
  element('text', { x, y, 'font-size': 10, fill: '#333', ...attributes }, parent).textContent = content;
}

function svgRoot(title) {
  const svg = element('svg', { viewBox: `0 0 ${W} ${H}`, width: W, height: H, class: 'plot', 'data-title': title });
  text(svg, W / 2, 13, title, { 'text-anchor': 'middle', 'font-size': 11, 'font-weight': 'bold' });
  return svg;
}

function legend(svg, series, x, y) {
  series.forEach((s, i) => {
    const yy = y + 11 * i;
    element('line', { x1: x, y1: yy - 3, x2: x + 14, y2: yy - 3, stroke: s.color, 'stroke-width': 1.6, 'stroke-dasharray': s.dash ?? '' }, svg);
    text(svg, x + 17, yy, s.name, { 'font-size': 9 });
  });
}

// series: [{ name, x: [], y: [], dash? }]; logY: a logarithmic value axis (values <= floor dropped).
export function linePlot({ title, xLabel, yLabel, series, logY = false, floor = 0 }) {
  const svg = svgRoot(title);
  const ty = (v) => (logY ? Math.log10(v) : v);
  const keep = (v) => Number.isFinite(v) && (!logY || v > floor);
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const s of series)
    s.x.forEach((x, i) => {
      if (!keep(s.y[i])) return;
      x0 = Math.min(x0, x), x1 = Math.max(x1, x), y0 = Math.min(y0, ty(s.y[i])), y1 = Math.max(y1, ty(s.y[i]));
    });
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) (y1 = y0 + 1), (y0 -= 1);
  const px = (x) => M.left + ((x - x0) / (x1 - x0)) * (W - M.left - M.right);
  const py = (y) => H - M.bottom - ((ty(y) - y0) / (y1 - y0)) * (H - M.top - M.bottom);
  element('rect', { x: M.left, y: M.top, width: W - M.left - M.right, height: H - M.top - M.bottom, fill: 'none', stroke: '#999' }, svg);
  const yText = (v) => (logY ? `1e${Math.round(v * 10) / 10}` : formatNumber(v));
  text(svg, M.left - 3, H - M.bottom, yText(y0), { 'text-anchor': 'end' });
  text(svg, M.left - 3, M.top + 8, yText(y1), { 'text-anchor': 'end' });
  text(svg, M.left, H - M.bottom + 11, formatNumber(x0), { 'text-anchor': 'middle' });
  text(svg, W - M.right, H - M.bottom + 11, formatNumber(x1), { 'text-anchor': 'end' });
  text(svg, (M.left + W - M.right) / 2, H - 4, xLabel, { 'text-anchor': 'middle' });
  text(svg, 10, (M.top + H - M.bottom) / 2, yLabel + (logY ? ' (log)' : ''),
    { 'text-anchor': 'middle', transform: `rotate(-90 10 ${(M.top + H - M.bottom) / 2})` });
  const drawn = series.map((s, i) => ({ ...s, color: s.color ?? COLORS[i % COLORS.length] }));
  for (const s of drawn) {
    const points = s.x.map((x, i) => [x, s.y[i]]).filter(([, y]) => keep(y));
    element('polyline', { points: points.map(([x, y]) => `${px(x).toFixed(1)},${py(y).toFixed(1)}`).join(' '),
      fill: 'none', stroke: s.color, 'stroke-width': 1.6, 'stroke-dasharray': s.dash ?? '' }, svg);
  }
  legend(svg, drawn, W - M.right - 110, M.top + 12);
  return svg;
}

// curves: [{ name, degrees: [], radius: [] }] in the plane's own axes (0 degrees along the first).
export function polarPlot({ title, curves, axes = ['x', 'y'] }) {
  const svg = svgRoot(title);
  const cx = W / 2 - 40, cy = (H + M.top) / 2, R = (H - M.top - 14) / 2;
  const rmax = Math.max(...curves.flatMap((c) => c.radius.map(Math.abs))) || 1;
  for (const f of [0.5, 1]) element('circle', { cx, cy, r: f * R, fill: 'none', stroke: '#bbb' }, svg);
  element('line', { x1: cx - R, y1: cy, x2: cx + R, y2: cy, stroke: '#bbb' }, svg);
  element('line', { x1: cx, y1: cy - R, x2: cx, y2: cy + R, stroke: '#bbb' }, svg);
  text(svg, cx + R + 2, cy + 3, axes[0]);
  text(svg, cx - 3, cy - R - 2, axes[1], { 'text-anchor': 'end' });
  text(svg, cx + 0.5 * R * Math.SQRT1_2 + 2, cy - 0.5 * R * Math.SQRT1_2, formatNumber(rmax / 2), { 'font-size': 8 });
  text(svg, cx + R * Math.SQRT1_2 + 2, cy - R * Math.SQRT1_2, formatNumber(rmax), { 'font-size': 8 });
  const drawn = curves.map((c, i) => ({ ...c, color: COLORS[i % COLORS.length] }));
  for (const c of drawn) {
    const points = c.degrees.map((d, i) => {
      const a = (d * Math.PI) / 180, r = (Math.abs(c.radius[i]) / rmax) * R;
      return `${(cx + r * Math.cos(a)).toFixed(1)},${(cy - r * Math.sin(a)).toFixed(1)}`;
    });
    element('polygon', { points: points.join(' '), fill: 'none', stroke: c.color, 'stroke-width': 1.6 }, svg);
  }
  legend(svg, drawn, W - 105, M.top + 12);
  return svg;
}

const column = (rows, key) => rows.map((r) => r[key]);
const range = (n, f) => Array.from({ length: n }, (_, i) => f(i));

// The plots that `report` (a parsed report.json) has numbers for: [{ kind, title, svg }].
export function reportPlots(report) {
  const plots = [];
  if (Array.isArray(report.history) && report.history.length) {
    const it = column(report.history, 'iteration');
    plots.push({ kind: 'convergence', title: 'convergence', svg: linePlot({ title: 'convergence', xLabel: 'iteration', yLabel: 'value', logY: true,
      series: [{ name: 'objective', x: it, y: column(report.history, 'objective') },
               { name: 'gradient norm', x: it, y: column(report.history, 'gradient_norm'), dash: '4 2' }] }) });
  }
  for (const d of Array.isArray(report.directional) ? report.directional : []) {
    if (!Array.isArray(d.angle_degrees) || !Array.isArray(d.youngs_modulus)) continue;
    const plane = d.plane || 'xy';
    const title = `E(d), plane ${plane}`;
    plots.push({ kind: 'polar', title, svg: polarPlot({ title, axes: [plane[0], plane[1]],
      curves: [{ name: 'E(d)', degrees: d.angle_degrees, radius: d.youngs_modulus }] }) });
  }
  const modes = Array.isArray(report.modes) ? report.modes.filter((m) => Number.isFinite(m.designed_rate)) : [];
  if (modes.length) {
    // Over three decay times of the slowest target, on a log axis (a rate is a slope) down to 1e-3.
    const slowest = Math.min(...modes.map((m) => m.target_rate ?? m.designed_rate).filter((r) => r > 0));
    const t = range(121, (i) => (i / 120) * (3 / slowest));
    const series = [];
    modes.forEach((m, i) => {
      const color = COLORS[i % COLORS.length];
      series.push({ name: `mode ${m.mode} designed`, x: t, y: t.map((s) => Math.exp(-m.designed_rate * s)), color });
      if (Number.isFinite(m.target_rate))
        series.push({ name: `mode ${m.mode} target`, x: t, y: t.map((s) => Math.exp(-m.target_rate * s)), color, dash: '4 2' });
      if (Number.isFinite(m.plain_rate))
        series.push({ name: `mode ${m.mode} plain`, x: t, y: t.map((s) => Math.exp(-m.plain_rate * s)), color, dash: '1 2' });
    });
    plots.push({ kind: 'decay', title: 'damping decay', svg: linePlot({ title: 'damping decay exp(-σt)', xLabel: 't (s)', yLabel: 'amplitude', series, logY: true, floor: 1e-3 }) });
  }
  const cycles = Array.isArray(report.nonlinear_cycles) ? report.nonlinear_cycles : [];
  if (cycles.length > 1) {
    const a = column(cycles, 'amplitude');
    plots.push({ kind: 'cycle_loss', title: 'loss per cycle', svg: linePlot({ title: 'loss per cycle', xLabel: 'amplitude', yLabel: 'loss',
      series: [{ name: 'achieved', x: a, y: column(cycles, 'achieved_loss') }, { name: 'designed', x: a, y: column(cycles, 'designed_loss'), dash: '4 2' }] }) });
  }
  const s = report.series;
  if (s && Array.isArray(s.time) && s.time.length > 1) {
    const series = ['kinetic_energy', 'potential_energy', 'total_energy'].filter((k) => Array.isArray(s[k]))
      .map((k) => ({ name: k.replace('_', ' '), x: s.time, y: s[k] }));
    if (series.length) plots.push({ kind: 'energy', title: 'energy', svg: linePlot({ title: 'energy', xLabel: 't (s)', yLabel: 'J', series }) });
  }
  return plots;
}
