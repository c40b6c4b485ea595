// The cells of a legacy .vtk file as triangles. A cell array comes in two layouts: the classic
// one (up to file version 4.2: for each cell its point count, then its points) and the one of
// VTK 9's version 5.1 (an OFFSETS array, then a CONNECTIVITY array). Polygons and quads become
// fans, triangle strips their triangles; an unstructured grid's 0-D and 1-D cells are left out,
// and its 3-D cells (a volume mesh) are refused with their names.
import { VtkFormatError } from './vtk_legacy_cursor.js';

// A cell array as { offsets, connectivity }: cell c has the points
// connectivity[offsets[c] .. offsets[c + 1]). `cells` and `size` are the two numbers after its
// keyword; `what` names it in errors.
export function readCellArray(cursor, cells, size, newLayout, what) {
  return newLayout ? readOffsetsLayout(cursor, cells, size, what) :
    readClassicLayout(cursor, cells, size, what);
}

function readClassicLayout(cursor, cells, size, what) {
  if (cells > size)
    throw new VtkFormatError(`${what} announces ${cells} cells in ${size} numbers`);
  const data = cursor.values('int', size, what);
  const offsets = new Float64Array(cells + 1);
  const connectivity = new Float64Array(Math.max(0, size - cells));
  let at = 0;
  let n = 0;
  for (let c = 0; c < cells; ++c) {
    const points = data[at];
    if (!(at < size && Number.isInteger(points) && points >= 0 && at + 1 + points <= size))
      throw new VtkFormatError(`${what}: cell ${c} does not fit in the ${size} numbers announced`);
    for (let k = at + 1; k <= at + points; ++k) connectivity[n++] = data[k];
    at += 1 + points;
    offsets[c + 1] = n;
  }
  return { offsets, connectivity: connectivity.subarray(0, n) };
}

function readOffsetsLayout(cursor, offsetCount, size, what) {
  const word = (expected) => {
    const w = cursor.required(`${expected} of ${what}`);
    if (w.toUpperCase() !== expected)
      throw new VtkFormatError(`${what}: "${w}" where ${expected} should be (file version 5)`);
    return cursor.required(`the data type of ${what}'s ${expected}`);
  };
  const offsets = cursor.values(word('OFFSETS'), offsetCount, `${what} OFFSETS`);
  cursor.skipMetadata();
  const connectivity = cursor.values(word('CONNECTIVITY'), size, `${what} CONNECTIVITY`);
  if (!offsets || !connectivity) throw new VtkFormatError(`${what}: cells given as strings`);
  if (offsetCount > 0 && offsets[0] !== 0)
    throw new VtkFormatError(`${what}: the first offset is ${offsets[0]}, not 0`);
  for (let c = 1; c < offsetCount; ++c)
    if (!(offsets[c] >= offsets[c - 1] && offsets[c] <= size))
      throw new VtkFormatError(`${what}: offset ${c} (${offsets[c]}) is out of order or past ` +
        `the ${size} points of the connectivity`);
  return { offsets: offsetCount ? offsets : new Float64Array(1), connectivity };
}

// The number of cells in a cell array.
export const cellCount = ({ offsets }) => offsets.length - 1;

// Throws unless every point of `cells` is one of `pointCount` points.
export function checkPoints({ connectivity }, pointCount, what) {
  for (let i = 0; i < connectivity.length; ++i) {
    const p = connectivity[i];
    if (!(Number.isInteger(p) && p >= 0 && p < pointCount))
      throw new VtkFormatError(`${what} refers to point ${p}, but there are ${pointCount}`);
  }
}

// Triangles as they are found, in a Uint32Array that grows; `array()` is the result.
export class TriangleList {
  constructor() {
    this.data = new Uint32Array(3 * 1024);
    this.length = 0;
  }

  push(a, b, c) {
    if (this.length + 3 > this.data.length) {
      const grown = new Uint32Array(2 * this.data.length);
      grown.set(this.data);
      this.data = grown;
    }
    this.data[this.length++] = a;
    this.data[this.length++] = b;
    this.data[this.length++] = c;
  }

  array() {
    return this.data.slice(0, this.length);
  }
}

// Appends cell c's triangles as a fan (polygon, quad, triangle) to `out`.
function fan({ offsets, connectivity }, c, out) {
  const first = offsets[c];
  for (let k = first + 1; k + 1 < offsets[c + 1]; ++k)
    out.push(connectivity[first], connectivity[k], connectivity[k + 1]);
}

