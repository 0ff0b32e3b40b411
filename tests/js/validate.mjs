// Runs the Khronos glTF-Validator on each file named on the command line and
// prints one JSON array: for each file its path and the validator's issues
// (numErrors, numWarnings, numInfos, numHints, messages). Exit status 0 when
// every file was validated (whatever it found), 2 on a usage or I/O error.
// Used by tests/tests/glb_validator.rs; install with `npm ci` here first.
import { readFile } from "node:fs/promises";
import path from "node:path";
import validator from "gltf-validator";

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error("usage: node validate.mjs FILE.glb...");
  process.exit(2);
}
const reports = [];
for (const file of files) {
  const bytes = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) =>
      readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then(
        (b) => new Uint8Array(b),
      ),
  });
  reports.push({ file, validatorVersion: report.validatorVersion, issues: report.issues });
}
console.log(JSON.stringify(reports, null, 1));
