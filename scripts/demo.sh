#!/usr/bin/env bash
# meshlift's main demo on real meshes (Debian's libcgal-demo corpus): installs what it needs,
# builds, then remeshes armadillo, camel, fandisk and elephant, encodes them, streams and decodes
# them, sweeps rate against distortion next to Draco, renders pictures, codes a function on the
# sphere and a coloured camel's vertex colours, and writes everything under out/demo/ (REPORT.md
# first). From a fresh clone: 8 min 7 s of wall-clock time (4 min 43 s of CPU;
# 5 min of it building) on 2 cores shared with other work.
#
# MESHLIFT_BUILD_DIR (default build) names the build directory (relative to the repository, or absolute).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${MESHLIFT_BUILD_DIR:-build}"
out="$root/out/demo"
case "$build" in /*) ml="$build/meshlift" ;; *) ml="$root/$build/meshlift" ;; esac
py=/usr/bin/python3
meshes=(armadillo camel fandisk elephant)
levels=3

say() { echo "== $*"; }
# Runs meshlift, echoing the command line; its stderr goes to the log file named first.
run() { local log="$1"; shift; echo "   meshlift $*" | sed "s|$root/||g"; "$ml" "$@" 2>>"$log"; }

prepare() {
  ./scripts/setup.sh
  corpus="$(./scripts/corpus.sh)"
  say "building meshlift in $build/"
  local start=$SECONDS
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMESHLIFT_BENCH=ON >/dev/null
  cmake --build "$build" -j"$(nproc)" --target meshlift_cli bench_sphere_function >/dev/null
  rm -rf "$out"
  mkdir -p "$out"/{info,remesh,codec,decode,pictures,rd}
  echo "$(( SECONDS - start ))" >"$out/build_seconds.txt"
}

# The development corpus passes `meshlift info` (JSON reports), and a bad input fails cleanly.
validate() {
  local corpus_meshes=(armadillo camel fandisk bear_bis cow homer elephant knot1 lion-head)
  say "validating ${#corpus_meshes[@]} corpus meshes (meshlift info --json -> out/demo/info/)"
  for m in "${corpus_meshes[@]}"; do
    "$ml" info "$corpus/$m.off" --json >"$out/info/$m.json"
  done
  say "a bad input gets a one-line message and a non-zero exit:"
  set +e
  # pig.stl: 421 vertices where separate fans of faces meet (non-manifold). Nothing is written.
  rm -f "$out/remesh/should_not_exist.ply"
  "$ml" remesh "$corpus/pig.stl" -o "$out/remesh/should_not_exist.ply" 2>&1 | sed "s|$root/||g; s/^/   /" | tee "$out/bad_input.txt"
  local code=${PIPESTATUS[0]}
  set -e
  echo "   (exit code $code)" | tee -a "$out/bad_input.txt"
  if [ "$code" -eq 0 ] || [ -e "$out/remesh/should_not_exist.ply" ]; then
    echo "demo: the bad input was not refused, or left a file" >&2
    exit 1
  fi
}

# Step 1: every mesh becomes semi-regular (a decimated base refined $levels times by 1:4 splits).
remesh() {
  say "remeshing (meshlift remesh --levels $levels -> out/demo/remesh/)"
  for m in "${meshes[@]}"; do
    run "$out/remesh/$m.log" remesh "$corpus/$m.off" -o "$out/remesh/$m.ply" --levels "$levels" --binary
    sed "s|$root/||g; s/^/      /" "$out/remesh/$m.log"
  done
  # The same base size with --snap: the remesh's vertices on the input's own corners and creases,
  # closer to the input, for a remesh used as a mesh (the codec's files below are made without it).
  say "remeshing with --snap, same base sizes (a remesh used as a mesh -> out/demo/remesh/*_snap.ply)"
  for m in "${meshes[@]}"; do
    local base
    base=$(sed -n 's/.* remesh: base \([0-9]*\), .*/\1/p' "$out/remesh/$m.log")
    run "$out/remesh/${m}_snap.log" remesh "$corpus/$m.off" -o "$out/remesh/${m}_snap.ply" --levels "$levels" \
      --base-vertices "$base" --snap --binary
    grep -E "snap:|remesh error" "$out/remesh/${m}_snap.log" | sed "s|$root/||g; s/^/      /"
  done
}

