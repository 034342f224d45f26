#!/usr/bin/env node
// Runs Khronos' glTF-Validator on each file given and prints one JSON object per file:
// {"file", "errors", "warnings", "infos", "hints", "messages": [first 20 issues]}.
// Exit code: 0 when every file has 0 errors, 1 otherwise, 2 on a usage or read problem.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const dir = path.dirname(file);
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 200,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) =>
        err ? reject(err.toString()) : resolve(new Uint8Array(data)));
    }),
  });
  const n = report.issues;
  return {
    file,
    errors: n.numErrors, warnings: n.numWarnings, infos: n.numInfos, hints: n.numHints,
    messages: n.messages.slice(0, 20).map((m) => ({code: m.code, severity: m.severity, message: m.message, pointer: m.pointer})),
  };
}

(async () => {
  const files = process.argv.slice(2);
  if (files.length === 0) { console.error('usage: validate.js FILE...'); process.exit(2); }
  let failed = false;
  for (const f of files) {
    try {
      const r = await validate(f);
      console.log(JSON.stringify(r));
      if (r.errors > 0) failed = true;
    } catch (e) {
      console.error(`${f}: ${e}`);
      process.exit(2);
    }
  }
  process.exit(failed ? 1 : 0);
})();
