// Validates JSON files against a JSON Schema (draft 2020-12) with Ajv.
// Usage: node validate-schema.mjs SCHEMA FILE...   Exit 0 when every file is valid.
import { readFile } from 'node:fs/promises';
import Ajv2020 from 'ajv/dist/2020.js';

const [schemaPath, ...files] = process.argv.slice(2);
const ajv = new Ajv2020({ allErrors: true, strict: false });
const validate = ajv.compile(JSON.parse(await readFile(schemaPath, 'utf8')));
let failures = 0;
for (const file of files) {
  const ok = validate(JSON.parse(await readFile(file, 'utf8')));
  console.log(`${ok ? 'valid' : 'INVALID'} ${file}${ok ? '' : ' ' + JSON.stringify(validate.errors)}`);
  if (!ok) failures += 1;
}
process.exit(failures === 0 ? 0 : 1);
