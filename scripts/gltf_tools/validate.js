// Validates glTF / GLB files with the Khronos glTF validator (npm
// gltf-validator). Prints one JSON line per file with the counts of errors,
// warnings, infos and hints, and the messages of errors and warnings.
// Exit status 0 iff every file has 0 errors and 0 warnings.
//   node scripts/gltf_tools/validate.js FILE...
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)),
                    (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
      }),
  });
  const issues = report.issues;
  const serious = issues.messages
      .filter((m) => m.severity <= 1)
      .map((m) => `${m.code}: ${m.message} (${m.pointer || ''})`);
  console.log(JSON.stringify({
    file,
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    hints: issues.numHints,
    messages: serious,
  }));
  return issues.numErrors === 0 && issues.numWarnings === 0;
}

(async () => {
  let ok = true;
  for (const file of process.argv.slice(2)) {
    try {
      ok = (await validate(file)) && ok;
    } catch (e) {
      console.log(JSON.stringify({file, errors: 1, messages: [String(e)]}));
      ok = false;
    }
  }
  process.exit(ok ? 0 : 1);
})();
