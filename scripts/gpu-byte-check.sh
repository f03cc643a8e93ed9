#!/usr/bin/env bash
# Issue 32's promise, end to end on the GPU host: every golden document of
# testdata/ (the SVGs of golden/ and golden-text/, the PDFs of
# pdf/features/) written by svg2png / pdf2png with --backend cpu (one
# thread and every core) and --backend cuda, at every preset, must give the
# same PNG file byte for byte. Prints one line per preset and the files
# that differ; exit 1 when any does.
#
# Here:   scripts/gpu-byte-check.sh --pack   (writes .gpu/bytes.tar.xz: the
#         two converters built in build/, the shared libraries they name)
# There:  scripts/gpu-byte-check.sh          (carry .gpu/bytes.tar.xz; or MPVG_BIN=DIR
#         naming a folder holding svg2png and pdf2png)
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Across machines (the issue's "done when"): here, `scripts/gpu-byte-check.sh
# --reference DIR` writes every golden rendered by the CPU backend into
# DIR/PRESET/; there, MPVG_REFERENCE=DIR also compares the CUDA backend's
# files with those.
render() {  # converter-dir file preset backend... out
  local bin=$1 f=$2 preset=$3 out=${*: -1}
  local run=("${@:4:$#-4}")
  if [ "${f##*.}" = svg ]; then
    "$bin/svg2png" -q --aa "$preset" --font-dir "$root/testdata/fonts" --backend "${run[@]}" "$f" "$out" 2>/dev/null
  else
    "$bin/pdf2png" -q --aa "$preset" -r 100 --singlefile --backend "${run[@]}" "$f" "${out%.png}" 2>/dev/null
  fi
}
goldens() { ls "$root"/testdata/golden/*.svg "$root"/testdata/golden-text/*.svg "$root"/testdata/pdf/features/*.pdf; }
if [ "${1:-}" = "--reference" ]; then
  for preset in 1x8 1x32 4x4x32; do
    mkdir -p "$2/$preset"
    for f in $(goldens); do
      n=$(basename "$f"); render "$root/build/apps" "$f" "$preset" cpu "$2/$preset/${n%.*}.png" || echo "$n: failed"
    done
  done
  exit 0
fi
if [ "${1:-}" = "--pack" ]; then
  set -e
  stage=$(mktemp -d)
  mkdir -p "$stage/bytes/bin" "$stage/bytes/lib" "$root/.gpu"
  cp "$root/build/apps/svg2png" "$root/build/apps/pdf2png" "$stage/bytes/bin/"
  bash "$root/scripts/carry-libs.sh" "$stage/bytes/bin" "$stage/bytes/lib"
  strip "$stage/bytes/bin/"*
  tar -C "$stage" -cf - bytes | xz -T4 -9 > "$root/.gpu/bytes.tar.xz"
  rm -rf "$stage"
  du -h "$root/.gpu/bytes.tar.xz"
  exit 0
fi
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
if [ -n "${MPVG_BIN:-}" ]; then  # converters unpacked already (their libraries on LD_LIBRARY_PATH)
  bin=$MPVG_BIN
else
  tar -C "$scratch" -xJf "$root/.gpu/bytes.tar.xz"
  export LD_LIBRARY_PATH=$scratch/bytes/lib
  bin=$scratch/bytes/bin
fi
echo "host: $(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null), $(nproc) cores"
status=0
for preset in 1x8 1x32 4x4x32; do
  same=0 total=0 differ=()
  xsame=0 xdiffer=()
  for f in $(goldens); do
    name=$(basename "$f")
    outs=()
    for run in "cpu --threads 1" "cpu" "cuda"; do
      o=$scratch/$(echo "$run" | tr -d ' -').png
      # shellcheck disable=SC2086
      render "$bin" "$f" "$preset" $run "$o" || { echo "  $name ($run): failed"; status=1; }
      outs+=("$o")
    done
    total=$((total + 1))
    if cmp -s "${outs[0]}" "${outs[1]}" && cmp -s "${outs[1]}" "${outs[2]}"; then
      same=$((same + 1))
    else
      differ+=("$name")
    fi
    if [ -n "${MPVG_REFERENCE:-}" ]; then
      if cmp -s "${outs[2]}" "$MPVG_REFERENCE/$preset/${name%.*}.png"; then xsame=$((xsame + 1)); else xdiffer+=("$name"); fi
    fi
  done
  echo "preset $preset: $same of $total files the same bytes (CPU 1 thread, CPU all, CUDA)"
  for d in "${differ[@]}"; do echo "  differs: $d"; done
  [ ${#differ[@]} -eq 0 ] || status=1
  if [ -n "${MPVG_REFERENCE:-}" ]; then
    echo "preset $preset: $xsame of $total CUDA files here the same bytes as the CPU backend's on the reference machine"
    for d in "${xdiffer[@]}"; do echo "  differs from the reference: $d"; done
  fi
done
exit $status
