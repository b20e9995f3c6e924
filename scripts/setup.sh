#!/usr/bin/env bash
# Installs every Debian package that meshlift's build, tests and demo need.
# Idempotent: when everything is present it only checks and returns (about a second).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libopenmesh-dev libcli11-dev catch2
  libxxhash-dev libembree-dev libspng-dev
  python3-matplotlib python3-numpy
  draco
)

# `setup.sh --fuzz` (scripts/fuzz.sh): also clang and its libFuzzer/sanitizer runtimes.
fuzz_packages() { packages+=(clang libclang-rt-dev); }
[ "${1:-}" = "--fuzz" ] && fuzz_packages

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