file_size() { stat -c %s "$1"; }
input_vertices() { $py -c 'import json,sys; print(json.load(open(sys.argv[1]))["vertices"])' "$out/info/$1.json"; }

# Step 2: encode (butterfly), stream armadillo, decode a 1 bpv prefix and the whole of each file,
# and check that a truncated file decodes to what its prefix decodes to.
codec() {
  say "encoding the remeshed meshes (butterfly wavelets -> out/demo/codec/*.mlz)"
  for m in "${meshes[@]}"; do
    run "$out/codec/$m.log" encode "$out/remesh/$m.ply" -o "$out/codec/$m.mlz" --scheme butterfly
  done

  # The whole file streamed in ~8 steps (PSNR per step), and the first 4 bits per original vertex
  # (a truncated copy) streamed in 8 steps and rendered: most of the sharpening happens there.
  local size every bytes
  size=$(file_size "$out/codec/armadillo.mlz")
  every=$(( (size + 7) / 8 ))
  say "streaming armadillo.mlz ($size bytes) $every bytes at a time, as a viewer receives it"
  run "$out/codec/armadillo_stream.log" stream "$out/codec/armadillo.mlz" --every "$every" \
    --reference "$out/remesh/armadillo.ply" --csv "$out/codec/armadillo_stream.csv"
  bytes=$(( 4 * $(input_vertices armadillo) / 8 ))
  every=$(( (bytes + 7) / 8 ))
  say "streaming its first $bytes bytes (4 bits per original vertex) $every bytes at a time -> out/demo/stream_strip.png"
  run "$out/codec/armadillo_stream.log" truncate "$out/codec/armadillo.mlz" --bytes "$bytes" -o "$out/codec/armadillo_4bpv.mlz"
  run "$out/codec/armadillo_stream.log" stream "$out/codec/armadillo_4bpv.mlz" --every "$every" \
    -o "$out/codec/armadillo_stream" --reference "$out/remesh/armadillo.ply" --csv "$out/codec/armadillo_stream_4bpv.csv"
  $py tools/render.py strip "$out"/codec/armadillo_stream/prefix_*.ply --csv "$out/codec/armadillo_stream_4bpv.csv" \
    --view 180,10 --size 280,360 \
    --title "armadillo: the first $bytes bytes of one butterfly stream (bpv here: bits per remeshed vertex)" \
    -o "$out/stream_strip.png"

  say "decoding a 1 bpv prefix (bits per original vertex) and the whole file (--stats)"
  for m in "${meshes[@]}"; do
    bytes=$(( ($(input_vertices "$m") + 7) / 8 ))
    echo "$bytes" >"$out/decode/$m.1bpv_bytes"
    run "$out/decode/$m.log" decode "$out/codec/$m.mlz" --bytes "$bytes" -o "$out/decode/${m}_1bpv.ply" --binary --stats
    run "$out/decode/$m.log" decode "$out/codec/$m.mlz" -o "$out/decode/${m}_full.ply" --binary --stats
  done
  # A quality target against the original mesh, as a user asks for it: encode remeshes the input
  # itself and cuts the stream where its decode is 70 dB from it (the metric of docs/METRIC.md).
  say "encoding camel.off for 70 dB against itself (encode --psnr 70 -> out/demo/codec/camel_70dB.mlz)"
  run "$out/codec/camel_70dB.log" encode "$corpus/camel.off" -o "$out/codec/camel_70dB.mlz" --psnr 70
  grep -- "--psnr 70" "$out/codec/camel_70dB.log" | sed 's/^/   /'
  run "$out/decode/camel_70dB.log" decode "$out/codec/camel_70dB.mlz" -o "$out/decode/camel_70dB.ply" --binary

  bytes=$(cat "$out/decode/armadillo.1bpv_bytes")
  say "truncating armadillo.mlz to its 1 bpv prefix ($bytes bytes): a valid file that decodes the same"
  run "$out/decode/truncate.log" truncate "$out/codec/armadillo.mlz" --bytes "$bytes" -o "$out/codec/armadillo_1bpv.mlz"
  run "$out/decode/truncate.log" decode "$out/codec/armadillo_1bpv.mlz" -o "$out/decode/armadillo_truncated.ply" --binary
  if cmp -s "$out/decode/armadillo_truncated.ply" "$out/decode/armadillo_1bpv.ply"; then
    echo "identical" >"$out/decode/truncate_check.txt"
    echo "   the truncated file's decode is byte-identical to the prefix's"
  else
    echo "DIFFERENT" >"$out/decode/truncate_check.txt"
    echo "   WARNING: the truncated file's decode differs from the prefix's" >&2
  fi
}

