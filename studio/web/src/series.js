// Frame series of an output folder: a .pvd collection (its DataSets grouped by time step, so that
// a step with several parts draws them together) and the numbered files the rigid-body and torus
// scenes write, one per body and output step (<body>_<step>.vtu, the step zero-padded to 4 or
// more digits): one series per folder, whose frame n holds each body's file with the largest step
// <= n. A frame is { time, label, files }.
import { formatNumber } from './colormap.js';

const NUMBERED = /^(.*)_(\d{4,})\.vtu$/;

export function pvdFrames(text, pvdPath) {
  const doc = new DOMParser().parseFromString(text, 'application/xml');
  const folder = pvdPath.includes('/') ? pvdPath.slice(0, pvdPath.lastIndexOf('/') + 1) : '';
  const byTime = new Map();
  for (const d of doc.getElementsByTagName('DataSet')) {
    const time = Number(d.getAttribute('timestep'));
    if (!byTime.has(time)) byTime.set(time, []);
    byTime.get(time).push(folder + d.getAttribute('file'));
  }
  return [...byTime.entries()].sort((a, b) => a[0] - b[0])
    .map(([time, files]) => ({ time, label: `t = ${formatNumber(time)}`, files }));
}

// The numbered series among `paths`: [{ name, frames, members }] (members: the files it holds).
export function numberedSeries(paths) {
  const folders = new Map();
  for (const path of paths) {
    const slash = path.lastIndexOf('/');
    const folder = path.slice(0, slash + 1), m = path.slice(slash + 1).match(NUMBERED);
    if (!m) continue;
    if (!folders.has(folder)) folders.set(folder, new Map());
    const bodies = folders.get(folder);
    if (!bodies.has(m[1])) bodies.set(m[1], []);
    bodies.get(m[1]).push({ step: Number(m[2]), path });
  }
  const series = [];
  for (const [folder, bodies] of folders) {
    const steps = [...new Set([...bodies.values()].flat().map((f) => f.step))].sort((a, b) => a - b);
    if (steps.length < 2) continue;
    for (const files of bodies.values()) files.sort((a, b) => a.step - b.step);
    const frames = steps.map((step) => ({
      time: step,
      label: `step ${step}`,
      files: [...bodies.values()].map((files) => files.filter((f) => f.step <= step).at(-1)?.path).filter(Boolean),
    }));
    const names = [...bodies.keys()].sort();
    series.push({
      name: `${folder}${names.length > 3 ? `${names[0]} ... ${names.at(-1)}` : names.join(', ')} (${names.length} bodies, ${steps.length} steps)`,
      frames,
      members: new Set([...bodies.values()].flat().map((f) => f.path)),
    });
  }
  return series;
}
