// A minimal native-protocol client for the page tests: frames over TCP, one message at a time,
// with the messages from the project's own schema.
import { readFileSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { requireFromWeb } from './harness.mjs';

const protobuf = requireFromWeb('protobufjs');
const schema = protobuf.parse(readFileSync(path.join(process.env.DDSIMP_WEB_SRC,
  '../protocol/proto/ddsimp/v1/ddsimp.proto'), 'utf8'), { keepCase: true }).root;
const TYPES = { Hello: 1, Welcome: 2, Error: 5, JoinSession: 10, SessionState: 13,
  UploadBegin: 20, UploadChunk: 21, UploadEnd: 22, UploadResult: 23 }; // docs/protocol.md

// A minimal native-protocol client: frames over TCP, one message at a time.
export class NativeClient {
  constructor(port) {
    this.socket = net.connect(port, '127.0.0.1');
    this.buffer = Buffer.alloc(0);
    this.waiting = [];
    this.frames = [];
    this.socket.on('data', (d) => {
      this.buffer = Buffer.concat([this.buffer, d]);
      while (this.buffer.length >= 12 && this.buffer.length >= 12 + this.buffer.readUInt32LE(8)) {
        const type = this.buffer.readUInt16LE(6);
        const payload = this.buffer.subarray(12, 12 + this.buffer.readUInt32LE(8));
        this.buffer = this.buffer.subarray(12 + payload.length);
        const name = Object.keys(TYPES).find((k) => TYPES[k] === type);
        if (name) this.frames.push({ name, message: schema.lookupType(`ddsimp.v1.${name}`)
          .toObject(schema.lookupType(`ddsimp.v1.${name}`).decode(payload), { longs: Number }) });
        this.wake();
      }
    });
  }

  send(name, fields) {
    const type = schema.lookupType(`ddsimp.v1.${name}`);
    const payload = type.encode(type.fromObject(fields)).finish();
    const header = Buffer.alloc(12);
    header.write('DDSP', 0, 'latin1');
    header.writeUInt16LE(1, 4);
    header.writeUInt16LE(TYPES[name], 6);
    header.writeUInt32LE(payload.length, 8);
    this.socket.write(Buffer.concat([header, payload]));
  }

  wake() {
    for (const w of this.waiting.splice(0)) w();
  }

  // The next message called `name` (others are skipped); an Error fails.
  async next(name) {
    for (;;) {
      const i = this.frames.findIndex((f) => f.name === name || f.name === 'Error');
      if (i >= 0) {
        const [f] = this.frames.splice(i, 1);
        if (f.name === 'Error') throw new Error(`the server says: ${f.message.message}`);
        return f.message;
      }
      await new Promise((resolve) => this.waiting.push(resolve));
    }
  }
}
