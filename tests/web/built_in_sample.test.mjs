// A newcomer's first look: a server started without --sample shows its built-in sample, the
// carotid isosurface (data/README.md), on the page's first load, coloured by its blood velocity.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, triangleCount, WAIT_MS } from './harness.mjs';

const env = serverAndBrowser({ sample: null });

test('the built-in sample is shown on first load', async () => {
  const opened = Date.now();
  const page = await env.browser.newPage(env.server.url);
  // The first level on the screen: the server's preview, while it computes the exact levels.
  await page.waitForFunction(() => Number.parseInt(
    document.querySelector('[data-testid="triangle-count"]').textContent, 10) > 0, null,
  { timeout: WAIT_MS, polling: 50 });
  const shown = await triangleCount(page);
  console.log(`first level (${shown} triangles) on the page ${Date.now() - opened} ms after ` +
    'opening it');
  const listed = await page.evaluate(() => ({
    name: document.querySelector('#surface').selectedOptions[0].textContent,
    of: document.getElementById('triangles-of').textContent,
    field: document.querySelector('#field').value,
    legend: !document.getElementById('legend').hidden,
  }));
  assert.match(listed.name, /Carotid/);
  const total = Number.parseInt(listed.of.replaceAll(',', ''), 10);
  assert.ok(total >= 200000, `the sample has ${listed.of} triangles`);
  assert.ok(shown < total, `${shown} of ${total} triangles shown`);
  assert.equal(listed.field, 'vectors');
  assert.ok(listed.legend, 'the colour legend is shown');
  assert.deepEqual(page.errors, []);
});
