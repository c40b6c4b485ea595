// Legacy .vtk files (VTK's "# vtk DataFile Version" format), ASCII or BINARY, as a surface:
// a POLYDATA's polygons and triangle strips, or an UNSTRUCTURED_GRID's 2-D cells, as triangles,
// with the point data (SCALARS, VECTORS, NORMALS, TEXTURE_COORDINATES, TENSORS, TENSORS6,
// COLOR_SCALARS and FIELD arrays) as fields. Cell data, vertices, lines and the data set's own
// FIELD data are read past. Throws VtkFormatError saying what is wrong.
import { checkPoints, gridTriangles, polygonTriangles, readCellArray, stripTriangles, TriangleList }
  from './vtk_legacy_cells.js';
import { decodeName, VtkCursor, VtkFormatError } from './vtk_legacy_cursor.js';

export { VtkFormatError };

const DATA_SETS = ['POLYDATA', 'UNSTRUCTURED_GRID'];

// The four header lines: version, title, ASCII or BINARY, DATASET type.
function readHeader(bytes) {
  const cursor = new VtkCursor(bytes, false);
  const first = cursor.line();
  const version = /^#\s*vtk\s+DataFile\s+Version\s+(\d+)(?:\.(\d+))?/i.exec(first);
  if (!version)
    throw new VtkFormatError(`it does not start with "# vtk DataFile Version" (but "${first.slice(0, 30)}")`);
  cursor.line(); // the title
  const format = cursor.keyword();
  if (format !== 'ascii' && format !== 'binary')
    throw new VtkFormatError(`its third line says "${format}", not ASCII or BINARY`);
  if (cursor.keyword() !== 'dataset')
    throw new VtkFormatError('it has no DATASET line after ASCII or BINARY');
  const dataset = (cursor.word() ?? '').toUpperCase();
  if (!DATA_SETS.includes(dataset))
    throw new VtkFormatError(`it holds a ${dataset || 'nameless'} data set; the page reads ` +
      'surfaces from POLYDATA and UNSTRUCTURED_GRID');
  cursor.binary = format === 'binary';
  return { cursor, dataset, newLayout: Number(version[1]) >= 5 };
}

// One attribute of POINT_DATA or CELL_DATA, after its keyword: { name, components, values }
// (values null for a string array), or null for a lookup table.
function readAttribute(cursor, key, tuples) {
  const name = () => decodeName(cursor.required(`the name of ${key.toUpperCase()}`));
  const type = () => cursor.required(`the data type of ${key.toUpperCase()}`);
  const array = (n, components, dataType, what) => ({
    name: n, components, values: cursor.values(dataType, tuples * components, what),
  });
  switch (key) {
    case 'scalars': {
      const n = name();
      const dataType = type();
      let components = 1;
      let next = cursor.keyword();
      if (next !== 'lookup_table') {
        components = Number(next);
        if (!(Number.isInteger(components) && components >= 1 && components <= 4))
          throw new VtkFormatError(`SCALARS ${n}: "${next}" where its component count (1-4) or ` +
            'LOOKUP_TABLE should be');
        next = cursor.keyword();
      }
      if (next !== 'lookup_table')
        throw new VtkFormatError(`SCALARS ${n} has no LOOKUP_TABLE line`);
      cursor.required(`the lookup table of SCALARS ${n}`);
      return array(n, components, dataType, `SCALARS ${n}`);
    }
    case 'vectors':
    case 'normals': {
      const n = name();
      return array(n, 3, type(), `${key.toUpperCase()} ${n}`);
    }
    case 'tensors':
    case 'tensors6': { // the full 3 x 3, or the 6 of a symmetric one (VTK 9.1)
      const n = name();
      return array(n, key === 'tensors' ? 9 : 6, type(), `${key.toUpperCase()} ${n}`);
    }
    case 'texture_coordinates': {
      const n = name();
      const components = cursor.count(`the dimension of TEXTURE_COORDINATES ${n}`);
      return array(n, components, type(), `TEXTURE_COORDINATES ${n}`);
    }
    case 'color_scalars': {
      // Bytes in a BINARY file, numbers in [0, 1] in an ASCII one.
      const n = name();
      const components = cursor.count(`the component count of COLOR_SCALARS ${n}`);
      const a = array(n, components, cursor.binary ? 'unsigned_char' : 'float', `COLOR_SCALARS ${n}`);
      if (cursor.binary) a.values = a.values.map((x) => x / 255);
      return a;
    }
    case 'global_ids':
    case 'pedigree_ids':
    case 'edge_flags': {
      const n = name();
      cursor.values(type(), tuples, `${key.toUpperCase()} ${n}`);
      return null; // identifiers, not data
    }
    case 'lookup_table': {
      const n = name();
      const size = cursor.count(`the size of LOOKUP_TABLE ${n}`);
      cursor.values(cursor.binary ? 'unsigned_char' : 'float', 4 * size, `LOOKUP_TABLE ${n}`);
      return null;
    }
    default:
      return undefined;
  }
}

