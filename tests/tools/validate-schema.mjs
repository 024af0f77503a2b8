// Validates JSON files against a JSON Schema (draft 2020-12) with Ajv.
// Usage: node validate-schema.mjs SCHEMA FILE...   Exit 0 when every file is valid.
//        node validate-schema.mjs --expect-invalid PATH SCHEMA FILE...
//   Exit 0 when every file is invalid *and* one of its errors is at the JSON pointer PATH
//   (e.g. /rows): a file refused for another reason, an unreadable schema or a crash fail.
import { readFile } from 'node:fs/promises';
import Ajv2020 from 'ajv/dist/2020.js';

let args = process.argv.slice(2);
let expectAt = null;
if (args[0] === '--expect-invalid') {
  expectAt = args[1];
  args = args.slice(2);
}
const [schemaPath, ...files] = args;
if (!schemaPath || files.length === 0) {
  console.error('usage: validate-schema.mjs [--expect-invalid PATH] SCHEMA FILE...');
  process.exit(2);
}
const ajv = new Ajv2020({ allErrors: true, strict: false });
const validate = ajv.compile(JSON.parse(await readFile(schemaPath, 'utf8')));
let failures = 0;
for (const file of files) {
  const ok = validate(JSON.parse(await readFile(file, 'utf8')));
  console.log(`${ok ? 'valid' : 'INVALID'} ${file}${ok ? '' : ' ' + JSON.stringify(validate.errors)}`);
  if (expectAt === null) {
    if (!ok) failures += 1;
  } else if (ok) {
    console.log(`  expected ${file} to be refused at ${expectAt}, but it is valid`);
    failures += 1;
  } else if (!validate.errors.some((e) => e.instancePath === expectAt)) {
    console.log(`  expected an error at ${expectAt}; the errors are elsewhere`);
    failures += 1;
  }
}
process.exit(failures === 0 ? 0 : 1);
