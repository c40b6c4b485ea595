// A lower level shows fewer triangles; the page authenticates with ?token= and says so when
// the token is missing.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import {
  serverAndBrowser, setRange, triangleCount, WAIT_MS, waitForTriangles,
} from './harness.mjs';

const env = serverAndBrowser({ extraArgs: ['--token', 's3cret'] });

test('lowering the level lowers the triangle count', async () => {
  const page = await env.browser.newPage(`${env.server.url}/?token=s3cret`);
  const before = await waitForTriangles(page, (n) => n > 300, 'shown');
  await setRange(page, 'level', 0.1);
  // floor(0.1 * 756) = 75 triangles at most.
  const after = await waitForTriangles(page, (n) => n <= 75, 'at most 75');
  assert.ok(after > 0 && after < before, `${before} -> ${after}`);
  assert.equal(await page.getByTestId('level').inputValue(), '0.1');
  assert.deepEqual(page.errors, []);
});

test('without the token the page says that it needs one', async () => {
  const page = await env.browser.newPage(`${env.server.url}/`);
  const status = page.getByTestId('status');
  await status.filter({ hasText: /needs a token/ }).waitFor({ timeout: WAIT_MS });
  assert.equal(await status.getAttribute('data-state'), 'failed');
  assert.ok(Number.isNaN(await triangleCount(page)));
});
