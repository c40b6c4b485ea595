// The page shows the server's built-in sample coloured by the colour map, coarse first and
// refined to the level asked for.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { PNG, serverAndBrowser, setRange, WAIT_MS, waitForTriangles } from './harness.mjs';

// matplotlib 3.6's viridis at i/8 (an independent source: `matplotlib.colormaps['viridis']`).
const VIRIDIS_9 = ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962',
  '#addc30', '#fde725'].map((h) => [1, 3, 5].map((i) => Number.parseInt(h.slice(i, i + 2), 16)));
const BACKGROUND = [0x20, 0x24, 0x28];

// The viridis curve, 8 pieces of 32 samples each.
const CURVE = [];
for (let i = 0; i < 8; ++i)
  for (let s = 0; s < 32; ++s) {
    const f = s / 32;
    CURVE.push({ piece: i,
      rgb: VIRIDIS_9[i].map((c, k) => c + f * (VIRIDIS_9[i + 1][k] - c)) });
  }

function nearestOnCurve(rgb) {
  let best = { distance: Infinity, piece: -1 };
  for (const p of CURVE) {
    const d = Math.hypot(rgb[0] - p.rgb[0], rgb[1] - p.rgb[1], rgb[2] - p.rgb[2]);
    if (d < best.distance) best = { distance: d, piece: p.piece };
  }
  return best;
}

const env = serverAndBrowser();

test('the sample appears in the colour map, refined level by level', async () => {
  // coarse=100: even this small sample arrives as a coarse level plus refinements.
  const page = await env.browser.newPage(`${env.server.url}/?coarse=100`);
  // The default level is half the triangles: floor(0.5 * 756) = 378 at most, and an edge
  // collapse removes at most two, so at least 376.
  const half = await waitForTriangles(page, (n) => n >= 376 && n <= 378, 'about half of 756');
  assert.ok(half <= 378);

  // Everything: the whole sample has 756 triangles (data/README.md). Three levels (47, 189 and
  // 756 triangles asked for) arrive, the last two as refinements of the first.
  await setRange(page, 'level', 1);
  await waitForTriangles(page, (n) => n === 756, '756');
  assert.match(await page.getByTestId('levels').textContent(), /^3 \(coarsest first/);
  assert.equal(await page.getByTestId('status').getAttribute('data-state'), 'connected');

  // The legend names the field coloured by and its range.
  const field = await page.getByTestId('field').inputValue();
  assert.equal(field, 'Temp'); // the first field that is a varying scalar
  assert.equal(await page.locator('#legend .legend-title').textContent(), 'Temp');
  const min = Number(await page.locator('#legend .legend-min').textContent());
  const max = Number(await page.locator('#legend .legend-max').textContent());
  assert.ok(min < max, `legend range ${min} .. ${max}`);

  // The picture: most of what is not background lies on the viridis curve, and the data spans
  // much of it (the temperature varies across the reactor).
  const png = PNG.sync.read(await page.locator('#view').screenshot());
  let surface = 0;
  let onCurve = 0;
  const pieces = new Set();
  for (let i = 0; i < png.data.length; i += 4) {
    const rgb = [png.data[i], png.data[i + 1], png.data[i + 2]];
    if (Math.hypot(...rgb.map((c, k) => c - BACKGROUND[k])) < 6) continue;
    ++surface;
    const near = nearestOnCurve(rgb);
    if (near.distance < 12) {
      ++onCurve;
      pieces.add(near.piece);
    }
  }
  const pixels = png.width * png.height;
  assert.ok(surface > pixels / 10, `the surface covers ${surface} of ${pixels} pixels`);
  assert.ok(onCurve > 0.8 * surface, `${onCurve} of ${surface} surface pixels are viridis colours`);
  assert.ok(pieces.size >= 5, `colours from ${pieces.size} of the colour map's 8 pieces`);
  assert.deepEqual(page.errors, []);
});

test('"Enter VR" is offered exactly where immersive-vr is supported', async () => {
  // Headless Chromium has no VR device: no button.
  const plain = await env.browser.newPage(`${env.server.url}/`);
  await waitForTriangles(plain, (n) => n > 0, 'shown');
  assert.equal(await plain.getByTestId('enter-vr').count(), 0);

  // A browser that reports immersive-vr (a stand-in for a headset's browser): the button.
  const page = await env.browser.context.newPage();
  await page.addInitScript(() => {
    Object.defineProperty(navigator, 'xr', { value: {
      isSessionSupported: async (mode) => mode === 'immersive-vr',
      requestSession: async () => { throw new Error('no headset in a test'); },
      addEventListener() {}, removeEventListener() {},
    } });
  });
  await page.goto(`${env.server.url}/`);
  await page.getByTestId('enter-vr').filter({ hasText: /ENTER VR/ }).waitFor({ timeout: WAIT_MS });
});
