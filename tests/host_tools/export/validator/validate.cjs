// Runs the Khronos glTF validator on one file and prints its JSON report.
// Usage: node validate.cjs FILE.glb  (exit 0 when the report was made)
'use strict';
const fs = require('fs');
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate.cjs FILE.glb');
  process.exit(2);
}
validator
    .validateBytes(new Uint8Array(fs.readFileSync(file)), {uri: file, maxIssues: 200})
    .then((report) => process.stdout.write(JSON.stringify(report, null, 1) + '\n'))
    .catch((error) => {
      console.error('gltf-validator: ' + error);
      process.exit(2);
    });
