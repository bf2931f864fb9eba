#!/bin/sh
# Times psignifit 2.5.6 (Debian package `psignifit`) and burrlab on the same
# 6-level data sets with a 1999-sample bootstrap, and prints the ratio.
#   sh tests/bench/psignifit_time.sh [BUILD_DIR] [REPEATS]
# BUILD_DIR holds tests/bench/burrlab_bench (default build/release); REPEATS
# psignifit runs per case (default 15). psignifit's time is the one it prints
# itself in verbose mode ("0.05 seconds."), without process start-up; its
# median is compared with burrlab_bench's mean real time per fit.
set -eu
build=${1:-build/release}
repeats=${2:-15}
bench="$build/tests/bench/burrlab_bench"
command -v psignifit >/dev/null || { echo "psignifit is not installed" >&2; exit 1; }
[ -x "$bench" ] || { echo "$bench not built (ninja burrlab_bench)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The data of tests/bench/psychometric_bench.cc.
printf '1 21 40\n2 24 40\n3 29 40\n4 35 40\n5 38 40\n6 40 40\n' >"$tmp/2afc"
printf '1 2 40\n2 6 40\n3 15 40\n4 28 40\n5 35 40\n6 38 40\n' >"$tmp/yesno"

"$bench" --benchmark_filter=BootstrapFit --benchmark_format=csv \
  --benchmark_min_time=1 2>/dev/null >"$tmp/burrlab.csv"

printf '%-16s %14s %14s %8s\n' case "psignifit ms" "burrlab ms" ratio
for case in logistic_2afc weibull_2afc cumnorm_yesno gumbel_yesno; do
  sigmoid=${case%_*}
  task=${case#*_}
  case $sigmoid in
    logistic) shape=logistic ;;
    weibull) shape=Weibull ;;
    cumnorm) shape="cumulative Gaussian" ;;
    gumbel) shape=Gumbel ;;
  esac
  if [ "$task" = 2afc ]; then intervals=2; else intervals=1; fi
  printf '#shape %s\n#n_intervals %s\n#matrix_format xrn\n#runs 1999\n#sens 0\n#cuts 0.2, 0.5, 0.8\n#conf 0.023, 0.159, 0.841, 0.977, 0.025, 0.975\n#random_seed 1\n#verbose true\n#write_th_lims null\n' \
    "$shape" "$intervals" >"$tmp/prefs"
  i=0
  : >"$tmp/times"
  while [ $i -lt "$repeats" ]; do
    psignifit "$tmp/$task" "$tmp/prefs" 2>&1 | sed -n 's/^\([0-9.]*\) seconds\.$/\1/p' >>"$tmp/times"
    i=$((i + 1))
  done
  theirs=$(sort -n "$tmp/times" | awk '{a[NR]=$1} END {print 1000 * a[int((NR + 1) / 2)]}')
  ours=$(awk -F, -v n="\"BootstrapFit/$case\"" '$1 == n {print $3}' "$tmp/burrlab.csv")
  awk -v c="$case" -v t="$theirs" -v o="$ours" \
    'BEGIN {printf "%-16s %14.1f %14.1f %8.2f\n", c, t, o, t / o}'
done
echo "ratio = psignifit time / burrlab time (above 1: burrlab is faster)"
