#!/usr/bin/env node
// Decodes a GLB's EXT_meshopt_compression with meshoptimizer's reference JavaScript decoder (the
// one three.js ships, scripts/node/node_modules/three/examples/jsm/libs/meshopt_decoder.module.js)
// and writes a plain GLB: every compressed view decoded (filters applied) into buffer 0, the
// fallback buffer and the extension dropped, every other view copied. Lets tools that do not
// decode EXT_meshopt_compression (and tests) read what a browser decodes.
//   node meshopt_unpack.mjs NODE_MODULES IN.glb OUT.glb
// Exit codes: 0 written, 1 usage, 2 unreadable or undecodable input.
import fs from 'fs';
import path from 'path';
import { pathToFileURL } from 'url';

const kJson = 0x4E4F534A, kBin = 0x004E4942;

function readGlb(file) {
  const data = fs.readFileSync(file);
  if (data.readUInt32LE(0) !== 0x46546C67) throw new Error(file + ': not a GLB');
  let json = null, bin = Buffer.alloc(0);
  for (let off = 12; off < data.readUInt32LE(8);) {
    const len = data.readUInt32LE(off), type = data.readUInt32LE(off + 4);
    const chunk = data.subarray(off + 8, off + 8 + len);
    if (type === kJson) json = JSON.parse(chunk.toString('utf8'));
    else if (type === kBin) bin = chunk;
    off += 8 + len;
  }
  if (!json) throw new Error(file + ': no JSON chunk');
  return { json, bin };
}

function writeGlb(file, json, bin) {
  let text = Buffer.from(JSON.stringify(json), 'utf8');
  text = Buffer.concat([text, Buffer.alloc((4 - text.length % 4) % 4, 0x20)]);
  const head = Buffer.alloc(20), binHead = Buffer.alloc(8);
  const total = 20 + text.length + (bin.length ? 8 + bin.length : 0);
  head.writeUInt32LE(0x46546C67, 0); head.writeUInt32LE(2, 4); head.writeUInt32LE(total, 8);
  head.writeUInt32LE(text.length, 12); head.writeUInt32LE(kJson, 16);
  binHead.writeUInt32LE(bin.length, 0); binHead.writeUInt32LE(kBin, 4);
  fs.writeFileSync(file, Buffer.concat(bin.length ? [head, text, binHead, bin] : [head, text]));
}

async function main() {
  const [modules, input, output] = process.argv.slice(2);
  if (!output) { console.error('usage: meshopt_unpack.mjs NODE_MODULES IN.glb OUT.glb'); return 1; }
  const decoderPath = path.join(modules, 'three/examples/jsm/libs/meshopt_decoder.module.js');
  const { MeshoptDecoder } = await import(pathToFileURL(decoderPath).href);
  await MeshoptDecoder.ready;
  const { json, bin } = readGlb(input);
  const parts = [];
  let size = 0;
  for (const view of json.bufferViews || []) {
    const ext = view.extensions && view.extensions.EXT_meshopt_compression;
    let bytes;
    if (ext) {
      const source = new Uint8Array(bin.buffer, bin.byteOffset + (ext.byteOffset || 0), ext.byteLength);
      const target = new Uint8Array(ext.count * ext.byteStride);
      MeshoptDecoder.decodeGltfBuffer(target, ext.count, ext.byteStride, source, ext.mode, ext.filter || 'NONE');
      bytes = Buffer.from(target.buffer, target.byteOffset, target.byteLength);
      delete view.extensions.EXT_meshopt_compression;
      if (Object.keys(view.extensions).length === 0) delete view.extensions;
    } else {
      if (view.buffer !== 0) throw new Error(input + ': a view of buffer ' + view.buffer + ' without EXT_meshopt_compression');
      bytes = bin.subarray(view.byteOffset || 0, (view.byteOffset || 0) + view.byteLength);
    }
    const pad = (4 - size % 4) % 4;
    if (pad) parts.push(Buffer.alloc(pad));
    view.buffer = 0;
    view.byteOffset = size + pad;
    view.byteLength = bytes.length;
    parts.push(bytes);
    size += pad + bytes.length;
  }
  if (size % 4) { parts.push(Buffer.alloc(4 - size % 4)); size += 4 - size % 4; }
  json.buffers = [{ byteLength: size }];
  for (const key of ['extensionsUsed', 'extensionsRequired']) {
    if (!json[key]) continue;
    json[key] = json[key].filter((e) => e !== 'EXT_meshopt_compression');
    if (json[key].length === 0) delete json[key];
  }
  writeGlb(output, json, Buffer.concat(parts));
  return 0;
}

main().then((rc) => { process.exitCode = rc; }, (e) => { console.error(String(e && e.stack || e)); process.exitCode = 2; });
