// Opening a file in the page (the button data-testid="upload"): a good file of each format is read
// in the browser, uploaded and shown with its triangle count (legacy .vtk: as VTK writes it, and
// ASCII and big-endian BINARY, POLYDATA and UNSTRUCTURED_GRID, both cell layouts, written byte by
// byte here, with their fields' ranges); a file that cannot be read (a truncated BINARY .vtk, a
// volume mesh, ...) gets a message that says why, and the page goes on.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, test } from 'node:test';
import { serverAndBrowser, WAIT_MS, waitForTriangles } from './harness.mjs';
import { gridFile, GRID_TRIANGLES, polyDataFile } from './vtk_legacy_files.mjs';

const env = serverAndBrowser();
const dir = mkdtempSync(path.join(os.tmpdir(), 'ddsimp-open-test-'));
after(() => rmSync(dir, { recursive: true, force: true }));
const plane = path.join(process.env.DDSIMP_WEB_SRC, '../data/SurfaceVectors.vtk');

// The plane reduced to `keep` by the command line, written as `name`: each file a different
// surface (the server stores surfaces by their content). Returns its triangle count.
function reduced(name, keep) {
  const out = JSON.parse(execFileSync(process.env.DDSIMP_CLI,
    ['simplify', plane, '-o', path.join(dir, name), '--keep', String(keep), '--json']));
  return out.triangles_out;
}

// A tetrahedron: 4 points, 4 triangles.
const TETRA_POINTS = '0 0 0\n1 0 0\n0 1 0\n0 0 1\n';
const TETRA_FACES = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

async function open(page, name) {
  await page.getByTestId('upload').setInputFiles(path.join(dir, name));
}

// The legend's range, once it shows `min` and `max` for the field `field`, chosen here.
async function showsRange(page, field, min, max) {
  await page.getByTestId('field').selectOption(field);
  const legend = page.getByTestId('legend');
  await legend.locator('.legend-title', { hasText: new RegExp(`^${field}$`) })
    .waitFor({ timeout: WAIT_MS });
  assert.deepEqual([await legend.locator('.legend-min').textContent(),
    await legend.locator('.legend-max').textContent()], [min, max], field);
}

async function waitForSurfaceNamed(page, name) {
  await page.locator('[data-testid="surface"] option:checked', { hasText: name })
    .waitFor({ state: 'attached', timeout: WAIT_MS });
}

test('a good file of each format opens and appears with its triangle count', async () => {
  const files = {
    'disk.vtp': reduced('disk.vtp', 0.9),
    'disk.ply': reduced('disk.ply', 0.8),
    'disk.obj': reduced('disk.obj', 0.7),
    'disk.off': reduced('disk.off', 0.6),
    'disk.vtk': reduced('disk.vtk', 0.5), // BINARY POLYDATA, as VTK writes it
  };
  // Legacy .vtk files written byte by byte here (vtk_legacy_files.mjs): big-endian BINARY and
  // ASCII, POLYDATA and UNSTRUCTURED_GRID, the classic cell layout and version 5.1's.
  const written = {
    'grid-poly-5.1.vtk': polyDataFile({ binary: true, newLayout: true, z: 1 }),
    'grid-binary.vtk': gridFile({ binary: true, newLayout: false, z: 2 }),
    'grid-ascii-5.1.vtk': gridFile({ binary: false, newLayout: true, z: 3 }),
  };
  for (const [name, bytes] of Object.entries(written)) {
    writeFileSync(path.join(dir, name), bytes);
    files[name] = GRID_TRIANGLES;
  }
  // Legacy ASCII POLYDATA with a point field, and ASCII STL, written here.
  writeFileSync(path.join(dir, 'tetra.vtk'), '# vtk DataFile Version 3.0\ntetra\nASCII\n' +
    `DATASET POLYDATA\nPOINTS 4 float\n${TETRA_POINTS}POLYGONS 4 16\n` +
    `${TETRA_FACES.map((f) => `3 ${f.join(' ')}`).join('\n')}\n` +
    'POINT_DATA 4\nSCALARS h float 1\nLOOKUP_TABLE default\n0 1 2 3\n');
  files['tetra.vtk'] = 4;
  const p = TETRA_POINTS.trim().split('\n');
  writeFileSync(path.join(dir, 'tetra.stl'), `solid tetra\n${TETRA_FACES.map((f) =>
    `facet normal 0 0 0\nouter loop\n${f.map((v) => `vertex ${p[v]}`).join('\n')}\nendloop\n` +
    'endfacet').join('\n')}\nendsolid tetra\n`);
  files['tetra.stl'] = 4;

  const page = await env.browser.newPage(env.server.url);
  await waitForTriangles(page, (n) => n > 0, 'the first surface shown');
  for (const [name, triangles] of Object.entries(files)) {
    await open(page, name);
    await waitForSurfaceNamed(page, name);
    await page.locator('#triangles-of').filter({ hasText: new RegExp(`^${triangles}$`) })
      .waitFor({ timeout: WAIT_MS });
    const half = Math.floor(triangles / 2);
    await waitForTriangles(page, (n) => n > 0 && n <= Math.max(half, 4),
      `at most half of ${triangles} (level 50%) for ${name}`);
    if (name === 'disk.vtp' || name === 'disk.vtk') { // its point data came along
      const fields = await page.getByTestId('field').locator('option').allTextContents();
      assert.ok(fields.includes('Temp') && fields.includes('V (|vector|)'), JSON.stringify(fields));
    }
    if (name === 'grid-poly-5.1.vtk') { // float SCALARS, double VECTORS, an int FIELD array
      const fields = await page.getByTestId('field').locator('option').allTextContents();
      assert.deepEqual(fields, ['height', 'velocity (|vector|)', 'label']);
      await showsRange(page, 'height', '0', '27');
    }
    if (name.startsWith('grid-binary') || name.startsWith('grid-ascii'))
      await showsRange(page, 'pressure', '100', '113.5');
  }
  assert.equal(await page.getByTestId('notice').isHidden(), true);
  assert.deepEqual(page.errors, []);
  await page.close();
});

