// `ddsimp simplify -o out.glb` writes files that Khronos's glTF-Validator accepts without an error
// and that three.js's GLTFLoader loads: the level's triangles, normals, colours and every field.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, test } from 'node:test';
import { loadWithThree, validateGlb } from './glb_support.mjs';

const cli = process.env.DDSIMP_CLI;
const sample = path.join(process.env.DDSIMP_WEB_SRC, '../data/SurfaceVectors.vtk');
const dir = mkdtempSync(path.join(os.tmpdir(), 'ddsimp-glb-test-'));
after(() => rmSync(dir, { recursive: true, force: true }));

function simplifyToGlb(name, extra) {
  const out = path.join(dir, name);
  const report = JSON.parse(execFileSync(cli, ['simplify', sample, '-o', out, '--keep', '0.3',
    '--json', ...extra], { encoding: 'utf8' }));
  return { bytes: readFileSync(out), triangles: report.triangles_out };
}

for (const [name, extra] of [['plain.glb', []], ['meshopt.glb', ['--meshopt', '--colour-by', 'V']]]) {
  test(`${name}: valid glTF that three.js loads with every field`, async () => {
    const { bytes, triangles } = simplifyToGlb(name, extra);
    const report = await validateGlb(bytes, name);
    assert.equal(report.info.totalTriangleCount, triangles);
    if (extra.includes('--meshopt'))
      assert.deepEqual(report.info.extensionsRequired, ['EXT_meshopt_compression']);

    const mesh = await loadWithThree(bytes);
    const g = mesh.geometry;
    assert.equal(g.index.count, 3 * triangles);
    for (const a of ['position', 'normal', 'color', '_v', '_temp', '_pres', '_ash3', '_game3',
      '_ch4', '_h2'])
      assert.ok(g.attributes[a], `attribute ${a} (has ${Object.keys(g.attributes)})`);
    assert.equal(g.attributes._v.itemSize, 3);
    assert.equal(g.attributes.position.count, g.attributes._temp.count);
    assert.equal(mesh.material.vertexColors, true);
    const extras = mesh.userData; // the mesh's extras
    assert.equal(extras.colour_field, extra.includes('V') ? 'V' : 'Temp');
    // The colours are viridis between its ends: never grey, never outside [0, 1].
    const c = g.attributes.color.array;
    assert.ok(c.every((x) => x >= 0 && x <= 1));
    assert.ok(new Set(Array.from(c.subarray(0, 300), (x) => x.toFixed(3))).size > 10,
      'the colours vary over the surface');
  });
}
