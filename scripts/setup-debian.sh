#!/usr/bin/env bash
# Installs the Debian 12 packages mpvg needs to build and test.
# clang with its sanitizer runtimes (libclang-rt-14-dev, only recommended
# by clang, so named) and Ninja build the sanitized fuzz regressions that
# scripts/test.sh runs (scripts/fuzz.sh sanitized).
# help2man writes the man pages from each program's --help and
# bash-completion's helpers back packaging/bash-completion/ (and its test).
# python3-dask and python3-distributed run the Dask batch example
# (python/examples/dask_render.py, tests/python/test_dask.py).
# Idempotent: when every package is already installed it does nothing
# (no apt-get update, no network), so warm rebuilds stay fast.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libtinyxml2-dev
  libfreetype-dev
  libopenimageio-dev
  libmupdf-dev libmujs-dev libgumbo-dev libjbig2dec0-dev libopenjp2-7-dev
  libjpeg-dev libharfbuzz-dev libfribidi-dev zlib1g-dev
  libfontconfig-dev fonts-dejavu-core fonts-lohit-deva fonts-wqy-microhei
  fonts-liberation fonts-urw-base35
  catch2
  libpng-dev libdeflate-dev liblcms2-dev
  python3-dev python3-numpy pybind11-dev python3-venv python3-pytest
  python3-dask python3-distributed
  time util-linux
  help2man bash-completion
  clang libclang-rt-14-dev ninja-build
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "mpvg setup: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
