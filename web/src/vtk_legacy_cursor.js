// A cursor over the bytes of a legacy .vtk file. Keywords, names and ASCII numbers are words
// separated by white space; in a BINARY file an array's values are big-endian and start on the
// line after the words that announce it. Every read checks the bytes left first, so a truncated
// or malformed file throws a VtkFormatError that says where, and an announced count never
// allocates more than the file can hold.

export class VtkFormatError extends Error {}

// The legacy data types: bytes per value in a BINARY file, and how DataView reads one.
// (`long` is 8 bytes, as VTK writes it on 64-bit Linux and macOS; vtkIdType arrays are
// written as 32-bit ints.)
const TYPES = {
  unsigned_char: [1, 'getUint8'], char: [1, 'getInt8'], signed_char: [1, 'getInt8'],
  unsigned_short: [2, 'getUint16'], short: [2, 'getInt16'],
  unsigned_int: [4, 'getUint32'], int: [4, 'getInt32'], vtkidtype: [4, 'getInt32'],
  unsigned_long: [8, 'getBigUint64'], long: [8, 'getBigInt64'],
  unsigned_long_long: [8, 'getBigUint64'], long_long: [8, 'getBigInt64'],
  vtktypeuint64: [8, 'getBigUint64'], vtktypeint64: [8, 'getBigInt64'],
  float: [4, 'getFloat32'], double: [8, 'getFloat64'],
};
const STRING_TYPES = ['string', 'utf8_string'];

const isSpace = (b) => b === 32 || (b >= 9 && b <= 13);
const ASCII_SPECIALS = { nan: NaN, '-nan': NaN, inf: Infinity, '+inf': Infinity, '-inf': -Infinity };

// A name as VTK writes it: characters outside a word's safe set as %XX.
export function decodeName(word) {
  return word.replace(/%([0-9A-Fa-f]{2})/g, (_, hex) => String.fromCharCode(parseInt(hex, 16)));
}

