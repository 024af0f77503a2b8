// Validates a .glb with the Khronos glTF validator and prints its report summary as JSON:
// {"numErrors": n, "numWarnings": n, "messages": [...]}. Exit code 0 when there are no
// errors, 1 when there are, 2 when the file cannot be read.
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

const path = process.argv[2];
let bytes;
try {
  bytes = new Uint8Array(await readFile(path));
} catch (e) {
  console.error(`cannot read ${path}: ${e.message}`);
  process.exit(2);
}
const report = await validator.validateBytes(bytes, { maxIssues: 50 });
const summary = {
  numErrors: report.issues.numErrors,
  numWarnings: report.issues.numWarnings,
  numInfos: report.issues.numInfos,
  messages: report.issues.messages.map((m) => `${m.severity} ${m.code} ${m.pointer ?? ''} ${m.message}`),
};
console.log(JSON.stringify(summary));
process.exit(summary.numErrors === 0 ? 0 : 1);
