#!/usr/bin/env bash
# Prepares .deps/pdf.tar.xz (ignored by git) for pdf2png benchmarks on the
# GPU host, which has no MuPDF: pdf2png built here for sm_90 with the libpng
# writer (build-pdfhost/, MuPDF linked statically), Debian's mutool for the
# comparison, the shared libraries both name (glibc's own excepted), and the
# corpus documents the benchmarks read, stripped and packed with xz -9 (its
# 64 MiB window stores MuPDF's built-in fonts, in both binaries, once:
# 42 MB instead of 132 MB, within what a device call carries). Run on the
# Debian development machine; then carry .deps with the checkout
# (scripts/gpu-pdf-bench.sh unpacks it).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
corpus=${1:-$root/../shared/pdf-corpus}
build=$root/build-pdfhost
out=$build/pdf
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DMPVG_IMAGE_IO=png -DMPVG_BUILD_TESTS=OFF \
  -DCMAKE_CUDA_ARCHITECTURES=90 > /dev/null
cmake --build "$build" -j "$(nproc)" --target pdf2png > /dev/null
rm -rf "$out"
mkdir -p "$out/bin" "$out/lib" "$out/corpus"
cp "$build/apps/pdf2png" "$(command -v mutool)" "$out/bin/"
bash "$root/scripts/carry-libs.sh" "$out/bin" "$out/lib"
cp "$corpus"/pgfmanual.pdf "$corpus"/asymptote.pdf "$corpus"/utfsym.pdf "$corpus"/beameruserguide.pdf \
  "$corpus"/R-intro.pdf "$out/corpus/"
strip "$out"/bin/*
tar -C "$out/.." -cf - "$(basename "$out")" | xz -9 > "$root/.deps/pdf.tar.xz"
du -sh "$root/.deps/pdf.tar.xz"
