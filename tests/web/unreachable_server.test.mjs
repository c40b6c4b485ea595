// When the server goes away the page says so, and it reconnects by itself when it is back.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, startServer, WAIT_MS, waitForTriangles } from './harness.mjs';

const env = serverAndBrowser();

test('an unreachable server shows a message, and the page reconnects', async () => {
  const page = await env.browser.newPage(`${env.server.url}/`);
  // The exact level (a preview may come first): half of the sample's 756 triangles, at least 376
  // (an edge collapse removes at most two).
  const shown = await waitForTriangles(page, (n) => n >= 376 && n <= 378, 'the exact level');
  const status = page.getByTestId('status');

  const { httpPort } = env.server;
  await env.server.stop();
  await status.filter({ hasText: /Cannot reach the ddsimp server/ }).waitFor({ timeout: WAIT_MS });
  assert.equal(await status.getAttribute('data-state'), 'unreachable');
  // What was shown stays shown meanwhile.
  assert.equal(await waitForTriangles(page, (n) => n === shown, 'unchanged'), shown);

  env.server = await startServer({ httpPort });
  await status.filter({ hasText: /^Connected/ }).waitFor({ timeout: WAIT_MS });
  await waitForTriangles(page, (n) => n === shown, 'shown again');
  assert.deepEqual(page.errors, []);
});
