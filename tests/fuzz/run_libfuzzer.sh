#!/usr/bin/env bash
# Runs every libFuzzer executable of a -DBURRLAB_LIBFUZZER=ON build for RUNS
# executions from a fresh copy of its corpus, with its dictionary, and prints
# executions, crashes and timeouts per target (`make fuzz` calls it).
# Usage: tests/fuzz/run_libfuzzer.sh BUILD_DIR [RUNS] [TARGET...]
set -euo pipefail
build=${1:?usage: run_libfuzzer.sh BUILD_DIR [RUNS] [TARGET...]}
runs=${2:-1000000}
shift $(($# < 2 ? $# : 2))
here=$(cd "$(dirname "$0")" && pwd)
# target and longest input (bytes), as in fuzz_targets.cc
all=(protocol:8192 station:4096 station_script:4096 material:4096 nrrd:4096 measured:4096
     traces:4096 psychometric:4096 beh_tsv:4096 physio_sidecar:4096 physio_rows:4096
     participants:4096)
# A single input taking longer than this (s) is a timeout.
timeout_s=10
work=$build/fuzz-runs
failed=0
rows=()
for entry in "${all[@]}"; do
  name=${entry%%:*}
  max_len=${entry##*:}
  if [ $# -gt 0 ] && [[ " $* " != *" $name "* ]]; then continue; fi
  exe=$build/tests/fuzz/fuzz_$name
  dir=$work/$name
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  cp "$here/corpus/$name/"* "$dir/corpus/"
  start=$(date +%s)
  set +e
  "$exe" -runs="$runs" -max_len="$max_len" -timeout="$timeout_s" -rss_limit_mb=2560 \
    -dict="$here/dictionaries/$name.dict" -artifact_prefix="$dir/artifacts/" \
    -print_final_stats=1 "$dir/corpus" >"$dir/log" 2>&1
  code=$?
  set -e
  seconds=$(($(date +%s) - start))
  executed=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
  crashes=$(find "$dir/artifacts" -name 'crash-*' -o -name 'leak-*' -o -name 'oom-*' | wc -l)
  timeouts=$(find "$dir/artifacts" -name 'timeout-*' | wc -l)
  if [ "$code" -ne 0 ] && [ "$crashes" -eq 0 ] && [ "$timeouts" -eq 0 ]; then
    crashes=1  # stopped without an artifact (e.g. a failure at start-up)
  fi
  if [ "$crashes" -ne 0 ] || [ "$timeouts" -ne 0 ]; then
    failed=1
    echo "fuzz_$name: see $dir/log and $dir/artifacts/" >&2
  fi
  rows+=("$(printf '%-15s %10s %8s %9s %7ss' "$name" "${executed:-?}" "$crashes" "$timeouts" "$seconds")")
done
printf '%-15s %10s %8s %9s %8s\n' target executions crashes timeouts wall
printf '%s\n' "${rows[@]}"
exit $failed