test('a broken file gets a message, and the page goes on to open the next', async () => {
  const page = await env.browser.newPage(env.server.url);
  const before = await waitForTriangles(page, (n) => n > 0, 'the first surface shown');

  writeFileSync(path.join(dir, 'broken.ply'),
    'ply\nformat ascii 1.0\nelement vertex 3\nthis is not a surface\n');
  await open(page, 'broken.ply');
  const notice = page.getByTestId('notice');
  await notice.filter({ hasText: /Cannot open broken\.ply: / }).waitFor({ timeout: WAIT_MS });
  writeFileSync(path.join(dir, 'broken.off'), 'OFF\n3 1 0\n0 0 0\n1 0 0\n4 0 1 2\n');
  await open(page, 'broken.off');
  await notice.filter({ hasText: /Cannot open broken\.off: / }).waitFor({ timeout: WAIT_MS });
  // A BINARY .vtk cut off in its points, and a volume mesh.
  const grid = gridFile({ binary: true, newLayout: false, z: 4 });
  writeFileSync(path.join(dir, 'cut.vtk'), grid.subarray(0, grid.indexOf('POINTS') + 400));
  await open(page, 'cut.vtk');
  await notice.filter({ hasText: 'Cannot open cut.vtk: it ends early: POINTS announces 84 values' })
    .waitFor({ timeout: WAIT_MS });
  writeFileSync(path.join(dir, 'volume.vtk'), gridFile({ binary: true, newLayout: true,
    cells: [[10, [0, 1, 7, 8]], [12, [0, 1, 8, 7, 14, 15, 22, 21]], [12, [1, 2, 9, 8, 15, 16, 23, 22]]] }));
  await open(page, 'volume.vtk');
  await notice.filter({ hasText: /^Cannot open volume\.vtk: it holds 3-D cells \(1 tetra, 2 hexahedron\)/ })
    .waitFor({ timeout: WAIT_MS });
  assert.equal(await page.getByTestId('status').getAttribute('data-state'), 'connected');
  assert.equal(await page.getByTestId('triangle-count').textContent(), String(before));

  // The page goes on: a square as one OFF polygon opens as 2 triangles.
  writeFileSync(path.join(dir, 'square.off'),
    'OFF\n# a unit square\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n');
  await open(page, 'square.off');
  await waitForSurfaceNamed(page, 'square.off');
  await page.locator('#triangles-of').filter({ hasText: /^2$/ }).waitFor({ timeout: WAIT_MS });
  await waitForTriangles(page, (n) => n >= 1 && n <= 2, '1 or 2');
  assert.deepEqual(page.errors, []);
  await page.close();
});
