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
# The suite built with AddressSanitizer + UndefinedBehaviorSanitizer in its own directory (the
# install test is skipped there). By default the part that reads untrusted bytes: the bitstream
# and codec tests and the replays of the decoder fuzz corpora (a full sanitizer build of
# remesh/tools with OpenMesh and Embree takes over half an hour on 2 shared cores);
# MESHLIFT_ASAN_FULL=1 builds and runs the whole suite. -O1 -g1: faster to build, line numbers
# in reports; not -Werror, as GCC's -fsanitize=address raises false -Wmaybe-uninitialized in
# OpenMesh's headers (the build above enforces warnings).
asan="${MESHLIFT_ASAN_BUILD_DIR:-build-asan}"
cmake -S . -B "$asan" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1" -DMESHLIFT_SANITIZE=ON >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [ "${MESHLIFT_ASAN_FULL:-0}" = 1 ]; then
  cmake --build "$asan" -j"$(nproc)"
  ctest --test-dir "$asan" --output-on-failure -j"$(nproc)"
else
  cmake --build "$asan" -j"$(nproc)" --target test_bitstream test_codec replay_decode replay_stream replay_base_mesh
  ctest --test-dir "$asan" --output-on-failure -j"$(nproc)" -R '^(bitstream|codec):|^fuzz: (decode|stream|base_mesh) '
fi
