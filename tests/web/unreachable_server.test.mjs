// When the server goes away the page says so, and it reconnects by itself when it is back.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { startBrowser, startServer, waitForTriangles, WAIT_MS } from './harness.mjs';

let server;
let browser;
before(async () => {
  server = await startServer();
  browser = await startBrowser();
});
after(async () => {
  await browser?.close();
  await server?.stop();
});

test('an unreachable server shows a message, and the page reconnects', async () => {
  const page = await browser.newPage(`${server.url}/`);
  const shown = await waitForTriangles(page, (n) => n > 0, 'shown');
  const status = page.getByTestId('status');

  const { httpPort } = server;
  await server.stop();
  await status.filter({ hasText: /Cannot reach the ddsimp server/ }).waitFor({ timeout: WAIT_MS });
  assert.equal(await status.getAttribute('data-state'), 'unreachable');
  // What was shown stays shown meanwhile.
  assert.equal(await waitForTriangles(page, (n) => n === shown, 'unchanged'), shown);

  server = await startServer({ httpPort });
  await status.filter({ hasText: /^Connected/ }).waitFor({ timeout: WAIT_MS });
  await waitForTriangles(page, (n) => n === shown, 'shown again');
  assert.deepEqual(page.errors, []);
});
