// Opening a surface file in the page: the file button and drag-and-drop. The file is read here,
// in the browser, with vtk.js's readers (.vtp, .ply, .obj, .stl), the page's own legacy .vtk
// reader (vtk_legacy.js: ASCII and BINARY, POLYDATA and UNSTRUCTURED_GRID) or the few lines
// below (.off), and uploaded into the current session (or for this page) in chunks, with the
// progress bar. A file that cannot be read gets a message; nothing else stops.
// vtk.js's readers are loaded when a file is opened (their own chunk), not with the page.
import { readLegacyVtk, VtkFormatError } from './vtk_legacy.js';

const READERS = {
  '.vtp': () => import('@kitware/vtk.js/IO/XML/XMLPolyDataReader'),
  '.ply': () => import('@kitware/vtk.js/IO/Geometry/PLYReader'),
  '.stl': () => import('@kitware/vtk.js/IO/Geometry/STLReader'),
  '.obj': () => import('@kitware/vtk.js/IO/Misc/OBJReader'),
};

export const OPENABLE = ['.vtp', '.vtk', '.ply', '.obj', '.stl', '.off'];
const CHUNK_BYTES = 256 * 1024;
const MAX_BUFFERED = 4 * CHUNK_BYTES; // the WebSocket's queue is kept this short
const FIRST_UPLOAD_ID = 1_000_000_000; // apart from the page's request ids

export class FileError extends Error {}

function extensionOf(name) {
  const dot = name.lastIndexOf('.');
  return dot < 0 ? '' : name.slice(dot).toLowerCase();
}

