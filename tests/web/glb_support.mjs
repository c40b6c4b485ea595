// Checks of a .glb shared by the glTF tests: Khronos's glTF-Validator, and three.js's
// GLTFLoader (with its meshopt decoder) under node.
import assert from 'node:assert/strict';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { requireFromWeb } from './harness.mjs';

const validator = requireFromWeb('gltf-validator');
const three = path.join(process.env.DDSIMP_WEB_SRC, 'node_modules/three/examples/jsm');
const { GLTFLoader } = await import(pathToFileURL(path.join(three, 'loaders/GLTFLoader.js')));
const { MeshoptDecoder } = await import(pathToFileURL(path.join(three, 'libs/meshopt_decoder.module.js')));

// The validator's report; fails on any error, naming them.
export async function validateGlb(bytes, what) {
  const report = await validator.validateBytes(new Uint8Array(bytes));
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  assert.equal(report.issues.numErrors, 0,
    `${what}: the glTF validator finds errors: ${JSON.stringify(errors, null, 1)}`);
  return report;
}

// The mesh three.js makes of the file.
export async function loadWithThree(bytes) {
  const loader = new GLTFLoader();
  loader.setMeshoptDecoder(MeshoptDecoder);
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await loader.parseAsync(buffer, '');
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
  assert.equal(meshes.length, 1, 'one mesh');
  return meshes[0];
}
