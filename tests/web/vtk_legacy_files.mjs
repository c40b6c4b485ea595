// Legacy .vtk files written by the tests, byte by byte, so that the page's reader is checked
// against the format (big-endian BINARY, both cell layouts, VTK's cell types) and not against
// itself. The surface is a grid of 7 x 4 points, 18 unit squares in three rows, each row cut
// into triangles a different way; every file holds its 36 triangles.
export const GRID_TRIANGLES = 36;
const COLUMNS = 7;
const ROWS = 4;
const bottom = (row, i) => row * COLUMNS + i;
const top = (row, i) => (row + 1) * COLUMNS + i;
const quad = (row, i) => [bottom(row, i), bottom(row, i + 1), top(row, i + 1), top(row, i)];

// The grid's points, lifted by `z` (so that each file is a different surface), and its fields:
// `height` is the point's index (0..27), `pressure` 100 + index / 2, `velocity` a vector.
export function gridPoints(z) {
  const points = [];
  for (let r = 0; r < ROWS; ++r) for (let i = 0; i < COLUMNS; ++i) points.push([i, r, z]);
  return points;
}
export const height = (p) => p.map((_, k) => k);
export const pressure = (p) => p.map((_, k) => 100 + k / 2);
export const velocity = (p) => p.map(([x, y]) => [x, y, 1]);

// The cells as a POLYDATA has them: row 0 as quads, row 1 as triangles (POLYGONS), row 2 as one
// triangle strip. Each list holds the cells' point lists.
export function polyDataCells() {
  const polygons = [];
  for (let i = 0; i < COLUMNS - 1; ++i) polygons.push(quad(0, i));
  for (let i = 0; i < COLUMNS - 1; ++i) {
    const [a, b, c, d] = quad(1, i);
    polygons.push([a, b, c], [a, c, d]);
  }
  const strip = [];
  for (let i = 0; i < COLUMNS; ++i) strip.push(top(2, i), bottom(2, i));
  return { polygons, strips: [strip] };
}

// The cells of an UNSTRUCTURED_GRID with their VTK types: row 0 quads (9), row 1 hexagons over
// two squares each (7), row 2 triangles (5), pixels (8) and a strip (6); and a vertex (1) and a
// line (3), which hold no triangles.
export function gridCells() {
  const cells = [];
  for (let i = 0; i < COLUMNS - 1; ++i) cells.push([9, quad(0, i)]);
  for (let i = 0; i < COLUMNS - 1; i += 2)
    cells.push([7, [bottom(1, i + 1), bottom(1, i + 2), top(1, i + 2), top(1, i + 1), top(1, i),
      bottom(1, i)]]); // begun mid-side, so that no triangle of its fan is flat
  for (let i = 0; i < 2; ++i) {
    const [a, b, c, d] = quad(2, i);
    cells.push([5, [a, b, c]], [5, [a, c, d]]);
  }
  for (let i = 2; i < 4; ++i) cells.push([8, [bottom(2, i), bottom(2, i + 1), top(2, i), top(2, i + 1)]]);
  cells.push([6, [top(2, 4), bottom(2, 4), top(2, 5), bottom(2, 5), top(2, 6), bottom(2, 6)]]);
  cells.push([1, [0]], [3, [0, 1]]);
  return cells;
}

// Big-endian bytes of `values` as the legacy type `type`.
function bigEndian(type, values) {
  const [size, setter] = {
    int: [4, 'setInt32'], float: [4, 'setFloat32'], double: [8, 'setFloat64'],
    vtktypeint64: [8, 'setBigInt64'], unsigned_char: [1, 'setUint8'],
  }[type];
  const view = new DataView(new ArrayBuffer(size * values.length));
  values.forEach((v, i) => view[setter](i * size, setter === 'setBigInt64' ? BigInt(v) : v, false));
  return Buffer.from(view.buffer);
}

// A writer of one file: `line(text)` adds a header line, `array(type, values)` the values in the
// file's format (ASCII numbers, or big-endian bytes and a newline).
function writer(binary) {
  const parts = [];
  return {
    line: (text) => parts.push(Buffer.from(`${text}\n`, 'latin1')),
    array: (type, values) => parts.push(binary ? bigEndian(type, values) :
      Buffer.from(values.join(' '), 'latin1'), Buffer.from('\n')),
    bytes: () => Buffer.concat(parts),
  };
}

// A cell array in the layout of the file's version: classic (count, points, ...) or OFFSETS and
// CONNECTIVITY (version 5.1).
function cellArray(w, keyword, lists, newLayout) {
  if (newLayout) {
    const offsets = [0];
    for (const l of lists) offsets.push(offsets.at(-1) + l.length);
    w.line(`${keyword} ${offsets.length} ${offsets.at(-1)}`);
    w.line('OFFSETS vtktypeint64');
    w.array('vtktypeint64', offsets);
    w.line('CONNECTIVITY vtktypeint64');
    w.array('vtktypeint64', lists.flat());
  } else {
    const size = lists.reduce((n, l) => n + 1 + l.length, 0);
    w.line(`${keyword} ${lists.length} ${size}`);
    w.array('int', lists.flatMap((l) => [l.length, ...l]));
  }
}

function header(w, { binary, newLayout, dataset }) {
  w.line(`# vtk DataFile Version ${newLayout ? '5.1' : '4.2'}`);
  w.line('a grid written by the tests');
  w.line(binary ? 'BINARY' : 'ASCII');
  w.line(`DATASET ${dataset}`);
}

// POLYDATA with float points, SCALARS height (float), VECTORS velocity (double), a FIELD array
// `label` (int) and cell data the page reads past.
export function polyDataFile({ binary, newLayout = false, z = 0 }) {
  const w = writer(binary);
  header(w, { binary, newLayout, dataset: 'POLYDATA' });
  const points = gridPoints(z);
  w.line(`POINTS ${points.length} float`);
  w.array('float', points.flat());
  const { polygons, strips } = polyDataCells();
  cellArray(w, 'POLYGONS', polygons, newLayout);
  cellArray(w, 'TRIANGLE_STRIPS', strips, newLayout);
  w.line(`CELL_DATA ${polygons.length + strips.length}`);
  w.line('SCALARS cell_id int 1');
  w.line('LOOKUP_TABLE default');
  w.array('int', [...polygons, ...strips].map((_, k) => k));
  w.line(`POINT_DATA ${points.length}`);
  w.line('SCALARS height float 1');
  w.line('LOOKUP_TABLE default');
  w.array('float', height(points));
  w.line('VECTORS velocity double');
  w.array('double', velocity(points).flat());
  w.line('FIELD FieldData 1');
  w.line(`label 1 ${points.length} int`);
  w.array('int', points.map((_, k) => k % 3));
  return w.bytes();
}

// UNSTRUCTURED_GRID with double points and SCALARS pressure (double).
export function gridFile({ binary, newLayout, z = 0, cells = gridCells() }) {
  const w = writer(binary);
  header(w, { binary, newLayout, dataset: 'UNSTRUCTURED_GRID' });
  const points = gridPoints(z);
  w.line(`POINTS ${points.length} double`);
  w.array('double', points.flat());
  cellArray(w, 'CELLS', cells.map(([, l]) => l), newLayout);
  w.line(`CELL_TYPES ${cells.length}`);
  w.array('int', cells.map(([type]) => type));
  w.line(`POINT_DATA ${points.length}`);
  w.line('SCALARS pressure double');
  w.line('LOOKUP_TABLE default');
  w.array('double', pressure(points));
  return w.bytes();
}
