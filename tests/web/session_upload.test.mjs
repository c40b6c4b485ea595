// Another kind of client steers a page's session: a tool on the native port joins the session
// and uploads a new surface into it; the page lists it, switches to it and shows it.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { test } from 'node:test';
import { requireFromWeb, serverAndBrowser, WAIT_MS, waitForTriangles } from './harness.mjs';

const protobuf = requireFromWeb('protobufjs');
const schema = protobuf.parse(readFileSync(path.join(process.env.DDSIMP_WEB_SRC,
  '../protocol/proto/ddsimp/v1/ddsimp.proto'), 'utf8'), { keepCase: true }).root;
const TYPES = { Hello: 1, Welcome: 2, Error: 5, JoinSession: 10, SessionState: 13,
  UploadBegin: 20, UploadChunk: 21, UploadEnd: 22, UploadResult: 23 }; // docs/protocol.md

// A minimal native-protocol client: frames over TCP, one message at a time.
class NativeClient {
  constructor(port) {
    this.socket = net.connect(port, '127.0.0.1');
    this.buffer = Buffer.alloc(0);
    this.waiting = [];
    this.frames = [];
    this.socket.on('data', (d) => {
      this.buffer = Buffer.concat([this.buffer, d]);
      while (this.buffer.length >= 12 && this.buffer.length >= 12 + this.buffer.readUInt32LE(8)) {
        const type = this.buffer.readUInt16LE(6);
        const payload = this.buffer.subarray(12, 12 + this.buffer.readUInt32LE(8));
        this.buffer = this.buffer.subarray(12 + payload.length);
        const name = Object.keys(TYPES).find((k) => TYPES[k] === type);
        if (name) this.frames.push({ name, message: schema.lookupType(`ddsimp.v1.${name}`)
          .toObject(schema.lookupType(`ddsimp.v1.${name}`).decode(payload), { longs: Number }) });
        this.wake();
      }
    });
  }

  send(name, fields) {
    const type = schema.lookupType(`ddsimp.v1.${name}`);
    const payload = type.encode(type.fromObject(fields)).finish();
    const header = Buffer.alloc(12);
    header.write('DDSP', 0, 'latin1');
    header.writeUInt16LE(1, 4);
    header.writeUInt16LE(TYPES[name], 6);
    header.writeUInt32LE(payload.length, 8);
    this.socket.write(Buffer.concat([header, payload]));
  }

  wake() {
    for (const w of this.waiting.splice(0)) w();
  }

  // The next message called `name` (others are skipped); an Error fails.
  async next(name) {
    for (;;) {
      const i = this.frames.findIndex((f) => f.name === name || f.name === 'Error');
      if (i >= 0) {
        const [f] = this.frames.splice(i, 1);
        if (f.name === 'Error') throw new Error(`the server says: ${f.message.message}`);
        return f.message;
      }
      await new Promise((resolve) => this.waiting.push(resolve));
    }
  }
}

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
