// A perceptually ordered colour map (dark blue -> teal -> green -> yellow, after the shape of
// matplotlib's viridis, sampled at five points and interpolated linearly) and the colour bar.
const stops = [
  [0.267, 0.005, 0.329], [0.231, 0.322, 0.545], [0.129, 0.569, 0.549], [0.369, 0.788, 0.384], [0.993, 0.906, 0.144],
];

// Writes the colour of value t in [0, 1] into out[offset..offset+2]; grey where there is no value
// (NaN: a body without the chosen field).
export function colorAt(t, out, offset) {
  if (Number.isNaN(t)) {
    out[offset] = out[offset + 1] = out[offset + 2] = 0.72;
    return;
  }
  const x = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x));
  const f = x - i;
  for (let k = 0; k < 3; ++k) out[offset + k] = stops[i][k] * (1 - f) + stops[i + 1][k] * f;
}

export function formatNumber(v) {
  if (!Number.isFinite(v)) return String(v);
  const a = Math.abs(v);
  return a !== 0 && (a >= 1e4 || a < 1e-3) ? v.toExponential(3) : v.toPrecision(4);
}

// Shows the bar for `name` over [min, max].
export function showColorBar(name, min, max) {
  const css = stops.map((c, i) => `rgb(${c.map((x) => Math.round(255 * x)).join(',')}) ${(100 * i) / (stops.length - 1)}%`);
  document.getElementById('colorbar-gradient').style.background = `linear-gradient(to right, ${css.join(', ')})`;
  document.getElementById('colorbar-min').textContent = formatNumber(min);
  document.getElementById('colorbar-max').textContent = formatNumber(max);
  document.getElementById('colorbar-name').textContent = name;
}
