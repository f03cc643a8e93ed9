#!/usr/bin/env bash
# pdf2png against mutool draw on the GPU host, at 150 dpi (issue 11's
# yardstick), from .deps/pdf.tar.xz (scripts/gpu-pdf-deps.sh). Prints:
#   - per-page stage times of pgfmanual p. 1 and utfsym p. 6 (pdf2png
#     --stats, the page rendered 5 times in one process by one worker and
#     one render thread, the last shown: a warm, uncontended pipeline), and mutool's own time for
#     the page (-s t);
#   - whole-document throughput, pages per second, for pgfmanual and
#     asymptote: pdf2png (one process, CUDA; three rounds), mutool draw in
#     one process,
#     and mutool draw in $(nproc) processes over equal page ranges (three
#     rounds: it varies by 20 % from run to run);
#   - variants: asymptote through pdf2png with other render-thread counts,
#     in two processes, and at --aa 1x32, each with its per-stage means and
#     idle shares (--stats).
# Every run writes its PNGs to a scratch folder on local disk.
#
#   scripts/gpu-pdf-bench.sh [pages] [throughput] [variants]   (default: all)
#   MPVG_BENCH_DOCS="asymptote pgfmanual" (throughput's documents),
#   MPVG_BENCH_MUTOOL1=0 skips single-process mutool runs.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tar -C "$scratch" -xJf "$root/.deps/pdf.tar.xz"
d=$scratch/pdf
export LD_LIBRARY_PATH=$d/lib:${LD_LIBRARY_PATH:-}
pdf2png=$d/bin/pdf2png
mutool=$d/bin/mutool
out=$scratch/out
mkdir -p "$out"
steps=${*:-pages throughput variants}
has() { [[ " $steps " == *" $1 "* ]]; }
now() { date +%s.%N; }
cores=$(nproc)
echo "host: $(nvidia-smi --query-gpu=name --format=csv,noheader), $cores cores"

if has pages; then
  for spec in pgfmanual:1 utfsym:6; do
    doc=${spec%%:*}
    page=${spec##*:}
    echo "== $doc p. $page"
    "$pdf2png" --backend cuda --stats --threads 1 --render-threads 1 --repeat 5 -r 150 -f "$page" -l "$page" "$d/corpus/$doc.pdf" "$out/p" 2>&1 |
      grep -E "^page|^pdf2png" | tail -2
    for i in 1 2 3; do "$mutool" draw -s t -r 150 -o "$out/m.png" "$d/corpus/$doc.pdf" "$page" 2>&1 | grep -E "^page"; done
  done
fi

if has throughput; then
  for doc in ${MPVG_BENCH_DOCS:-asymptote pgfmanual}; do
    f=$d/corpus/$doc.pdf
    n=$("$mutool" info -M "$f" 2>/dev/null | sed -n 's/^Pages: *//p')
    echo "== $doc, $n pages"
    for round in 1 2 3; do
      rm -rf "$out"/*
      t0=$(now)
      "$pdf2png" --backend cuda --stats -q -r 150 "$f" "$out/p" 2>&1 | grep -E "pages/s|per page"
      t1=$(now)
      echo "pdf2png: $(awk "BEGIN{printf \"%.2f\", $t1 - $t0}") s wall, $(awk "BEGIN{printf \"%.1f\", $n / ($t1 - $t0)}") pages/s wall, $(ls "$out" | wc -l) files"
    done
    if [ "${MPVG_BENCH_MUTOOL1:-1}" != 0 ]; then
      rm -rf "$out"/*
      t0=$(now)
      "$mutool" draw -q -r 150 -o "$out/m%d.png" "$f" 2>/dev/null
      t1=$(now)
      echo "mutool, 1 process: $(awk "BEGIN{printf \"%.2f\", $t1 - $t0}") s, $(awk "BEGIN{printf \"%.1f\", $n / ($t1 - $t0)}") pages/s"
    fi
    for round in 1 2 3; do
      rm -rf "$out"/*
      t0=$(now)
      for ((k = 0; k < cores; k++)); do
        a=$((k * n / cores + 1))
        b=$(((k + 1) * n / cores))
        [ "$a" -le "$b" ] && "$mutool" draw -q -r 150 -o "$out/m$k-%d.png" "$f" "$a-$b" 2>/dev/null &
      done
      wait
      t1=$(now)
      echo "mutool, $cores processes: $(awk "BEGIN{printf \"%.2f\", $t1 - $t0}") s, $(awk "BEGIN{printf \"%.1f\", $n / ($t1 - $t0)}") pages/s"
    done
  done
fi

if has variants; then
  f=$d/corpus/asymptote.pdf
  echo "== variants, asymptote"
  run() {
    rm -rf "$out"/*
    echo "-- $*"
    env "$@" --backend cuda --stats -q -r 150 "$f" "$out/p" 2>&1 | grep -E "pages/s|per page"
  }
  for r in 1 2 4 6; do run "$pdf2png" --render-threads $r; done
  # pgfmanual in two processes, half the pages and threads each: more
  # than one process's rate (throughput above) means the limit is per
  # process (driver locks), not the device.
  g=$d/corpus/pgfmanual.pdf
  n=$("$mutool" info -M "$g" 2>/dev/null | sed -n 's/^Pages: *//p')
  rm -rf "$out"/*
  t0=$(now)
  "$pdf2png" --backend cuda -q --threads 6 --render-threads 2 -r 150 -l $((n / 2)) "$g" "$out/a" &
  "$pdf2png" --backend cuda -q --threads 6 --render-threads 2 -r 150 -f $((n / 2 + 1)) "$g" "$out/b" &
  wait
  t1=$(now)
  echo "-- pgfmanual in two processes: $(awk "BEGIN{printf \"%.1f\", $n / ($t1 - $t0)}") pages/s"
  run "$pdf2png" --aa 1x32
fi
