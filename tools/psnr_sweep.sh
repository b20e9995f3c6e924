#!/bin/bash
# Encodes meshes for PSNR targets against themselves (`meshlift encode M --psnr P`), decodes each
# file and measures it with `meshlift compare`: the figures of docs/RESULTS.md, "`encode --psnr`
# against the input". Writes one CSV row per mesh and target to standard output:
#   mesh,target_db,bytes,reported_db,compared_db,reached,seconds,density_kept
# reported_db is what encode's summary line says, compared_db what `compare` says of the decoded
# file (the two agree), reached is 1 if encode met the target, seconds the whole command's wall
# time, density_kept the denser remesh encode kept (empty: its automatic one).
#
# usage: tools/psnr_sweep.sh [-m MESHLIFT] [-t 60,65,70,75] MESH...
#   -m  the meshlift binary (default build/meshlift): run it twice with two builds to compare them
#   -t  comma-separated targets in dB
set -euo pipefail

meshlift=build/meshlift
targets=60,65,70,75
while getopts "m:t:" opt; do
  case "$opt" in
    m) meshlift="$OPTARG" ;;
    t) targets="$OPTARG" ;;
    *) sed -n '2,14p' "$0" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
if [ $# -eq 0 ]; then sed -n '2,14p' "$0" >&2; exit 2; fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "mesh,target_db,bytes,reported_db,compared_db,reached,seconds,density_kept"
for mesh in "$@"; do
  name=$(basename "${mesh%.*}")
  for target in ${targets//,/ }; do
    start=$(date +%s%N)
    if ! log=$("$meshlift" encode "$mesh" -o "$work/f.mlz" --psnr "$target" 2>&1); then
      echo "$name,$target,,,,0,,"
      continue
    fi
    ms=$((($(date +%s%N) - start) / 1000000))
    seconds=$(printf "%d.%03d" $((ms / 1000)) $((ms % 1000)))
    "$meshlift" decode "$work/f.mlz" -o "$work/f.ply" --binary >/dev/null 2>&1
    compared=$("$meshlift" compare "$mesh" "$work/f.ply" | sed -n 's/^PSNR: \([0-9.inf-]*\).*/\1/p')
    reported=$(echo "$log" | sed -n 's/.*: cut at [0-9]* of [0-9]* bytes, whose decode is \([0-9.inf-]*\) dB.*/\1/p;
                                      s/.*the whole stream decodes to \([0-9.inf-]*\) dB.*/\1/p' | tail -1)
    reached=$(echo "$log" | grep -c -- "--psnr $target: cut at" || true)
    kept=$(echo "$log" | sed -n 's/.*: ~\([0-9.]*\)x: .*: kept$/\1/p' | tail -1)
    echo "$name,$target,$(stat -c %s "$work/f.mlz"),$reported,$compared,$reached,$seconds,$kept"
  done
done
