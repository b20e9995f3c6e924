#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/) with clang, ASan and UBSan in build-fuzz, and runs
# each for SECONDS (default 60) on a working copy of its checked-in corpus, at nice 19 and at most
# two at a time (the machine is shared). Crashes, hangs (> 10 s) and leaks land in
# $FUZZ_WORK/artifacts/<target>/; reduce one, fix the cause, and add it to
# tests/fuzz/regressions/<target>/ (replayed by ctest). Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
./scripts/setup.sh --fuzz
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(decode stream base_mesh read_obj read_off read_ply read_stl)
build="${MESHLIFT_FUZZ_BUILD_DIR:-build-fuzz}"
work="${FUZZ_WORK:-$root/.cache/fuzz}"
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESHLIFT_FUZZ=ON \
  -DMESHLIFT_TESTS=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}")
run() {
  local t=$1
  mkdir -p "$work/corpus/$t" "$work/artifacts/$t"
  cp -n tests/fuzz/corpus/"$t"/* "$work/corpus/$t/" 2>/dev/null || true
  nice -n 19 "$build/fuzz_$t" "$work/corpus/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=8192 -print_final_stats=1 -artifact_prefix="$work/artifacts/$t/" >"$work/$t.log" 2>&1 || true
  echo "$t: $(grep -E 'stat::number_of_executed_units|stat::average_exec_per_sec' "$work/$t.log" | awk '{print $2}' | paste -sd' ') (executions, exec/s);" \
    "artifacts: $(ls "$work/artifacts/$t" | wc -l)"
}
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  run "${targets[i]}" &
  [ $((i + 1)) -lt ${#targets[@]} ] && run "${targets[i + 1]}" &
  wait
done
