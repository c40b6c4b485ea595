// The colour map (matplotlib's viridis: perceptually uniform, readable in grey and by most colour
// blind viewers) and the legend that explains it.

// viridis at i/16, i = 0..16, as matplotlib 3.6 gives it (sRGB).
const VIRIDIS = [
  0x440154, 0x48186a, 0x472d7b, 0x424086, 0x3b528b, 0x33638d, 0x2c728e, 0x26828e, 0x21918c,
  0x1fa088, 0x28ae80, 0x3fbc73, 0x5ec962, 0x84d44b, 0xaddc30, 0xd8e219, 0xfde725,
].map((c) => [(c >> 16) / 255, ((c >> 8) & 0xff) / 255, (c & 0xff) / 255]);

// The sRGB colour (components in [0, 1]) of t in [0, 1]; t outside is clamped, NaN is grey.
export function viridis(t) {
  if (Number.isNaN(t)) return [0.5, 0.5, 0.5];
  const x = Math.min(1, Math.max(0, t)) * (VIRIDIS.length - 1);
  const i = Math.min(VIRIDIS.length - 2, Math.floor(x));
  const f = x - i;
  const a = VIRIDIS[i];
  const b = VIRIDIS[i + 1];
  return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
}

// Numbers for the legend: short, and the same digits for the same magnitude.
export function formatValue(v) {
  if (!Number.isFinite(v)) return String(v);
  const a = Math.abs(v);
  if (a !== 0 && (a < 1e-3 || a >= 1e5)) return v.toExponential(2);
  return Number(v.toPrecision(4)).toString();
}

// Draws the bar and writes the labels of a legend element built by index.html.
export function drawLegend(legend, { title, min, max, note }) {
  const canvas = legend.querySelector('canvas');
  const ctx = canvas.getContext('2d');
  for (let x = 0; x < canvas.width; ++x) {
    const [r, g, b] = viridis(x / (canvas.width - 1));
    ctx.fillStyle = `rgb(${Math.round(255 * r)},${Math.round(255 * g)},${Math.round(255 * b)})`;
    ctx.fillRect(x, 0, 1, canvas.height);
  }
  legend.querySelector('.legend-title').textContent = title;
  legend.querySelector('.legend-min').textContent = formatValue(min);
  legend.querySelector('.legend-mid').textContent = formatValue((min + max) / 2);
  legend.querySelector('.legend-max').textContent = formatValue(max);
  legend.querySelector('.legend-note').textContent = note ?? '';
  legend.hidden = false;
}
