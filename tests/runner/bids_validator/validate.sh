#!/usr/bin/env bash
# burrlab's exports pass the official BIDS validator (install.sh installs it):
# `burrlab run` of a simulated subject beside one answering at the prompt,
# one subject's two sessions (--session 1 and 2), and `burrlab study`, each
# with two authors and participants.tsv, must give no error, no warning, and
# no ignored issue but NO_T1W (code 53: "Dataset does not contain any T1w
# scans", an MRI check the validator itself ignores by default). Two runs
# without enough authors show the warnings no export can avoid without
# inventing names: NO_AUTHORS (code 113) with none, TOO_FEW_AUTHORS (102) with
# one. Every issue is printed with its code.
#   validate.sh BURRLAB VALIDATOR_PREFIX SOURCE_DIR WORK_DIR
set -euo pipefail
burrlab=$1
validator=$2/node_modules/.bin/bids-validator
source_dir=$3
work=$4
protocol=$source_dir/protocols/examples/two_interval_2afc.toml
rm -rf "$work"
mkdir -p "$work"
cd "$work"
authors=(--author "Doe, Jane" --author "Roe, Richard")
failed=0

# check DIR EXPECTED: validates DIR, prints every issue, and fails unless it
# has no error, exactly the warnings EXPECTED lists (codes, space separated)
# and no ignored issue but code 53.
check() {
  local dir=$1 expected=$2
  "$validator" "$dir" --json > "$dir.json" 2> "$dir.stderr" || true
  if ! node - "$dir" "$dir.json" "$expected" <<'NODE'
const [dir, file, expected] = process.argv.slice(2);
const fs = require('fs');
let report;
try {
  report = JSON.parse(fs.readFileSync(file, 'utf8'));
} catch (e) {
  console.log(`${dir}: the validator gave no JSON report (${e.message}):`);
  console.log(fs.readFileSync(`${dir}.stderr`, 'utf8'));
  process.exit(1);
}
const issues = report.issues;
const codes = (list) => list.map((i) => i.code).sort((a, b) => a - b);
for (const kind of ['errors', 'warnings', 'ignored']) {
  for (const issue of issues[kind]) {
    console.log(`${dir}: ${kind.replace(/s$/, '')} ${issue.code} ` +
                `${issue.key}: ${issue.reason}`);
    for (const f of issue.files || []) {
      if (f.file || f.evidence) {
        console.log(`    ${f.file ? f.file.relativePath : ''} ` +
                    `${f.evidence || ''}`);
      }
    }
  }
}
const want = expected.split(' ').filter((c) => c !== '').map(Number)
                     .sort((a, b) => a - b);
const warnings = codes(issues.warnings);
const unexpectedIgnored = codes(issues.ignored).filter((c) => c !== 53);
const summary = report.summary;
console.log(`${dir}: ${issues.errors.length} errors, warnings ` +
            `[${warnings.join(' ')}] (expected [${want.join(' ')}]), ` +
            `ignored [${codes(issues.ignored).join(' ')}]; ` +
            `${summary.subjects.length} subjects, sessions ` +
            `[${summary.sessions.join(' ')}], ${summary.totalFiles} files`);
const ok = issues.errors.length === 0 &&
           JSON.stringify(warnings) === JSON.stringify(want) &&
           unexpectedIgnored.length === 0;
process.exit(ok ? 0 : 1);
NODE
  then
    echo "FAILED: $dir"
    failed=1
  fi
}

# A simulated subject with the experimenter's values, and a person typing
# answers (from a pipe) with a table row of theirs.
"$burrlab" run "$protocol" --subject 01 --out run --seed 7 \
    --observer simulated:weber=0.3 "${authors[@]}" \
    --participant age=34 --participant sex=F --participant handedness=R \
    --participant group=expert
printf 'participant_id,age,group\r\nsub-02,51,novice\r\n' > roster.csv
printf '1\n2\n1\n1\n2\n2\n1\n2\n1\n1\n2\n1\n' |
    "$burrlab" run "$protocol" --subject 02 --out run --seed 8 \
        --participants roster.csv > /dev/null
check run ""

# One subject, two sessions.
for session in 1 2; do
  "$burrlab" run "$protocol" --subject 01 --session "$session" --out sessions \
      --seed "$session" --observer simulated "${authors[@]}" \
      --participant age=34
done
check sessions ""

# A simulated population.
"$burrlab" study "$protocol" --simulated-subjects 3 --out study --seed 3 \
    --renderings 2 --weber-spread 0.3 --jobs 2 "${authors[@]}" 2> /dev/null
check study ""

# What no export can avoid without inventing names.
"$burrlab" run "$protocol" --subject 01 --out no-authors --observer simulated
check no-authors "113"
"$burrlab" run "$protocol" --subject 01 --out one-author --observer simulated \
    --author "Doe, Jane"
check one-author "102"

exit $failed
