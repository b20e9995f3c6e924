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
