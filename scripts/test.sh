#!/usr/bin/env bash
# Installs what is needed, builds meshlift with warnings as errors, and runs the whole test
# suite through ctest (the corpus tests read the real meshes of Debian's libcgal-demo).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
./scripts/setup.sh
export MESHLIFT_CORPUS="$(./scripts/corpus.sh)"
build="${MESHLIFT_BUILD_DIR:-build}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMESHLIFT_WERROR=ON -DMESHLIFT_BENCH=ON >/dev/null
cmake --build "$build" -j"$(nproc)"
ctest --test-dir "$build" --output-on-failure -j"$(nproc)"
# The same suite built with AddressSanitizer + UndefinedBehaviorSanitizer in its own directory
# (the install test is skipped there). -O1 -g1: a faster build with line numbers in reports;
# not -Werror, as GCC's -fsanitize=address raises false -Wmaybe-uninitialized in OpenMesh's
# headers (the build above already enforces warnings).
asan="${MESHLIFT_ASAN_BUILD_DIR:-build-asan}"
cmake -S . -B "$asan" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1" -DMESHLIFT_SANITIZE=ON >/dev/null
cmake --build "$asan" -j"$(nproc)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$asan" --output-on-failure -j"$(nproc)"
