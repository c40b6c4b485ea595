// End-to-end harness for the browser renderer: a real ddsimp-server on free loopback ports
// serving the built page (--web-dir), and Debian's headless Chromium driven by playwright-core.
//
// Environment (set by tests/web/CMakeLists.txt):
//   DDSIMP_SERVER    the ddsimp-server binary
//   DDSIMP_WEB_DIST  the built page (vite build output)
//   DDSIMP_WEB_SRC   web/ (its node_modules hold playwright-core and pngjs)
//   DDSIMP_CHROMIUM  the browser (/usr/bin/chromium)
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { createRequire } from 'node:module';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { after, before } from 'node:test';

function required(name) {
  const value = process.env[name];
  if (!value) throw new Error(`${name} is not set (run these tests through ctest)`);
  return value;
}

const webSrc = required('DDSIMP_WEB_SRC');
export const requireFromWeb = createRequire(path.join(webSrc, 'package.json'));
export const { chromium } = requireFromWeb('playwright-core');
export const { PNG } = requireFromWeb('pngjs');

// How long a page may take to show what a test waits for. A limit on waiting, not a speed
// claim: SwiftShader renders on the CPU of a shared machine.
export const WAIT_MS = 60_000;

export async function freePort() {
  return new Promise((resolve, reject) => {
    const server = net.createServer();
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const { port } = server.address();
      server.close(() => resolve(port));
    });
  });
}

async function accepts(port) {
  return new Promise((resolve) => {
    const socket = net.connect(port, '127.0.0.1');
    socket.once('connect', () => {
      socket.destroy();
      resolve(true);
    });
    socket.once('error', () => resolve(false));
  });
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// The 756-triangle plane the tests start the server with (data/README.md): small and quick.
export const planeSample = () => path.join(required('DDSIMP_WEB_SRC'), '../data/SurfaceVectors.ddsurf');

// A ddsimp-server child with a sample and the built page. `sample`: a surface file, the plane by
// default, null for the server's own built-in sample (the carotid). `httpPort` may be given to
// start a server again where an earlier one listened.
export async function startServer({ extraArgs = [], httpPort, webDir, sample } = {}) {
  const dataDir = mkdtempSync(path.join(os.tmpdir(), 'ddsimp-web-test-'));
  const port = await freePort();
  httpPort ??= await freePort();
  if (sample === undefined) sample = planeSample();
  const args = ['--port', String(port), '--http-port', String(httpPort), '--data-dir', dataDir,
    '--web-dir', webDir ?? required('DDSIMP_WEB_DIST'), '--log-level', 'warn',
    // Speculation keeps the server busy after every upload; the service's own tests cover it.
    ...(extraArgs.includes('--speculate') ? [] : ['--speculate', 'false']),
    ...(sample === null ? [] : ['--sample', sample]), ...extraArgs];
  const child = spawn(required('DDSIMP_SERVER'), args, { stdio: ['ignore', 'inherit', 'inherit'] });
  let exited = null;
  child.once('exit', (code, signal) => { exited = { code, signal }; });
  for (let i = 0; i < 400 && !(await accepts(httpPort)); ++i) {
    if (exited) throw new Error(`ddsimp-server exited at start: ${JSON.stringify(exited)}`);
    await sleep(50);
  }
  if (!(await accepts(httpPort))) throw new Error('ddsimp-server did not listen');
  return {
    url: `http://127.0.0.1:${httpPort}`,
    port,
    httpPort,
    async stop() {
      if (!exited) {
        const gone = new Promise((resolve) => child.once('exit', resolve));
        child.kill('SIGTERM');
        await gone;
      }
      rmSync(dataDir, { recursive: true, force: true });
    },
  };
}

// Headless Chromium as the probe of this machine kind starts it (see README, "Tests"), with
// WebGL on SwiftShader, and a fresh profile.
export async function startBrowser() {
  const profile = mkdtempSync(path.join(os.tmpdir(), 'ddsimp-web-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: required('DDSIMP_CHROMIUM'),
    headless: true,
    viewport: { width: 1000, height: 700 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  return {
    context,
    // initScript, if given, runs in the page before its own scripts.
    async newPage(url, { initScript } = {}) {
      const page = await context.newPage();
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      page.errors = errors;
      if (initScript) await page.addInitScript(initScript);
      await page.goto(url);
      return page;
    },
    async close() {
      await context.close();
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

// The number the page shows as its triangle count, or NaN before it shows one.
export async function triangleCount(page) {
  return Number.parseInt(await page.getByTestId('triangle-count').textContent(), 10);
}

// Waits until the page shows an exact level (not a preview) whose triangle count satisfies `ok`;
// returns the count. A preview may satisfy `ok` too, but its error and fields are not the level's.
export async function waitForTriangles(page, ok, what) {
  const deadline = Date.now() + WAIT_MS;
  let n = NaN;
  while (Date.now() < deadline) {
    // Both read at once: the level shown may change between two reads.
    const shown = await page.evaluate(() => ({
      n: Number.parseInt(document.querySelector('[data-testid="triangle-count"]').textContent, 10),
      preview: document.querySelector('[data-testid="exactness"]').dataset.preview === 'true',
    }));
    n = shown.n;
    if (ok(n) && !shown.preview) return n;
    await sleep(100);
  }
  const status = await page.getByTestId('status').textContent();
  const notice = await page.getByTestId('notice').textContent();
  throw new Error(`the triangle count never became ${what} (last ${n}; status "${status}"; ` +
    `notice "${notice}"; page errors ${JSON.stringify(page.errors)})`);
}

// Sets a range input as a user would end a drag: the value, then input and change events.
export async function setRange(page, testId, value) {
  await page.getByTestId(testId).evaluate((input, v) => {
    input.value = String(v);
    input.dispatchEvent(new Event('input', { bubbles: true }));
    input.dispatchEvent(new Event('change', { bubbles: true }));
  }, value);
}

// For the tests of one file: a server (started with `serverOptions`) and a browser, started
// before the first test and stopped after the last. A test may replace `env.server`.
export function serverAndBrowser(serverOptions = {}) {
  const env = {};
  before(async () => {
    env.server = await startServer(serverOptions);
    env.browser = await startBrowser();
  });
  after(async () => {
    await env.browser?.close();
    await env.server?.stop();
  });
  return env;
}
