// Runs the Khronos glTF validator (npm package gltf-validator) on each file given; prints every
// issue and exits 1 on any error or warning (infos and hints are printed, not counted).
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');
(async () => {
  let bad = 0;
  for (const file of process.argv.slice(2)) {
    const data = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(data, {uri: path.basename(file), maxIssues: 50,
      externalResourceFunction: () => Promise.reject(new Error('no external resources'))});
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
    for (const m of i.messages) console.log(`  [${m.severity}] ${m.code} ${m.pointer || ''}: ${m.message}`);
    if (i.numErrors > 0 || i.numWarnings > 0) bad = 1;
  }
  process.exit(bad);
})();
