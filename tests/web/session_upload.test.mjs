// Another kind of client steers a page's session: a tool on the native port joins the session
// and uploads a new surface into it; the page lists it, switches to it and shows it.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, WAIT_MS, waitForTriangles } from './harness.mjs';
import { NativeClient } from './native_client.mjs';

const env = serverAndBrowser();

test('a surface uploaded into the session by a tool appears on the page', async () => {
  const page = await env.browser.newPage(`${env.server.url}/?session=up`);
  await waitForTriangles(page, (n) => n > 0, 'the sample shown');

  // A 3 x 3 grid of vertices, 8 triangles, with a field h = x + 2y.
  const positions = [];
  const h = [];
  for (let y = 0; y < 3; ++y)
    for (let x = 0; x < 3; ++x) {
      positions.push(x, y, 0);
      h.push(x + 2 * y);
    }
  const triangles = [];
  for (let y = 0; y < 2; ++y)
    for (let x = 0; x < 2; ++x) {
      const v = 3 * y + x;
      triangles.push(v, v + 1, v + 4, v, v + 4, v + 3);
    }
  const blob = Buffer.concat([Buffer.from(new Float32Array(positions).buffer),
    Buffer.from(new Uint32Array(triangles).buffer), Buffer.from(new Float32Array(h).buffer)]);

  const tool = new NativeClient(env.server.port);
  tool.send('Hello', { protocol_version: 1, client_name: 'web test tool', kind: 3,
    capabilities: ['sessions'] });
  await tool.next('Welcome');
  tool.send('JoinSession', { name: 'up' });
  await tool.next('SessionState');
  tool.send('UploadBegin', { upload_id: 1, name: 'grid', vertex_count: 9, triangle_count: 8,
    fields: [{ name: 'h', components: 1 }], total_bytes: blob.length, session: 'up' });
  tool.send('UploadChunk', { upload_id: 1, offset: 0, data: blob });
  tool.send('UploadEnd', { upload_id: 1 });
  const uploaded = await tool.next('UploadResult');
  assert.equal(uploaded.triangles, 8);

  // The page follows: the new surface, its only field, and at most its 8 triangles.
  const surface = page.getByTestId('surface');
  const deadline = Date.now() + WAIT_MS;
  while ((await surface.inputValue()) !== uploaded.surface && Date.now() < deadline)
    await new Promise((resolve) => setTimeout(resolve, 100));
  assert.equal(await surface.inputValue(), uploaded.surface);
  await page.locator('#triangles-of').filter({ hasText: /^8$/ }).waitFor({ timeout: WAIT_MS });
  await waitForTriangles(page, (n) => n > 0 && n <= 8, 'at most 8');
  assert.equal(await page.getByTestId('field').inputValue(), 'h');
  assert.equal(await page.locator('#legend .legend-title').textContent(), 'h');
  assert.equal(await page.locator('#legend .legend-max').textContent(), '6'); // 2 + 2 * 2
  tool.socket.destroy();
  assert.deepEqual(page.errors, []);
});
