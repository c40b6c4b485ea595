// The mesh a page shows, as the server sends it (docs/protocol.md, "Blobs"): a whole level
// (positions | triangles | fields) or a refinement of the previous one (new vertices | slot
// writes | their field values), raw or through meshoptimizer's codecs. Every size and index is
// checked before it is used; a bad blob throws MeshError and leaves the mesh as it was.
import { MeshoptDecoder } from 'meshoptimizer/decoder';
import { enumValues } from './protocol.js';

const Encoding = enumValues('Encoding');
const Kind = enumValues('MeshBegin.Kind');
const DEAD_SLOT = 0xffffffff;

export const decoderReady = MeshoptDecoder.ready;

export class MeshError extends Error {}

// One level's bytes as its MeshChunks arrive.
export class IncomingLevel {
  constructor(begin) {
    this.begin = begin;
    this.total = begin.total_bytes;
    if (!Number.isSafeInteger(this.total) || this.total > 2 ** 31)
      throw new MeshError(`a level of ${this.total} bytes`);
    this.bytes = new Uint8Array(this.total);
    this.received = 0;
  }

  add(chunk) {
    const data = chunk.data;
    if (chunk.offset !== this.received)
      throw new MeshError(`a chunk at offset ${chunk.offset} after ${this.received} bytes`);
    if (this.received + data.length > this.total)
      throw new MeshError(`more than the announced ${this.total} bytes`);
    this.bytes.set(data, this.received);
    this.received += data.length;
  }

  get fraction() {
    return this.total === 0 ? 1 : this.received / this.total;
  }

  get complete() {
    return this.received === this.total;
  }
}

function sectionsOf(begin, bytes) {
  const sizes = begin.section_bytes;
  if (sizes.length !== 2 + begin.fields.length)
    throw new MeshError(`${sizes.length} sections for ${begin.fields.length} fields`);
  let at = 0;
  const out = sizes.map((n) => {
    const s = bytes.subarray(at, at + n);
    at += n;
    return s;
  });
  if (at !== bytes.length)
    throw new MeshError(`sections of ${at} bytes in a blob of ${bytes.length}`);
  return out;
}

function vertexStream(section, count, size, encoding, what) {
  const out = new Uint8Array(count * size);
  if (encoding === Encoding.MESHOPT) {
    try {
      MeshoptDecoder.decodeVertexBuffer(out, count, size, section);
    } catch (e) {
      throw new MeshError(`${what}: not a meshopt vertex stream of ${count} vertices (${e.message})`);
    }
  } else {
    if (section.length !== out.length)
      throw new MeshError(`${what}: ${section.length} bytes, expected ${out.length}`);
    out.set(section);
  }
  return new Float32Array(out.buffer);
}

function uint32Stream(section, count, what) {
  if (section.length !== 4 * count)
    throw new MeshError(`${what}: ${section.length} bytes, expected ${4 * count}`);
  return new Uint32Array(section.slice().buffer);
}

function grow(array, needed) {
  if (array.length >= needed) return array;
  const bigger = new array.constructor(Math.max(needed, Math.ceil(array.length * 1.5)));
  bigger.set(array);
  return bigger;
}

// Vertices (positions and per-vertex fields) and triangle slots; a dead slot is kept as the
// degenerate triangle (0, 0, 0) so the index buffer can be drawn as it is.
export class MeshState {
  constructor() {
    this.clear();
  }

  clear() {
    this.vertexCount = 0;
    this.positions = new Float32Array(0);
    this.fields = []; // { name, components, values }
    this.slotCount = 0;
    this.slots = new Uint32Array(0);
    this.liveTriangles = 0;
  }

  // Applies one complete level; returns the live triangle count it leaves.
  apply(begin, bytes) {
    const encoding = begin.encoding === Encoding.MESHOPT ? Encoding.MESHOPT : Encoding.RAW;
    if (begin.encoding !== encoding && begin.encoding !== Encoding.RAW && begin.encoding !== 0)
      throw new MeshError(`unknown encoding ${begin.encoding}`);
    const sections = sectionsOf(begin, bytes);
    const n = begin.vertex_count;
    const newPositions = vertexStream(sections[0], n, 12, encoding, 'positions');
    const newFields = begin.fields.map((f, i) => {
      if (f.components < 1 || f.components > 256)
        throw new MeshError(`field "${f.name}" has ${f.components} components`);
      return {
        name: f.name,
        components: f.components,
        values: vertexStream(sections[2 + i], n, 4 * f.components, encoding, `field "${f.name}"`),
      };
    });
    if (begin.kind === Kind.REFINEMENT) this.refine(begin, sections[1], newPositions, newFields);
    else if (begin.kind === Kind.FULL || begin.kind === 0)
      this.replace(begin, sections[1], newPositions, newFields, encoding);
    else throw new MeshError(`unknown mesh kind ${begin.kind}`);
    return this.liveTriangles;
  }

