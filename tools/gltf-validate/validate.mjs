#!/usr/bin/env node
// Validates .gltf/.glb files with the Khronos glTF validator (npm gltf-validator).
// Usage: node validate.mjs PATH...   (a PATH may be a folder: its .gltf/.glb files are checked)
// Prints one line per file with its error/warning/info counts, the errors themselves, and exits
// with status 1 when any file has an error (2 on bad usage).
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const args = process.argv.slice(2);
if (args.length === 0) {
  console.error('usage: node validate.mjs FILE_OR_FOLDER...');
  process.exit(2);
}

const files = [];
for (const a of args) {
  if (!fs.existsSync(a)) {
    console.error(`error: ${a}: no such file or folder`);
    process.exit(2);
  }
  if (fs.statSync(a).isDirectory()) {
    for (const f of fs.readdirSync(a).sort()) {
      if (/\.(gltf|glb)$/i.test(f)) files.push(path.join(a, f));
    }
  } else {
    files.push(a);
  }
}
if (files.length === 0) {
  console.error('error: no .gltf or .glb files found');
  process.exit(2);
}

let failed = 0;
for (const file of files) {
  const dir = path.dirname(file);
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    // Resources (.bin, textures) are read from beside the file.
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
      }),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos`);
  for (const m of i.messages) {
    if (m.severity === 0) console.log(`  error ${m.code} at ${m.pointer ?? ''}: ${m.message}`);
  }
  if (i.numErrors > 0) failed++;
}
console.log(`${files.length} files, ${failed} with errors`);
process.exit(failed > 0 ? 1 : 0);
