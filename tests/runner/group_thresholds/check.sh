#!/usr/bin/env bash
# Group thresholds of a 12-subject constant-stimuli study against pandas:
# `burrlab study` runs 12 simulated subjects, `burrlab analyze thresholds`
# prints and writes (--json) each subject's fitted threshold and the group
# summary and draws the group figure (--plots), and group_thresholds.py recomputes the group from the exports with
# pandas, written independently of burrlab's code (the per-subject fits
# themselves are checked against psignifit 2.5.6 by the analysis tests).
#   check.sh BURRLAB SOURCE_DIR WORK_DIR
set -euo pipefail
burrlab=$1
source_dir=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
"$burrlab" study "$source_dir/protocols/examples/constant_stimuli_ce_ratio.toml" \
  --simulated-subjects 12 --seed 3 --jobs 2 --renderings 4 \
  --out "$work/study" > /dev/null
"$burrlab" analyze thresholds "$work/study" --plots "$work/figures" \
  > "$work/thresholds.txt"
"$burrlab" analyze thresholds "$work/study" --json > "$work/thresholds.json"
# Debian's python3-pandas is installed for the system interpreter, which a
# python3 earlier on PATH (pyenv, a virtualenv) may not see.
/usr/bin/python3 "$(dirname "$0")/group_thresholds.py" "$work/study" \
  "$work/thresholds.json" "$work/thresholds.txt"
