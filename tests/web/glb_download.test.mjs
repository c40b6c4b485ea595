// GET /surfaces/ID/level.glb: a level of a stored surface as binary glTF, behind the server's
// token; Khronos's validator finds no error in it and three.js loads it. Bad requests get a
// status and a reason, and the server goes on.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { startServer } from './harness.mjs';
import { loadWithThree, validateGlb } from './glb_support.mjs';

const TOKEN = 's3cret';
const sample = path.join(process.env.DDSIMP_WEB_SRC, '../data/SurfaceVectors.vtk');
let server;
let surface;

before(async () => {
  server = await startServer({ extraArgs: ['--token', TOKEN] });
  const uploaded = JSON.parse(execFileSync(process.env.DDSIMP_CLI, ['remote', 'upload', sample,
    '--server', `127.0.0.1:${server.port}`, '--token', TOKEN], { encoding: 'utf8' }));
  surface = uploaded.surface;
  assert.equal(uploaded.triangles, 756);
});
after(async () => server?.stop());

async function get(query, headers = {}) {
  const res = await fetch(`${server.url}/surfaces/${surface}/level.glb?${query}`, { headers });
  return { status: res.status, type: res.headers.get('content-type'),
    disposition: res.headers.get('content-disposition'),
    bytes: new Uint8Array(await res.arrayBuffer()) };
}

test('a level downloads as valid glTF that three.js loads, finer levels with more triangles',
  async () => {
    const coarse = await get(`alpha=0.5&keep=0.2&token=${TOKEN}`);
    assert.equal(coarse.status, 200, new TextDecoder().decode(coarse.bytes));
    assert.equal(coarse.type, 'model/gltf-binary');
    assert.match(coarse.disposition, /attachment; filename=".*\.glb"/);
    const report = await validateGlb(coarse.bytes, 'keep 0.2');
    const triangles = report.info.totalTriangleCount;
    assert.ok(triangles > 0 && triangles <= Math.floor(0.2 * 756), `${triangles} triangles`);

    const mesh = await loadWithThree(coarse.bytes);
    assert.equal(mesh.geometry.index.count, 3 * triangles);
    assert.ok(mesh.geometry.attributes._pres && mesh.geometry.attributes.color);

    const fine = await get(`alpha=0.5&keep=0.6&strategy=vertex`,
      { authorization: `Bearer ${TOKEN}` });
    assert.equal(fine.status, 200);
    const fineReport = await validateGlb(fine.bytes, 'keep 0.6, vertex removal');
    assert.ok(fineReport.info.totalTriangleCount > triangles);
    assert.ok(fineReport.info.totalTriangleCount <= Math.floor(0.6 * 756));
  });

test('meshopt=1 and field=NAME: compressed, coloured by that field', async () => {
  const r = await get(`keep=0.5&meshopt=1&field=V&token=${TOKEN}`);
  assert.equal(r.status, 200);
  const report = await validateGlb(r.bytes, 'meshopt');
  assert.deepEqual(report.info.extensionsRequired, ['EXT_meshopt_compression']);
  const mesh = await loadWithThree(r.bytes);
  assert.equal(mesh.userData.colour_field, 'V');
  assert.equal(mesh.geometry.index.count, 3 * report.info.totalTriangleCount);
  // The same request gives the same bytes.
  assert.deepEqual((await get(`keep=0.5&meshopt=1&field=V&token=${TOKEN}`)).bytes, r.bytes);
});

test('without the token, with a wrong one, or with bad parameters: refused with the reason',
  async () => {
    const text = (r) => new TextDecoder().decode(r.bytes);
    let r = await get('keep=0.5');
    assert.equal(r.status, 401);
    assert.match(text(r), /needs a token/);
    r = await get('keep=0.5&token=nope');
    assert.equal(r.status, 401);
    r = await get(`keep=2&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /keep=2 is not a number in \(0, 1\]/);
    r = await get(`keep=0.5&strategy=best&token=${TOKEN}`);
    assert.equal(r.status, 400);
    r = await get(`keep=0.5&data=mean&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /data=mean: least-error or interpolated/);
    r = await get(`keep=0.5&terms=best&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /terms=best: quadrics or paper/);
    r = await get(`keep=0.5&feature-angle=0&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /feature-angle=0 is not a number of degrees in \(0, 180\]/);
    r = await get(`keep=0.5&fields=${Array.from({ length: 65 }, (_, i) => `f${i}`)}&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /fields: more than 64 fields/);
    r = await get(`keep=0.5&field=nothing&token=${TOKEN}`);
    assert.equal(r.status, 400);
    assert.match(text(r), /no field 'nothing'/);
    const missing = await fetch(`${server.url}/surfaces/${'0'.repeat(64)}/level.glb?token=${TOKEN}`);
    assert.equal(missing.status, 404);
    // The server goes on.
    assert.equal(await (await fetch(`${server.url}/healthz`)).text(), 'ok\n');
  });
