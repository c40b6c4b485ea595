// One reduction by meshoptimizer's attribute-aware simplifiers (npm's meshoptimizer, WebAssembly),
// for ddsimp_report (meshopt_js_peer.cpp), which writes the input and reads the result:
//
//   node meshopt_peer.mjs attributes|update WEIGHT TARGET_INDICES IN OUT
//
// IN (little-endian): u32 vertices, u32 indices, u32 attributes per vertex; f32 positions
// (3 per vertex); u32 indices; f32 attributes, already scaled by their field's range. Every
// attribute gets WEIGHT. No vertex lock, no flags, no error bound: only the target stops it.
// OUT: f64 seconds and f64 CPU seconds of the call, f64 its error, u32 indices, u32 vertices;
// u32 indices into IN's vertices; for `update` then f32 positions and f32 attributes, every
// vertex, as simplifyWithUpdate left them. Errors go to stderr, exit status 1.
import { readFileSync, writeFileSync } from "node:fs";
import { performance } from "node:perf_hooks";

const NO_ERROR_BOUND = 3.4028234663852886e38; // FLT_MAX

async function loadSimplifier() {
    try {
        return (await import("meshoptimizer")).MeshoptSimplifier;
    } catch (e) {
        throw new Error(
            "the npm package meshoptimizer is not installed beside this script " +
                `(${e.code || e.message}): run \`npm ci\` in bench/report (bench/report/run.sh does)`,
        );
    }
}

function readInput(path) {
    const bytes = readFileSync(path);
    const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
    const [vertices, indexCount, attributeCount] = new Uint32Array(buffer, 0, 3);
    let at = 12;
    const take = (Type, n) => {
        const array = new Type(buffer, at, n);
        at += n * 4;
        return array;
    };
    const positions = take(Float32Array, 3 * vertices);
    const indices = take(Uint32Array, indexCount);
    const attributes = take(Float32Array, attributeCount * vertices);
    if (at !== buffer.byteLength) throw new Error(`${path}: ${buffer.byteLength} bytes, expected ${at}`);
    return { vertices, positions, indices, attributes, attributeCount };
}

async function main() {
    const [mode, weightText, targetText, inPath, outPath] = process.argv.slice(2);
    if (!["attributes", "update"].includes(mode) || !outPath)
        throw new Error("usage: node meshopt_peer.mjs attributes|update WEIGHT TARGET_INDICES IN OUT");
    const simplifier = await loadSimplifier();
    await simplifier.ready;
    const input = readInput(inPath);
    const weights = new Array(input.attributeCount).fill(Number(weightText));
    const target = Number(targetText);

    const cpuStart = process.cpuUsage();
    const start = performance.now();
    let indices, error;
    if (mode === "attributes") {
        [indices, error] = simplifier.simplifyWithAttributes(
            input.indices, input.positions, 3, input.attributes, input.attributeCount, weights,
            null, target, NO_ERROR_BOUND);
    } else {
        let count;
        [count, error] = simplifier.simplifyWithUpdate(
            input.indices, input.positions, 3, input.attributes, input.attributeCount, weights,
            null, target, NO_ERROR_BOUND);
        indices = input.indices.subarray(0, count);
    }
    const seconds = (performance.now() - start) / 1000;
    const cpu = process.cpuUsage(cpuStart);

    const header = Buffer.alloc(32);
    header.writeDoubleLE(seconds, 0);
    header.writeDoubleLE((cpu.user + cpu.system) / 1e6, 8);
    header.writeDoubleLE(error, 16);
    header.writeUInt32LE(indices.length, 24);
    header.writeUInt32LE(mode === "update" ? input.vertices : 0, 28);
    const parts = [header, Buffer.from(indices.buffer, indices.byteOffset, indices.byteLength)];
    if (mode === "update")
        for (const a of [input.positions, input.attributes])
            parts.push(Buffer.from(a.buffer, a.byteOffset, a.byteLength));
    writeFileSync(outPath, Buffer.concat(parts));
}

main().catch((e) => {
    process.stderr.write(`meshopt_peer.mjs: ${e.message}\n`);
    process.exit(1);
});
