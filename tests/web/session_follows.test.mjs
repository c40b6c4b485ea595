// Two pages in one session: what one changes, the other shows, controls included.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { serverAndBrowser, setRange, WAIT_MS, waitForTriangles } from './harness.mjs';

const env = serverAndBrowser();

async function waitForValue(page, testId, value) {
  const deadline = Date.now() + WAIT_MS;
  let now;
  while (Date.now() < deadline) {
    now = await page.getByTestId(testId).inputValue();
    if (now === value) return;
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  throw new Error(`${testId} stayed ${now}, expected ${value}`);
}

test('a second page in the session follows the first', async () => {
  const first = await env.browser.newPage(`${env.server.url}/?session=e2e`);
  await waitForTriangles(first, (n) => n > 0, 'shown on the first page');
  const second = await env.browser.newPage(`${env.server.url}/?session=e2e`);
  const shared = await waitForTriangles(second, (n) => n > 0, 'shown on the second page');
  assert.equal(shared, await waitForTriangles(first, (n) => n > 0, 'shown'));
  await second.getByTestId('session').filter({ hasText: /2 members/ }).waitFor({ timeout: WAIT_MS });

  // The first page steers: level and field.
  await setRange(first, 'level', 0.2);
  await first.getByTestId('field').selectOption('Pres');
  // floor(0.2 * 756) = 151 triangles at most, on both pages.
  const mine = await waitForTriangles(first, (n) => n <= 151, 'at most 151 on the first page');
  const theirs = await waitForTriangles(second, (n) => n === mine, `${mine} on the second page`);
  assert.equal(theirs, mine);
  await waitForValue(second, 'level', '0.2');
  await waitForValue(second, 'field', 'Pres');

  // And the other way round: the second page takes the lead with its change.
  await setRange(second, 'alpha', 0.8);
  await waitForValue(first, 'alpha', '0.8');
  await first.getByTestId('session').filter({ hasText: /led by/ }).waitFor({ timeout: WAIT_MS });
  assert.deepEqual(first.errors, []);
  assert.deepEqual(second.errors, []);
});

test('a session key keeps a page with another key out', async () => {
  const url = `${env.server.url}/?session=keyed`;
  const a = await env.browser.newPage(`${url}&key=k1`);
  await waitForTriangles(a, (n) => n > 0, 'shown on the first page');
  const b = await env.browser.newPage(`${url}&key=k1`);
  await waitForTriangles(b, (n) => n > 0, 'shown on the second page');
  const stranger = await env.browser.newPage(`${url}&key=other`);
  await waitForTriangles(stranger, (n) => n > 0, 'shown on the stranger\'s page');
  await a.getByTestId('session').filter({ hasText: /2 members/ }).waitFor({ timeout: WAIT_MS });
  await stranger.getByTestId('session').filter({ hasText: /1 member,/ })
    .waitFor({ timeout: WAIT_MS });

  await setRange(a, 'level', 0.3);
  await waitForValue(b, 'level', '0.3');
  // The stranger's session of the same name is another session: it did not move.
  await waitForTriangles(b, (n) => n <= 226, 'at most floor(0.3 * 756) on the second page');
  assert.equal(await stranger.getByTestId('level').inputValue(), '0.5');
  assert.match(await stranger.getByTestId('session').textContent(), /1 member,/);
});