# Step 3: the rate-distortion sweep against Draco, measured against the original meshes.
sweep() {
  local inputs=()
  for m in "${meshes[@]}"; do inputs+=("$corpus/$m.off"); done
  say "rate-distortion sweep (meshlift rd: 3 schemes x 7 rates, Draco at qp 6-12; a few minutes)"
  local start=$SECONDS
  "$ml" rd "${inputs[@]}" --levels "$levels" --schemes linear,butterfly,loop --bpv 0.25,0.5,1,2,4,8,16 \
    --draco-qp 6,7,8,9,10,11,12 --samples 200000 -o "$out/rd" 2>"$out/rd/rd.log"
  echo "$(( SECONDS - start ))" >"$out/rd/seconds.txt"
  echo "   $(tail -1 "$out/rd/rd.log" | sed "s|$root/||g") ($(cat "$out/rd/seconds.txt") s)"
  $py tools/plot_rd.py "$out/rd" >"$out/rd/plot_rd.log" 2>&1
}

# Step 4: the original, the remeshed and the decoded armadillo side by side.
pictures() {
  say "rendering the original, remeshed and decoded armadillo (out/demo/armadillo.png)"
  local p="$out/pictures"
  cp "$corpus/armadillo.off" "$p/1_original.off"
  cp "$out/remesh/armadillo.ply" "$p/2_remeshed.ply"
  cp "$out/decode/armadillo_1bpv.ply" "$p/3_decoded_1bpv.ply"
  cp "$out/decode/armadillo_full.ply" "$p/4_decoded_whole_file.ply"
  $py tools/render.py strip "$p/1_original.off" "$p/2_remeshed.ply" "$p/3_decoded_1bpv.ply" \
    "$p/4_decoded_whole_file.ply" --view 180,10 --size 360,460 \
    --title "armadillo: original, remeshed ($levels levels), decoded from 1 bpv, decoded whole" -o "$out/armadillo.png"
  rm -f "$p"/*.off "$p"/*.ply
  rmdir "$p"
}

# Spherical geometry images, when this build has them.
geometry_image() {
  if "$ml" gim --help >/dev/null 2>&1; then
    say "spherical geometry image of the camel (meshlift gim, n = 129)"
    if run "$out/gim.log" gim "$corpus/camel.off" -o "$out/camel_gim.png" --size 129; then
      sed "s|$root/||g; s/^/      /" "$out/gim.log"
    else
      echo "   meshlift gim failed (see out/demo/gim.log); the rest of the demo does not depend on it"
    fi
  fi
}

# A function on the sphere as an extra channel of the stream: the Earth (Debian's xplanet-images,
# fetched without installing; a procedural pattern if that fails) on the octahedral sphere grid.
sphere_function() {
  local cache="$root/.cache/earth" image=()
  if [ ! -f "$cache/earth.ppm" ]; then
    local work
    work="$(mktemp -d)"
    if (cd "$work" && apt-get download xplanet-images >/dev/null 2>&1) && dpkg -x "$work"/xplanet-images_*.deb "$work/pkg"; then
      mkdir -p "$cache"
      $py -c 'import sys, numpy as np, matplotlib.image as im
a = im.imread(sys.argv[1])[:, :, :3]
open(sys.argv[2], "wb").write(b"P6\n%d %d\n255\n" % (a.shape[1], a.shape[0]) + np.ascontiguousarray(a, dtype=np.uint8).tobytes())' \
        "$work/pkg/usr/share/xplanet/images/earth.jpg" "$cache/earth.ppm" || rm -f "$cache/earth.ppm"
    fi
    rm -rf "$work"
  fi
  [ -f "$cache/earth.ppm" ] && image=(--image "$cache/earth.ppm")
  mkdir -p "$out/sphere_function"
  say "a function on the sphere (${image[1]:-procedural}) as a colour channel: octahedral grid 513 x 513, 3 schemes"
  case "$build" in /*) local bench="$build/bench_sphere_function" ;; *) local bench="$root/$build/bench_sphere_function" ;; esac
  "$bench" "${image[@]}" --levels 8 --bits 10 -o "$out/sphere_function" >"$out/sphere_function/table.txt"
  sed "s|$root/||g; s/^/   /" "$out/sphere_function/table.txt" | head -3
  $py tools/plot_sphere_function.py "$out/sphere_function" >/dev/null
  rm -f "$out"/sphere_function/*.p[gp]m
}

# Vertex colours: camel coloured by a smooth field (tools/colour_mesh.py), encoded with and
# without its colours, decoded from 1 and 2 bpv prefixes and whole: PLY files with their colours,
# rendered side by side with the coloured input.
colours() {
  local c="$out/colour"
  mkdir -p "$c"
  say "vertex colours: camel with a smooth colour field, encoded with and without it (-> out/demo/colour/)"
  $py tools/colour_mesh.py "$corpus/camel.off" "$c/camel_coloured.ply" smooth
  $py tools/colour_mesh.py "$corpus/camel.off" "$c/camel_plain.ply" none
  run "$c/colour.log" encode "$c/camel_coloured.ply" -o "$c/camel_coloured.mlz"
  run "$c/colour.log" encode "$c/camel_plain.ply" -o "$c/camel_plain.mlz"
  local vertices
  vertices=$(input_vertices camel)
  for bpv in 1 2; do
    run "$c/colour.log" decode "$c/camel_coloured.mlz" --bytes $(( bpv * vertices / 8 )) -o "$c/camel_decoded_${bpv}bpv.ply" --binary
  done
  run "$c/colour.log" decode "$c/camel_coloured.mlz" -o "$c/camel_decoded_whole.ply" --binary
  echo "$(file_size "$c/camel_plain.mlz") $(file_size "$c/camel_coloured.mlz") $vertices" >"$c/sizes.txt"
  echo "   $(file_size "$c/camel_plain.mlz") bytes without the colours, $(file_size "$c/camel_coloured.mlz") with them"
  $py tools/render.py strip "$c/camel_coloured.ply" "$c/camel_decoded_1bpv.ply" "$c/camel_decoded_2bpv.ply" \
    "$c/camel_decoded_whole.ply" --view 90,10 --size 300,300 \
    --title "camel's vertex colours: the input, decoded from 1 and 2 bits per input vertex, decoded whole" \
    -o "$out/colour_strip.png"
}

report() {
  $py tools/demo_report.py "$out" "$levels" "${meshes[@]}"
}

start_time=$SECONDS
prepare
validate
remesh
codec
sweep
pictures
geometry_image
sphere_function
colours
echo "$(( SECONDS - start_time ))" >"$out/demo_seconds.txt"
report
