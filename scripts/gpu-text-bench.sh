#!/usr/bin/env bash
# On the GPU host: the text benchmark (BENCHMARKS.md, "Text"). Unpacks
# .deps/text.tar.xz (scripts/gpu-text-deps.sh) and renders the 5,000-
# character page and the text-free page of as many segments with svg2png
# --stats, CUDA and the CPU, at 4x4x32 (the default) and 1x32, ROUNDS times
# each, interleaved. Output: one --stats block per run, to stdout.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rounds=${1:-5}
work=${TMPDIR:-/tmp}/mpvg-text
rm -rf "$work" && mkdir -p "$work"
xz -dc "$root/.deps/text.tar.xz" | tar -C "$work" -xf -
t=$work/text
export LD_LIBRARY_PATH=$t/lib
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for r in $(seq "$rounds"); do
  for page in text_page shapes_page; do
    for aa in 4x4x32 1x32; do
      for backend in cuda cpu; do
        [ "$backend" = cpu ] && [ "$aa" = 4x4x32 ] && [ "$r" -gt 2 ] && continue
        echo "== round $r $page $aa $backend"
        "$t/bin/svg2png" --stats --backend "$backend" --aa "$aa" --font-dir "$t/fonts" \
          "$t/inputs/$page.svg" "$work/$page.png" 2>&1
      done
    done
  done
done
