#!/usr/bin/env node
// One-off converter: Utah teapot from the npm package `teapot` (v1.0.0,
// public domain, CommonJS port by Mikola Lysenko) -> Wavefront OBJ.
//
// The package exports { positions: [[x,y,z],...], cells: [[i,j,k],...] }
// with 0-based triangle indices. We write `v x y z` and 1-based `f i j k`.
//
// Reproduce meshes/teapot.obj (run outside the repo, any temp dir):
//   cd "$(mktemp -d)" && npm pack teapot@1.0.0 && tar xzf teapot-1.0.0.tgz
//   node /path/to/repo/meshes/tools/teapot_to_obj.js package /path/to/repo/meshes/teapot.obj
//
// Usage: teapot_to_obj.js <teapot package dir | teapot.js> [out.obj]
// Without out.obj the OBJ goes to stdout.
'use strict';
const fs = require('fs');
const path = require('path');

const src = process.argv[2];
if (!src) {
  console.error('usage: teapot_to_obj.js <teapot package dir | teapot.js> [out.obj]');
  process.exit(2);
}
const mod = require(path.resolve(src));
const pos = mod.positions, cells = mod.cells;
if (!Array.isArray(pos) || !Array.isArray(cells)) throw new Error('unexpected teapot module layout');

let version = 'unknown';
try {
  const dir = fs.statSync(src).isDirectory() ? src : path.dirname(src);
  version = JSON.parse(fs.readFileSync(path.join(dir, 'package.json'), 'utf8')).version;
} catch (e) { /* version is informational only */ }

const out = [];
out.push('# Utah teapot (Martin Newell, 1975). Public domain.');
out.push(`# Converted from npm package teapot@${version} by meshes/tools/teapot_to_obj.js`);
out.push(`# ${pos.length} vertices, ${cells.length} triangles`);
for (const p of pos) {
  if (p.length !== 3 || !p.every(Number.isFinite)) throw new Error('bad position ' + JSON.stringify(p));
  out.push(`v ${p[0]} ${p[1]} ${p[2]}`);
}
for (const c of cells) {
  for (const i of c) {
    if (!Number.isInteger(i) || i < 0 || i >= pos.length) throw new Error('bad index ' + JSON.stringify(c));
  }
  out.push('f ' + c.map(i => i + 1).join(' '));
}
const text = out.join('\n') + '\n';
if (process.argv[3]) fs.writeFileSync(process.argv[3], text);
else process.stdout.write(text);
