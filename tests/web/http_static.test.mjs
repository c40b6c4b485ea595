// The server's static files: the built page at / (also with a query), its assets with the
// right types, nothing outside the web directory, and a page that says how to build the
// renderer when --web-dir has none. No browser: plain HTTP.
import assert from 'node:assert/strict';
import { readdirSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { startServer } from './harness.mjs';

let server;
let empty;
before(async () => {
  server = await startServer();
  empty = await startServer({ webDir: path.join(process.env.DDSIMP_WEB_DIST, 'no-such-dir') });
});
after(async () => {
  await server?.stop();
  await empty?.stop();
});

// A request with the target exactly as written (fetch would normalise "..").
async function rawGet(port, target) {
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, '127.0.0.1');
    let text = '';
    socket.on('data', (d) => { text += d; });
    socket.on('end', () => resolve(text));
    socket.on('error', reject);
    socket.write(`GET ${target} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`);
  });
}

test('the page, with or without a query, and its assets', async () => {
  for (const target of ['/', '/?session=abc&token=t']) {
    const res = await fetch(server.url + target);
    assert.equal(res.status, 200);
    assert.equal(res.headers.get('content-type'), 'text/html; charset=utf-8');
    assert.equal(res.headers.get('cache-control'), 'no-cache');
    assert.match(await res.text(), /data-testid="triangle-count"/);
  }
  const assets = readdirSync(path.join(process.env.DDSIMP_WEB_DIST, 'assets'));
  const script = assets.find((f) => f.endsWith('.js'));
  const res = await fetch(`${server.url}/assets/${script}`);
  assert.equal(res.status, 200);
  assert.equal(res.headers.get('content-type'), 'text/javascript; charset=utf-8');
  assert.match(res.headers.get('cache-control'), /immutable/);
  assert.equal((await fetch(`${server.url}/assets/`)).status, 404); // a directory
  assert.equal((await fetch(`${server.url}/nothing.js`)).status, 404);
});

test('nothing outside the web directory', async () => {
  for (const target of ['/../index.html', '/assets/../../CMakeCache.txt', '/%2e%2e/x'])
    assert.match(await rawGet(server.httpPort, target), /^HTTP\/1\.1 404/, target);
});

test('without a built page, / says how to build it', async () => {
  const res = await fetch(`${empty.url}/`);
  assert.equal(res.status, 200);
  const text = await res.text();
  assert.match(text, /no index\.html in .*no-such-dir/);
  assert.match(text, /npm ci &amp;&amp; npm run build/);
  assert.equal((await fetch(`${empty.url}/assets/x.js`)).status, 404);
});