// Appends cell c's triangles as a strip, every other one turned so that all face one way.
function strip({ offsets, connectivity }, c, out) {
  for (let k = offsets[c], i = 0; k + 2 < offsets[c + 1]; ++k, ++i) {
    const [a, b, d] = [connectivity[k], connectivity[k + 1], connectivity[k + 2]];
    if (i % 2) out.push(b, a, d);
    else out.push(a, b, d);
  }
}

// A pixel's points run along x first: 0 1 / 2 3, not around.
function pixel({ offsets, connectivity }, c, out) {
  if (offsets[c + 1] - offsets[c] !== 4) return fan({ offsets, connectivity }, c, out);
  const at = offsets[c];
  const [a, b, d, e] = [connectivity[at], connectivity[at + 1], connectivity[at + 2],
    connectivity[at + 3]];
  out.push(a, b, e);
  out.push(a, e, d);
}

export function polygonTriangles(cells, out) {
  for (let c = 0; c < cellCount(cells); ++c) fan(cells, c, out);
}

export function stripTriangles(cells, out) {
  for (let c = 0; c < cellCount(cells); ++c) strip(cells, c, out);
}

// VTK's cell types (vtkCellType.h) by what the page does with them.
const SURFACE_CELLS = { 5: fan, 6: strip, 7: fan, 8: pixel, 9: fan };
const LEFT_OUT = new Set([1, 2, 3, 4, 21, 35, 68, 75]); // vertices and lines
const NAMES = {
  10: 'tetra', 11: 'voxel', 12: 'hexahedron', 13: 'wedge', 14: 'pyramid',
  15: 'pentagonal prism', 16: 'hexagonal prism', 22: 'quadratic triangle',
  23: 'quadratic quad', 24: 'quadratic tetra', 25: 'quadratic hexahedron',
  26: 'quadratic wedge', 27: 'quadratic pyramid', 28: 'biquadratic quad',
  29: 'triquadratic hexahedron', 30: 'quadratic linear quad', 31: 'quadratic linear wedge',
  32: 'biquadratic quadratic wedge', 33: 'biquadratic quadratic hexahedron',
  34: 'biquadratic triangle', 36: 'quadratic polygon', 37: 'triquadratic pyramid',
  41: 'convex point set', 42: 'polyhedron', 69: 'Lagrange triangle',
  70: 'Lagrange quadrilateral', 71: 'Lagrange tetrahedron', 72: 'Lagrange hexahedron',
  73: 'Lagrange wedge', 74: 'Lagrange pyramid', 76: 'Bezier triangle',
  77: 'Bezier quadrilateral', 78: 'Bezier tetrahedron', 79: 'Bezier hexahedron',
  80: 'Bezier wedge', 81: 'Bezier pyramid',
};
const VOLUME_CELLS = new Set([10, 11, 12, 13, 14, 15, 16, 24, 25, 26, 27, 29, 31, 32, 33, 37, 41,
  42, 71, 72, 73, 74, 78, 79, 80, 81]);

// An unstructured grid's cells (with their CELL_TYPES) appended to `out` as triangles.
export function gridTriangles(cells, types, out) {
  if (types.length !== cellCount(cells))
    throw new VtkFormatError(`CELL_TYPES gives ${types.length} types for ${cellCount(cells)} cells`);
  const refused = new Map(); // type -> cells of it
  for (let c = 0; c < types.length; ++c) {
    const type = types[c];
    const triangulate = SURFACE_CELLS[type];
    if (triangulate) triangulate(cells, c, out);
    else if (!LEFT_OUT.has(type)) refused.set(type, (refused.get(type) ?? 0) + 1);
  }
  if (refused.size === 0) return;
  const list = [...refused].map(([type, n]) => `${n} ${NAMES[type] ?? `of type ${type}`}`)
    .join(', ');
  if ([...refused.keys()].some((type) => VOLUME_CELLS.has(type)))
    throw new VtkFormatError(`it holds 3-D cells (${list}): a volume mesh, and the page reads ` +
      'surfaces; extract its surface first (e.g. ParaView\'s Extract Surface)');
  throw new VtkFormatError(`it holds cells the page does not read (${list}); it reads ` +
    'triangles, quads, pixels, polygons and triangle strips');
}
