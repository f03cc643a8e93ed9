#!/usr/bin/env bash
# Prepares .deps/ab.tar.xz (ignored by git) for scripts/gpu-pdf-ab.sh: the
# pdf2png and svg2png of two builds made here for sm_90 (BASE_BUILD, e.g. a
# worktree of the baseline commit configured with -DMPVG_IMAGE_IO=png
# -DCMAKE_CUDA_ARCHITECTURES=90, and NEW_BUILD, whose test_gpu comes too
# where it was built), Debian's mutool, the shared libraries they name
# (glibc's and the C++ runtime's excepted), the corpus documents and the
# bench SVGs, stripped and packed with xz -9 (a window of 256 MiB stores the
# binaries' common parts, MuPDF's fonts above all, about once).
#
#   scripts/gpu-ab-deps.sh BASE_BUILD NEW_BUILD   (AB_DOCS: the documents, default
#   "pgfmanual asymptote beameruserguide R-intro"; a device call carries 64 MiB)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
base=$1 new=$2
corpus=$root/../shared/pdf-corpus
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ab=$tmp/ab
mkdir -p "$ab/base" "$ab/new" "$ab/bin" "$ab/lib" "$ab/corpus" "$ab/svg"
cp "$base/apps/pdf2png" "$base/apps/svg2png" "$ab/base/"
cp "$new/apps/pdf2png" "$new/apps/svg2png" "$ab/new/"
[ -x "$new/tests/test_gpu" ] && cp "$new/tests/test_gpu" "$ab/new/"
cp "$(command -v mutool)" "$ab/bin/"
for dir in base new bin; do bash "$root/scripts/carry-libs.sh" "$ab/$dir" "$ab/lib"; done
for doc in ${AB_DOCS:-pgfmanual asymptote beameruserguide R-intro}; do cp "$corpus/$doc.pdf" "$ab/corpus/"; done
cp "$root"/../shared/bench/svg/{tiger,boston,hawaii,reschart}.svg "$ab/svg/"
strip "$ab"/base/* "$ab"/new/* "$ab"/bin/*
mkdir -p "$root/.deps"
# base and new side by side in the archive: xz finds the second in the first
# (in this order: the two pdf2pngs and mutool, which share MuPDF's
# fonts, within the window of each other)
(cd "$tmp" && { ls -d ab/base/pdf2png ab/new/pdf2png ab/bin/mutool ab/base/svg2png ab/new/svg2png ab/new/test_gpu 2>/dev/null || true; find ab -type f | sort; } |
  awk '!seen[$0]++' | tar -cf - --no-recursion -T -) | xz -T1 --lzma2=preset=9e,dict=256MiB > "$root/.deps/ab.tar.xz"
du -sh "$root/.deps/ab.tar.xz"