// A FIELD block after its keyword: its arrays as { name, components, tuples, values }.
function readFieldArrays(cursor) {
  const fieldName = decodeName(cursor.required('the name of a FIELD'));
  const count = cursor.count(`the array count of FIELD ${fieldName}`);
  const arrays = [];
  for (let i = 0; i < count; ++i) {
    const name = decodeName(cursor.required(`array ${i} of FIELD ${fieldName}`));
    if (name === 'NULL_ARRAY') continue;
    const components = cursor.count(`the component count of ${name}`);
    const tuples = cursor.count(`the tuple count of ${name}`);
    const type = cursor.required(`the data type of ${name}`);
    const values = cursor.values(type, components * tuples, `FIELD array ${name}`);
    cursor.skipMetadata();
    arrays.push({ name, components, tuples, values });
  }
  return arrays;
}

// Reads a legacy .vtk file's bytes into { positions, triangles, fields }.
export function readLegacyVtk(bytes) {
  const { cursor, dataset, newLayout } = readHeader(bytes);
  let positions = null;
  const polygons = []; // the POLYDATA's cell arrays that hold triangles: [array, keyword]
  const fields = [];
  let cells = null;
  let types = null;
  let attributesOf = null; // 'point' or 'cell' after POINT_DATA / CELL_DATA
  let tuples = 0;
  const cellArray = (key) => {
    const what = key.toUpperCase();
    const n = cursor.count(`the cell count of ${what}`);
    const size = cursor.count(`the size of ${what}`);
    const a = readCellArray(cursor, n, size, newLayout, what);
    cursor.skipMetadata();
    return a;
  };
  for (let key = cursor.keyword(); key !== null; key = cursor.keyword()) {
    if (key === 'points') {
      const n = cursor.count('the point count');
      const values = cursor.values(cursor.required('the data type of POINTS'), 3 * n, 'POINTS');
      if (!values) throw new VtkFormatError('its POINTS are strings');
      positions = Float32Array.from(values);
      cursor.skipMetadata();
    } else if ((key === 'polygons' || key === 'triangle_strips') && dataset === 'POLYDATA') {
      polygons.push([cellArray(key), key]);
    } else if ((key === 'vertices' || key === 'lines') && dataset === 'POLYDATA') {
      cellArray(key);
    } else if (key === 'cells' && dataset === 'UNSTRUCTURED_GRID') {
      cells = cellArray(key);
    } else if (key === 'cell_types' && dataset === 'UNSTRUCTURED_GRID') {
      const n = cursor.count('the count of CELL_TYPES');
      types = cursor.values('int', n, 'CELL_TYPES');
      cursor.skipMetadata();
    } else if (key === 'point_data' || key === 'cell_data') {
      attributesOf = key === 'point_data' ? 'point' : 'cell';
      tuples = cursor.count(`the count of ${key.toUpperCase()}`);
      const points = positions ? positions.length / 3 : 0;
      if (attributesOf === 'point' && tuples !== points)
        throw new VtkFormatError(`POINT_DATA is for ${tuples} points, but there are ${points}`);
    } else if (key === 'field') {
      // The data set's own field data, or arrays of the point or cell data.
      for (const a of readFieldArrays(cursor))
        if (attributesOf === 'point' && a.values && a.tuples === tuples)
          fields.push({ name: a.name, components: a.components, values: a.values });
    } else if (attributesOf) {
      const a = readAttribute(cursor, key, tuples);
      if (a === undefined) throw unexpected(key, dataset);
      cursor.skipMetadata();
      if (a && a.values && attributesOf === 'point') fields.push(a);
    } else {
      throw unexpected(key, dataset);
    }
  }
  if (!positions) throw new VtkFormatError('it has no POINTS');
  const vertexCount = positions.length / 3;
  const triangles = new TriangleList();
  for (const [array, key] of polygons) {
    checkPoints(array, vertexCount, key.toUpperCase());
    (key === 'polygons' ? polygonTriangles : stripTriangles)(array, triangles);
  }
  if (dataset === 'UNSTRUCTURED_GRID') {
    if (!cells) throw new VtkFormatError('the unstructured grid has no CELLS');
    if (!types) throw new VtkFormatError('the unstructured grid has no CELL_TYPES');
    checkPoints(cells, vertexCount, 'CELLS');
    gridTriangles(cells, types, triangles);
  }
  return {
    positions,
    triangles: triangles.array(),
    fields: fields.map((f) => ({ name: f.name, components: f.components,
      values: Float32Array.from(f.values) })),
  };
}

function unexpected(key, dataset) {
  return new VtkFormatError(`"${key.slice(0, 40)}" where a section of a ${dataset} ` +
    '(POINTS, cells, POINT_DATA, CELL_DATA, FIELD) should be');
}