export class VtkCursor {
  constructor(bytes, binary) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.binary = binary;
    this.at = 0;
  }

  get left() {
    return this.bytes.length - this.at;
  }

  // The next word, or null at the end of the file.
  word() {
    const b = this.bytes;
    while (this.at < b.length && isSpace(b[this.at])) ++this.at;
    if (this.at >= b.length) return null;
    const start = this.at;
    while (this.at < b.length && !isSpace(b[this.at])) ++this.at;
    return latin1(b, start, Math.min(this.at, start + 200));
  }

  // The next word in lower case (keywords are case-insensitive); null at the end.
  keyword() {
    return this.word()?.toLowerCase() ?? null;
  }

  // The next word, which must be there: `what` names it in the error.
  required(what) {
    const w = this.word();
    if (w === null) throw new VtkFormatError(`it ends where ${what} should follow`);
    return w;
  }

  // The next word as a whole number >= 0.
  count(what) {
    const w = this.required(what);
    if (!/^\+?\d+$/.test(w)) throw new VtkFormatError(`${what} is "${w}", not a whole number`);
    return Number(w);
  }

  // The rest of the current line (without its end).
  line() {
    const b = this.bytes;
    const start = this.at;
    while (this.at < b.length && b[this.at] !== 10) ++this.at;
    const text = latin1(b, start, Math.min(this.at, start + 1024)).replace(/\r$/, '');
    if (this.at < b.length) ++this.at;
    return text;
  }

  // The position and word that follow, without moving: for optional parts.
  peekKeyword() {
    const at = this.at;
    const w = this.keyword();
    this.at = at;
    return w;
  }

  // A METADATA block (component names, information keys) that VTK may write after an array:
  // skipped up to the empty line that ends it.
  skipMetadata() {
    if (this.peekKeyword() !== 'metadata') return;
    this.word();
    this.line();
    while (this.at < this.bytes.length && this.line().trim() !== '');
  }

  // `count` values of the legacy type `type` as a Float64Array (a string array is skipped and
  // gives null); `what` names the array in errors.
  values(type, count, what) {
    const t = type.toLowerCase();
    if (STRING_TYPES.includes(t)) {
      this.skipStrings(count, what);
      return null;
    }
    const spec = TYPES[t];
    if (!spec && this.at >= this.bytes.length) throw this.endsEarly(what, count, 0);
    if (!spec)
      throw new VtkFormatError(`${what} has the data type "${type}", which the page does not read`);
    return this.binary ? this.binaryValues(spec, count, what) : this.asciiValues(count, what);
  }

  asciiValues(count, what) {
    // Each value takes at least one character and a separator.
    if (count > this.left / 2 + 1) throw this.endsEarly(what, count);
    const out = new Float64Array(count);
    for (let i = 0; i < count; ++i) {
      const w = this.word();
      if (w === null) throw this.endsEarly(what, count, i);
      let x = Number(w);
      if (Number.isNaN(x)) {
        x = ASCII_SPECIALS[w.toLowerCase()];
        if (x === undefined)
          throw new VtkFormatError(`${what}: value ${i} is "${w.slice(0, 40)}", not a number`);
      }
      out[i] = x;
    }
    return out;
  }

  binaryValues([size, getter], count, what) {
    this.toNextLine(what);
    if (count * size > this.left) throw this.endsEarly(what, count, Math.floor(this.left / size));
    const out = new Float64Array(count);
    const v = this.view;
    let at = this.at;
    // One loop per getter: a call through a computed name would be several times slower.
    switch (getter) {
      case 'getFloat32': for (let i = 0; i < count; ++i, at += 4) out[i] = v.getFloat32(at); break;
      case 'getFloat64': for (let i = 0; i < count; ++i, at += 8) out[i] = v.getFloat64(at); break;
      case 'getInt32': for (let i = 0; i < count; ++i, at += 4) out[i] = v.getInt32(at); break;
      case 'getBigInt64':
        for (let i = 0; i < count; ++i, at += 8) out[i] = Number(v.getBigInt64(at));
        break;
      default:
        for (let i = 0; i < count; ++i, at += size)
          out[i] = size === 8 ? Number(v[getter](at)) : v[getter](at);
    }
    this.at = at;
    return out;
  }

  // Strings: one a line in an ASCII file; in a BINARY file each after a big-endian length whose
  // first byte's top two bits say its size (11: 1 byte, 10: 2, 01: 4, 00: 8).
  skipStrings(count, what) {
    if (!this.binary) {
      this.line(); // the end of the line that announced them
      for (let i = 0; i < count; ++i) {
        if (this.at >= this.bytes.length) throw this.endsEarly(what, count, i);
        this.line();
      }
      return;
    }
    this.toNextLine(what);
    for (let i = 0; i < count; ++i) {
      if (this.left < 1) throw this.endsEarly(what, count, i);
      const tag = this.bytes[this.at] >> 6;
      const size = [8, 4, 2, 1][tag];
      if (this.left < size) throw this.endsEarly(what, count, i);
      let length = 0;
      for (let k = 0; k < size; ++k)
        length = length * 256 + (k === 0 ? this.bytes[this.at] & 0x3f : this.bytes[this.at + k]);
      this.at += size;
      if (length > this.left) throw this.endsEarly(what, count, i);
      this.at += length;
    }
  }

  // A BINARY array starts after the end of the line that announced it.
  toNextLine(what) {
    const b = this.bytes;
    while (this.at < b.length && b[this.at] !== 10) ++this.at;
    if (this.at >= b.length) throw this.endsEarly(what, 1, 0);
    ++this.at;
  }

  endsEarly(what, count, read) {
    return new VtkFormatError(`it ends early: ${what} announces ${count} values` +
      (read === undefined ? ', more than the rest of the file holds' : ` but holds ${read}`));
  }
}

function latin1(bytes, start, end) {
  let s = '';
  for (let i = start; i < end; ++i) s += String.fromCharCode(bytes[i]);
  return s;
}
