// The error of the level shown (MeshBegin.error) stands next to the triangle count, in % of the
// diagonal and of the range, and grows when the level is lowered; the page asks for the
// least-error placement unless told otherwise.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, setRange, waitForTriangles } from './harness.mjs';

const env = serverAndBrowser();

async function shownError(page) {
  const el = page.getByTestId('level-error');
  return {
    text: await el.textContent(),
    geometric: Number(await el.getAttribute('data-geometric')),
    data: Number(await el.getAttribute('data-data')),
  };
}

// The percentages the text shows, in the order shown.
function percentages(text) {
  return [...text.matchAll(/([0-9.e+-]+)% of (diagonal|range)/g)].map((m) => Number(m[1]));
}

test('a lower level shows a larger error, in % of the diagonal and of the range', async () => {
  const page = await env.browser.newPage(env.server.url);
  assert.equal(await page.getByTestId('placement').inputValue(), '3'); // LEAST_ERROR
  // The page's default level: half of the sample's 756 triangles.
  const before = await waitForTriangles(page, (n) => n > 300 && n <= 378, 'at most 378');
  const coarse = await shownError(page);
  assert.match(coarse.text, /% of diagonal \(geometry\), .*% of range \(data\)/);
  // The sample is a plane: its geometry survives exactly, its data does not.
  assert.ok(coarse.geometric >= 0 && coarse.geometric < 1e-6, coarse.text);
  assert.ok(coarse.data > 0 && coarse.data < 1, coarse.text);
  const [geometricPercent, dataPercent] = percentages(coarse.text);
  // Two significant digits of the numbers the server sent.
  assert.equal(geometricPercent, 0, coarse.text);
  assert.ok(Math.abs(dataPercent - 100 * coarse.data) <= 0.05 * 100 * coarse.data,
    `${coarse.text} vs ${coarse.data}`);

  await setRange(page, 'level', 0.1);
  // floor(0.1 * 756) = 75 triangles at most.
  const after = await waitForTriangles(page, (n) => n <= 75, 'at most 75');
  const coarser = await shownError(page);
  assert.ok(after < before);
  assert.ok(coarser.geometric >= coarse.geometric,
    `geometric error ${coarse.geometric} at ${before} triangles, ${coarser.geometric} at ${after}`);
  assert.ok(coarser.data > coarse.data,
    `data error ${coarse.data} at ${before} triangles, ${coarser.data} at ${after}`);
  assert.deepEqual(page.errors, []);
});