  replace(begin, section, positions, fields, encoding) {
    const n = begin.vertex_count;
    const count = 3 * begin.triangle_count;
    let triangles;
    if (encoding === Encoding.MESHOPT) {
      const out = new Uint8Array(4 * count);
      try {
        MeshoptDecoder.decodeIndexBuffer(out, count, 4, section);
      } catch (e) {
        throw new MeshError(`triangles: not a meshopt index stream (${e.message})`);
      }
      triangles = new Uint32Array(out.buffer);
    } else {
      triangles = uint32Stream(section, count, 'triangles');
    }
    for (let i = 0; i < triangles.length; ++i)
      if (triangles[i] >= n)
        throw new MeshError(`triangle ${Math.floor(i / 3)} refers to vertex ${triangles[i]} of ${n}`);
    this.vertexCount = n;
    this.positions = positions;
    this.fields = fields;
    this.slotCount = begin.triangle_count;
    this.slots = triangles;
    this.liveTriangles = begin.triangle_count;
  }

  refine(begin, section, positions, fields) {
    if (this.fields.length !== fields.length ||
        this.fields.some((f, i) => f.name !== fields[i].name || f.components !== fields[i].components))
      throw new MeshError('a refinement whose fields differ from the level it refines');
    const writes = uint32Stream(section, 4 * begin.triangle_count, 'slot writes');
    const n = this.vertexCount + begin.vertex_count;
    // Check every write against the state it would leave before changing anything.
    let slotCount = this.slotCount;
    for (let w = 0; w < writes.length; w += 4) {
      const [slot, a, b, c] = [writes[w], writes[w + 1], writes[w + 2], writes[w + 3]];
      if (slot > slotCount) throw new MeshError(`a write to slot ${slot} of ${slotCount}`);
      if (slot === slotCount) ++slotCount;
      if (a !== DEAD_SLOT && (a >= n || b >= n || c >= n))
        throw new MeshError(`slot ${slot} refers to a vertex beyond ${n}`);
    }
    this.positions = grow(this.positions, 3 * n);
    this.positions.set(positions, 3 * this.vertexCount);
    this.fields.forEach((f, i) => {
      f.values = grow(f.values, f.components * n);
      f.values.set(fields[i].values, f.components * this.vertexCount);
    });
    this.vertexCount = n;
    this.slots = grow(this.slots, 3 * slotCount);
    let live = this.liveTriangles;
    for (let w = 0; w < writes.length; w += 4) {
      const slot = writes[w];
      const wasLive = slot < this.slotCount && !this.isDead(slot);
      if (slot === this.slotCount) ++this.slotCount;
      const dead = writes[w + 1] === DEAD_SLOT;
      this.slots[3 * slot] = dead ? 0 : writes[w + 1];
      this.slots[3 * slot + 1] = dead ? 0 : writes[w + 2];
      this.slots[3 * slot + 2] = dead ? 0 : writes[w + 3];
      live += (dead ? 0 : 1) - (wasLive ? 1 : 0);
    }
    this.liveTriangles = live;
  }

  isDead(slot) {
    const s = this.slots;
    return s[3 * slot] === s[3 * slot + 1] && s[3 * slot + 1] === s[3 * slot + 2];
  }

  // Per vertex, the value a field is coloured by: the scalar, or a vector's length.
  scalars(fieldName) {
    const field = this.fields.find((f) => f.name === fieldName);
    if (!field) return null;
    const out = new Float32Array(this.vertexCount);
    const c = field.components;
    for (let v = 0; v < this.vertexCount; ++v) {
      if (c === 1) {
        out[v] = field.values[v];
      } else {
        let sum = 0;
        for (let k = 0; k < c; ++k) sum += field.values[v * c + k] ** 2;
        out[v] = Math.sqrt(sum);
      }
    }
    return { values: out, components: c };
  }
}