// OFF: "OFF", the counts, a vertex a line, a face a line (a polygon is split into a fan; colours
// after a face's corners are ignored); comments start with #.
function parseOff(text) {
  const lines = text.split('\n').map((l) => l.replace(/#.*/, '').trim()).filter(Boolean);
  const header = lines.shift() ?? '';
  if (!/^C?N?OFF\b/.test(header))
    throw new FileError(`it does not start with OFF (but "${header.slice(0, 20)}")`);
  const counts = (header.replace(/^C?N?OFF/, '').trim() || lines.shift() || '').split(/\s+/).map(Number);
  const [nv, nf] = counts;
  if (!Number.isInteger(nv) || !Number.isInteger(nf) || nv < 0 || nf < 0)
    throw new FileError('the vertex and face counts are not whole numbers');
  if (lines.length < nv + nf)
    throw new FileError(`it announces ${nv} vertices and ${nf} faces but has ${lines.length} lines`);
  const positions = new Float32Array(3 * nv);
  for (let v = 0; v < nv; ++v) {
    const xyz = lines[v].split(/\s+/).map(Number);
    if (xyz.length < 3) throw new FileError(`vertex ${v} has fewer than 3 coordinates`);
    positions.set(xyz.slice(0, 3), 3 * v);
  }
  const triangles = [];
  for (let f = 0; f < nf; ++f) {
    const numbers = lines[nv + f].split(/\s+/).map(Number);
    const n = numbers[0];
    if (!Number.isInteger(n) || numbers.length < n + 1) throw new FileError(`face ${f} is malformed`);
    for (let k = 2; k < n; ++k) triangles.push(numbers[1], numbers[k], numbers[k + 1]);
  }
  return { positions, triangles: Uint32Array.from(triangles), fields: [] };
}

// vtkPolyData -> positions, triangles (polygons as fans, strips as triangles) and point data.
function fromPolyData(pd) {
  const points = pd.getPoints()?.getData();
  if (!points || points.length === 0) throw new FileError('it holds no points');
  const triangles = [];
  const polys = pd.getPolys().getData();
  for (let i = 0; i < polys.length; i += polys[i] + 1)
    for (let k = 1; k + 1 < polys[i]; ++k) triangles.push(polys[i + 1], polys[i + 1 + k], polys[i + 2 + k]);
  const strips = pd.getStrips().getData();
  for (let i = 0; i < strips.length; i += strips[i] + 1)
    for (let k = 0; k + 2 < strips[i]; ++k) {
      const [a, b, c] = [strips[i + 1 + k], strips[i + 2 + k], strips[i + 3 + k]];
      triangles.push(...(k % 2 ? [b, a, c] : [a, b, c]));
    }
  const vertexCount = points.length / 3;
  const fields = [];
  pd.getPointData().getArrays().forEach((array, i) => {
    const components = array.getNumberOfComponents();
    const values = array.getData();
    if (typeof values[0] === 'string' || values.length !== vertexCount * components) return;
    fields.push({ name: array.getName() || `field ${i}`, components, values: Float32Array.from(values) });
  });
  return { positions: Float32Array.from(points), triangles: Uint32Array.from(triangles), fields };
}

// Reads `file` (a File or Blob with a name) into { positions, triangles, fields }; throws FileError
// saying what is wrong.
export async function readSurfaceFile(file) {
  const ext = extensionOf(file.name);
  if (!OPENABLE.includes(ext))
    throw new FileError(`"${ext || file.name}" is not a format the page reads (${OPENABLE.join(' ')})`);
  if (file.size === 0) throw new FileError('the file is empty');
  let surface;
  try {
    if (ext === '.off') {
      surface = parseOff(await file.text());
    } else if (ext === '.vtk') {
      surface = readLegacyVtk(new Uint8Array(await file.arrayBuffer()));
    } else {
      const reader = (await READERS[ext]()).default.newInstance();
      if (ext === '.obj') reader.parseAsText(await file.text());
      else reader.parseAsArrayBuffer(await file.arrayBuffer());
      surface = fromPolyData(reader.getOutputData());
    }
  } catch (e) {
    if (e instanceof FileError) throw e;
    if (e instanceof VtkFormatError) throw new FileError(e.message);
    throw new FileError(`it is not a readable ${ext} file (${e.message || e})`);
  }
  check(surface);
  return surface;
}

// What the server would refuse anyway, said here in the file's terms.
function check({ positions, triangles }) {
  const vertexCount = positions.length / 3;
  if (triangles.length === 0) throw new FileError('it holds no triangles');
  for (let i = 0; i < positions.length; ++i)
    if (!Number.isFinite(positions[i]))
      throw new FileError(`vertex ${Math.floor(i / 3)} has a coordinate that is not a number`);
  for (let i = 0; i < triangles.length; ++i)
    if (!(triangles[i] < vertexCount))
      throw new FileError(`triangle ${Math.floor(i / 3)} refers to vertex ${triangles[i]}, ` +
        `but there are ${vertexCount}`);
}

// The upload's bytes as the protocol lays out a raw blob: positions, triangles, each field.
function blobOf({ positions, triangles, fields }) {
  const parts = [positions, triangles, ...fields.map((f) => f.values)];
  const out = new Uint8Array(parts.reduce((n, p) => n + p.byteLength, 0));
  let at = 0;
  for (const p of parts) {
    out.set(new Uint8Array(p.buffer, p.byteOffset, p.byteLength), at);
    at += p.byteLength;
  }
  return out;
}

const nextFrame = () => new Promise((resolve) => setTimeout(resolve, 10));

// The button and drop target of one page. `session()` names the session to upload into ('' for
// none); `progress(fraction|null, text)` and `notice(text)` are the page's; `onUploaded(result)`
// gets the server's UploadResult.
export class FileOpener {
  constructor({ connection, session, progress, notice, onUploaded }) {
    Object.assign(this, { connection, session, progress, notice, onUploaded });
    this.nextId = FIRST_UPLOAD_ID;
    this.pending = new Map(); // upload id -> file name
  }

  attach(input, dropTarget) {
    input.accept = OPENABLE.join(',');
    input.addEventListener('change', () => {
      if (input.files.length) this.open(input.files[0]);
      input.value = ''; // the same file may be chosen again
    });
    dropTarget.addEventListener('dragover', (e) => {
      e.preventDefault();
      dropTarget.dataset.dropping = '1';
    });
    dropTarget.addEventListener('dragleave', () => delete dropTarget.dataset.dropping);
    dropTarget.addEventListener('drop', (e) => {
      e.preventDefault();
      delete dropTarget.dataset.dropping;
      if (e.dataTransfer.files.length) this.open(e.dataTransfer.files[0]);
    });
  }

  async open(file) {
    this.progress(NaN, `reading ${file.name}…`);
    let surface;
    try {
      surface = await readSurfaceFile(file);
    } catch (e) {
      this.progress(null);
      this.notice(`Cannot open ${file.name}: ${e.message}`);
      return;
    }
    const bytes = blobOf(surface);
    const id = this.nextId++;
    this.pending.set(id, file.name);
    const session = this.session();
    this.connection.send('UploadBegin', {
      upload_id: id, name: file.name, vertex_count: surface.positions.length / 3,
      triangle_count: surface.triangles.length / 3,
      fields: surface.fields.map((f) => ({ name: f.name, components: f.components })),
      total_bytes: bytes.length, ...(session ? { session } : {}),
    });
    const ws = this.connection.ws;
    for (let offset = 0; offset < bytes.length; offset += CHUNK_BYTES) {
      this.connection.send('UploadChunk', { upload_id: id, offset,
        data: bytes.subarray(offset, offset + CHUNK_BYTES) });
      while (ws.bufferedAmount > MAX_BUFFERED && ws.readyState === WebSocket.OPEN) {
        this.showSent(file.name, offset + CHUNK_BYTES - ws.bufferedAmount, bytes.length);
        await nextFrame();
      }
      this.showSent(file.name, Math.min(bytes.length, offset + CHUNK_BYTES), bytes.length);
    }
    this.connection.send('UploadEnd', { upload_id: id });
    this.progress(NaN, `${file.name}: checking and storing on the server…`);
  }

  showSent(name, sent, total) {
    const fraction = Math.max(0, Math.min(1, sent / total));
    this.progress(fraction, `uploading ${name}: ${Math.round(100 * fraction)}% of ` +
      `${(total / (1 << 20)).toFixed(1)} MiB`);
  }

  // The server's answers to this page's uploads; true if `m` was one.
  onUploadResult(m) {
    if (!this.pending.delete(Number(m.upload_id))) return false;
    this.progress(null);
    this.onUploaded(m);
    return true;
  }

  onError(m) {
    const name = this.pending.get(Number(m.request_id));
    if (name === undefined) return false;
    this.pending.delete(Number(m.request_id));
    this.progress(null);
    this.notice(`The server refused ${name}: ${m.message}`);
    return true;
  }
}
