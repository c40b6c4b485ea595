// While the server computes the exact level, the page shows the preview it sent at once and says
// so; the exact level then replaces it and the label says that too.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, WAIT_MS, waitForTriangles } from './harness.mjs';
import { NativeClient } from './native_client.mjs';

const env = serverAndBrowser();

// A wavy n x n grid of vertices (2 (n-1)^2 triangles) with a field h: large enough that its
// exact levels take the server a while, so the preview is shown first.
function grid(n) {
  const positions = new Float32Array(3 * n * n);
  const h = new Float32Array(n * n);
  for (let y = 0; y < n; ++y)
    for (let x = 0; x < n; ++x) {
      const v = n * y + x;
      positions.set([x, y, 3 * Math.sin(x / 9) * Math.cos(y / 7)], 3 * v);
      h[v] = Math.sin(x / 5) + y / n;
    }
  const triangles = new Uint32Array(6 * (n - 1) * (n - 1));
  let t = 0;
  for (let y = 0; y + 1 < n; ++y)
    for (let x = 0; x + 1 < n; ++x) {
      const v = n * y + x;
      triangles.set([v, v + 1, v + n + 1, v, v + n + 1, v + n], t);
      t += 6;
    }
  return { vertices: n * n, triangles: triangles.length / 3,
    blob: Buffer.concat([Buffer.from(positions.buffer), Buffer.from(triangles.buffer),
      Buffer.from(h.buffer)]) };
}

function recordExactness() {
  window.exactnessSeen = [];
  const record = () => {
    const label = document.getElementById('exactness');
    if (!label || !label.dataset.preview) return;
    const last = window.exactnessSeen.at(-1);
    const now = { preview: label.dataset.preview, text: label.textContent };
    if (!last || last.preview !== now.preview || last.text !== now.text)
      window.exactnessSeen.push(now);
  };
  new MutationObserver(record).observe(document, { subtree: true, childList: true,
    characterData: true, attributes: true });
}

test('a preview is labelled as such until the exact level replaces it', async () => {
  const surface = grid(300);
  const tool = new NativeClient(env.server.port);
  tool.send('Hello', { protocol_version: 1, client_name: 'web test tool', kind: 3 });
  await tool.next('Welcome');
  tool.send('UploadBegin', { upload_id: 1, name: 'wavy grid', vertex_count: surface.vertices,
    triangle_count: surface.triangles, fields: [{ name: 'h', components: 1 }],
    total_bytes: surface.blob.length });
  const chunk = 1 << 20;
  for (let offset = 0; offset < surface.blob.length; offset += chunk)
    tool.send('UploadChunk', { upload_id: 1, offset,
      data: surface.blob.subarray(offset, offset + chunk) });
  tool.send('UploadEnd', { upload_id: 1 });
  const uploaded = await tool.next('UploadResult');
  tool.socket.destroy();

  // Every state the label passes through, read after each task of the page: a fast server's
  // exact level may replace the preview before a poll from here would see it.
  const page = await env.browser.newPage(`${env.server.url}/?surface=${uploaded.surface}`,
    { initScript: recordExactness });
  const exact = (s) => s.preview === 'false' && s.text !== '–'; // '–': nothing shown yet
  await page.waitForFunction(() => window.exactnessSeen.some(
    (s) => s.preview === 'false' && s.text !== '–'), null, { timeout: WAIT_MS });
  const seen = await page.evaluate(() => window.exactnessSeen);
  const firstExact = seen.findIndex(exact);
  assert.ok(firstExact > 0, `a preview is shown before the exact level: ${JSON.stringify(seen)}`);
  assert.equal(seen[firstExact - 1].preview, 'true');
  assert.match(seen[firstExact - 1].text, /^a preview \(.*\); the exact level follows$/);
  assert.equal(seen[firstExact].text, 'the exact level');
  // The exact level asked for: half the triangles (an edge collapse removes at most two).
  const half = Math.floor(surface.triangles / 2);
  await waitForTriangles(page, (n) => n >= half - 2 && n <= half, `about ${half}`);
  assert.deepEqual(page.errors, []);
});
