#!/bin/bash
# tools/psnr_sweep.sh on a small mesh: a row per target, the target met where it can be (the
# decode measured by compare at or above it, and encode's own figure the same), and a target out
# of reach reported as not reached.
# usage: test_psnr_sweep.sh MESHLIFT SOURCE_DIR
set -euo pipefail
meshlift=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' >"$work/tet.off"
"$meshlift" subdivide "$work/tet.off" -o "$work/tet3.off" --scheme loop --levels 3 2>/dev/null
"$source_dir/tools/psnr_sweep.sh" -m "$meshlift" -t 60,300 "$work/tet3.off" >"$work/out.csv"
cat "$work/out.csv"

fail() { echo "FAILED: $*" >&2; exit 1; }
[ "$(head -1 "$work/out.csv")" = "mesh,target_db,bytes,reported_db,compared_db,reached,seconds,density_kept" ] ||
  fail "header"
[ "$(wc -l <"$work/out.csv")" -eq 3 ] || fail "a row per target"
awk -F, 'NR == 2 && !($1 == "tet3" && $2 == 60 && $6 == 1 && $5 >= 60 && $4 - $5 < 0.01 && $5 - $4 < 0.01 && $3 > 0) {
           print "60 dB row: " $0; bad = 1 }
         NR == 3 && !($2 == 300 && $6 == 0 && $5 < 300) { print "300 dB row: " $0; bad = 1 }
         END { exit bad }' "$work/out.csv" || fail "rows"
echo "ok"
