#!/usr/bin/env bash
# Fetches the real-mesh corpus (Debian's libcgal-demo: data/meshes/*.off) into .cache/corpus
# without installing CGAL, and prints the directory. Idempotent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dest="$root/.cache/corpus"
if [ ! -f "$dest/meshes/armadillo.off" ]; then
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  (cd "$work" && apt-get download libcgal-demo >/dev/null 2>&1) || {
    [ "$(id -u)" -eq 0 ] && apt-get update -qq && (cd "$work" && apt-get download libcgal-demo >/dev/null)
  }
  dpkg -x "$work"/libcgal-demo_*.deb "$work/pkg"
  mkdir -p "$dest"
  tar -xzf "$work/pkg/usr/share/doc/libcgal-dev/data.tar.gz" -C "$work" data/meshes
  rm -rf "$dest/meshes"
  mv "$work/data/meshes" "$dest/meshes"
fi
echo "$dest/meshes"
