// Makes docs/images/web-renderer.png: the page showing the server's built-in sample, reduced to
// 5 % with the triangles' edges, in headless Chromium (playwright-core) against a real server,
// as the browser tests run them. From a configured release build (ctest -R web_build makes the
// page):
//   B=build/release; DDSIMP_SERVER=$B/server/ddsimp-server DDSIMP_WEB_DIST=$B/tests/web/dist \
//   DDSIMP_WEB_SRC=$PWD/web DDSIMP_CHROMIUM=/usr/bin/chromium node scripts/web-screenshot.mjs [OUT]
import { fileURLToPath } from 'node:url';
import { setRange, startBrowser, startServer, waitForTriangles } from '../tests/web/harness.mjs';

const out = process.argv[2] ??
  fileURLToPath(new URL('../docs/images/web-renderer.png', import.meta.url));
const server = await startServer({ sample: null });
const browser = await startBrowser();
try {
  const page = await browser.newPage(server.url);
  await page.setViewportSize({ width: 1200, height: 940 }); // the whole panel, legend included
  await waitForTriangles(page, (n) => n > 0, 'the sample');
  await setRange(page, 'level', 0.05);
  await page.getByTestId('edges').check();
  // The level itself (about 10,900 triangles), after the coarser ones before it.
  await waitForTriangles(page, (n) => n > 10000 && n < 12000, 'the sample at 5 %');
  await page.getByTestId('progress').waitFor({ state: 'hidden' });
  await page.waitForTimeout(500); // the last frame drawn
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
  await server.stop();
}
