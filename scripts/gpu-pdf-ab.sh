#!/usr/bin/env bash
# A/B of the whole pipeline on the GPU host: pdf2png and svg2png --batch of a
# baseline build against the working tree's, with mutool draw over every core
# in the same call (issue 49's yardstick), from .deps/ab.tar.xz made by
# scripts/gpu-ab-deps.sh BASE_BUILD NEW_BUILD. Prints, for each document at
# 150 dpi, pages/s of base, new and each variant (NEW_VARIANTS, ';'-separated
# option sets, default "--frame-scenes 8") and mutool's, interleaved rounds;
# whether base and new wrote the same files; the --stats summary of each;
# then the same for the 205-file SVG batch (scripts/gpu-e2e-bench.sh's);
# then test_gpu if the bundle has it.
#
#   scripts/gpu-pdf-ab.sh [rounds]     (default 2)
#   AB_DOCS="asymptote pgfmanual R-intro beameruserguide", AB_TESTS=0 skips test_gpu
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rounds=${1:-2}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tar -C "$scratch" -xJf "$root/.deps/ab.tar.xz"
d=$scratch/ab
export LD_LIBRARY_PATH=$d/lib:${LD_LIBRARY_PATH:-}
mutool=$d/bin/mutool
out=$scratch/out
mkdir -p "$out"
now() { date +%s.%N; }
cores=$(nproc)
echo "host: $(nvidia-smi --query-gpu=name --format=csv,noheader), $cores cores"
IFS=';' read -r -a variants <<< "${NEW_VARIANTS:---frame-scenes 8}"
rate() { awk "BEGIN{printf \"%.1f\", $1 / ($3 - $2)}"; }
# mpvg TOOL PROGRAM ARGS...: base's or new's PROGRAM, or new's with the
# variant TOOL's options first.
mpvg() {
  local tool=$1 prog=$2
  shift 2
  case $tool in
    base | new) "$d/$tool/$prog" "$@" ;;
    *) eval "\"$d/new/$prog\" $tool \"\$@\"" ;;
  esac
}
# same_files A B: how many of A's PNGs B has byte for byte.
same_files() {
  local same=0 differ=0 x
  for x in "$1"/*.png; do cmp -s "$x" "$2/$(basename "$x")" && same=$((same + 1)) || differ=$((differ + 1)); done
  echo "$same identical, $differ differ"
}
# rounds LABEL COUNT RUN: interleaved rounds of RUN TOOL (into $out) for
# base, new, the variants and mutool, the rate of each.
rounds() {
  local label=$1 count=$2 run=$3 round tool t0 t1 line
  for round in $(seq "$rounds"); do
    line="round $round:"
    for tool in base new "${variants[@]}" mutool; do
      rm -rf "$out"/*
      t0=$(now)
      "$run" "$tool"
      t1=$(now)
      line="$line $tool $(rate "$count" "$t0" "$t1") ($(ls "$out" | wc -l) files);"
    done
    echo "$line"
  done
}

pdf_run() {  # TOOL: the document $f into $out
  if [ "$1" = mutool ]; then
    local k a b
    for ((k = 0; k < cores; k++)); do
      a=$((k * n / cores + 1)); b=$(((k + 1) * n / cores))
      [ "$a" -le "$b" ] && "$mutool" draw -q -r 150 -o "$out/m$k-%d.png" "$f" "$a-$b" 2>/dev/null &
    done
    wait
  else
    mpvg "$1" pdf2png -q -r 150 "$f" "$out/p"
  fi
}
for doc in ${AB_DOCS:-asymptote pgfmanual R-intro beameruserguide}; do
  f=$d/corpus/$doc.pdf
  n=$("$mutool" info -M "$f" 2>/dev/null | sed -n 's/^Pages: *//p')
  echo "== $doc, $n pages, 150 dpi"
  rounds "$doc" "$n" pdf_run
  # the same files?
  rm -rf "$out"/* && mkdir -p "$out/b"
  mpvg base pdf2png -q -r 150 "$f" "$out/b/p"
  for tool in new "${variants[@]}"; do
    rm -rf "$out/v" && mkdir -p "$out/v"
    mpvg "$tool" pdf2png -q -r 150 "$f" "$out/v/p"
    echo "base and $tool files: $(same_files "$out/b" "$out/v")"
  done
  for tool in base new "${variants[@]}"; do
    rm -rf "$out/s" && mkdir -p "$out/s"
    mpvg "$tool" pdf2png -q --stats -r 150 "$f" "$out/s/p" 2>&1 | grep -E "pages/s|per page" | sed "s/^/$tool: /"
  done
done

# The SVG batch (scripts/svg-batch-list.sh).
list=$scratch/list.txt
source "$root/scripts/svg-batch-list.sh"
svg_batch_list "$d/svg" "$scratch/batch" "$out" "$root" > "$list"
n=$(wc -l < "$list")
echo "== svg2png --batch, $n files at 1024 px"
svg_run() {  # TOOL: the batch into $out
  if [ "$1" = mutool ]; then
    tr '\t' ' ' < "$list" | xargs -P "$cores" -L 1 sh -c '"$0" draw -q -w 1024 -o "$2" "$1" 2>/dev/null' "$mutool"
  else
    mpvg "$1" svg2png -q -w 1024 --batch "$list"
  fi
}
rounds batch "$n" svg_run
for tool in base new "${variants[@]}"; do
  rm -rf "$out"/*
  mpvg "$tool" svg2png -q --stats -w 1024 --batch "$list" 2>&1 | grep -E "files/s|per file" | sed "s/^/$tool: /"
done

if [ "${AB_TESTS:-1}" != 0 ] && [ -x "$d/new/test_gpu" ]; then
  echo "== test_gpu (new)"
  (cd "$root" && MPVG_SOURCE_DIR=$root "$d/new/test_gpu" 2>&1 | tail -6)
fi
