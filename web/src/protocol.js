// The ddsimp wire protocol (docs/protocol.md) for the browser: the message types come from the
// project's own schema, protocol/proto/ddsimp/v1/ddsimp.proto, parsed by protobufjs at start-up
// (bundled as text by Vite), so there is no second copy of the schema to keep in step.
import protobuf from 'protobufjs';
import schemaText from '../../protocol/proto/ddsimp/v1/ddsimp.proto?raw';

export const PROTOCOL_VERSION = 1;
const MAGIC = [0x44, 0x44, 0x53, 0x50]; // "DDSP"
export const HEADER_BYTES = 12;

const root = protobuf.parse(schemaText, { keepCase: true }).root;
const MessageType = root.lookupEnum('ddsimp.v1.MessageType').values;

// HELLO -> Hello, SET_SESSION_STATE -> SetSessionState: the schema names each message after its
// type, so the table is derived rather than written out.
const typeOfNumber = new Map();
const numberOfName = new Map();
for (const [enumName, number] of Object.entries(MessageType)) {
  if (number === 0) continue;
  const name = enumName
    .toLowerCase()
    .split('_')
    .map((w) => w[0].toUpperCase() + w.slice(1))
    .join('');
  typeOfNumber.set(number, { name, type: root.lookupType(`ddsimp.v1.${name}`) });
  numberOfName.set(name, number);
}

export function enumValues(name) {
  return root.lookupEnum(`ddsimp.v1.${name}`).values;
}

export class FrameError extends Error {}

// One frame: the 12-byte header and the message's protobuf encoding.
export function encodeFrame(name, fields) {
  const number = numberOfName.get(name);
  if (number === undefined) throw new FrameError(`no message type ${name}`);
  const { type } = typeOfNumber.get(number);
  const payload = type.encode(type.fromObject(fields)).finish();
  const frame = new Uint8Array(HEADER_BYTES + payload.length);
  const view = new DataView(frame.buffer);
  frame.set(MAGIC, 0);
  view.setUint16(4, PROTOCOL_VERSION, true);
  view.setUint16(6, number, true);
  view.setUint32(8, payload.length, true);
  frame.set(payload, HEADER_BYTES);
  return frame;
}

// A binary WebSocket message holds exactly one frame. Returns { name, message } with 64-bit
// integers as Numbers and every field present (defaults filled in).
export function decodeFrame(buffer) {
  const bytes = new Uint8Array(buffer);
  if (bytes.length < HEADER_BYTES) throw new FrameError(`a frame of ${bytes.length} bytes`);
  for (let i = 0; i < 4; ++i)
    if (bytes[i] !== MAGIC[i]) throw new FrameError('a frame without the "DDSP" magic');
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const version = view.getUint16(4, true);
  if (version !== PROTOCOL_VERSION) throw new FrameError(`protocol version ${version}`);
  const number = view.getUint16(6, true);
  const length = view.getUint32(8, true);
  if (length !== bytes.length - HEADER_BYTES)
    throw new FrameError(`a payload of ${bytes.length - HEADER_BYTES} bytes announced as ${length}`);
  const known = typeOfNumber.get(number);
  if (!known) throw new FrameError(`unknown message type ${number}`);
  const decoded = known.type.decode(bytes.subarray(HEADER_BYTES));
  return {
    name: known.name,
    message: known.type.toObject(decoded, { longs: Number, defaults: true, arrays: true }),
  };
}
