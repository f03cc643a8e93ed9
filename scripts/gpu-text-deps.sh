#!/usr/bin/env bash
# Prepares .deps/text.tar.xz (ignored by git) for the text benchmark on the
# GPU host, which has no FreeType, HarfBuzz or FriBiDi: svg2png built here
# for sm_90 (build-pdfhost/, the libpng writer) with the shared libraries it
# names (glibc's own excepted), DejaVu Sans, and the inputs of
# scripts/make_text_bench.py (a 5,000-character page and a text-free page of
# as many segments). Run on the Debian development machine; then carry
# .deps with the checkout (scripts/gpu-text-bench.sh unpacks it).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$root/build-pdfhost
out=$build/text
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DMPVG_IMAGE_IO=png -DMPVG_BUILD_TESTS=OFF \
  -DCMAKE_CUDA_ARCHITECTURES=90 > /dev/null
cmake --build "$build" -j "$(nproc)" --target svg2png > /dev/null
rm -rf "$out"
mkdir -p "$out/bin" "$out/lib" "$out/fonts" "$out/inputs"
cp "$build/apps/svg2png" "$out/bin/"
bash "$root/scripts/carry-libs.sh" "$out/bin" "$out/lib"
cp /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf "$out/fonts/"
python3 "$root/scripts/make_text_bench.py" "$out/inputs"
segments=$("$out/bin/svg2png" --backend cpu --stats --font-dir "$out/fonts" "$out/inputs/text_page.svg" /dev/null 2>&1 |
  sed -n 's/^input segments \([0-9]*\),.*/\1/p')
python3 "$root/scripts/make_text_bench.py" "$out/inputs" "$segments"
strip "$out/bin/svg2png"
mkdir -p "$root/.deps"
tar -C "$out/.." -cf - "$(basename "$out")" | xz -9 > "$root/.deps/text.tar.xz"
du -sh "$root/.deps/text.tar.xz"
