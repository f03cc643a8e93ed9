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

for doc in ${AB_DOCS:-asymptote pgfmanual R-intro beameruserguide}; do
  f=$d/corpus/$doc.pdf
  n=$("$mutool" info -M "$f" 2>/dev/null | sed -n 's/^Pages: *//p')
  echo "== $doc, $n pages, 150 dpi"
  for round in $(seq "$rounds"); do
    line="round $round:"
    for tool in base new "${variants[@]}" mutool; do
      rm -rf "$out"/*
      t0=$(now)
      case $tool in
        base) "$d/base/pdf2png" -q -r 150 "$f" "$out/p" ;;
        new) "$d/new/pdf2png" -q -r 150 "$f" "$out/p" ;;
        mutool)
          for ((k = 0; k < cores; k++)); do
            a=$((k * n / cores + 1)); b=$(((k + 1) * n / cores))
            [ "$a" -le "$b" ] && "$mutool" draw -q -r 150 -o "$out/m$k-%d.png" "$f" "$a-$b" 2>/dev/null &
          done
          wait ;;
        *) eval "\"$d/new/pdf2png\" -q $tool -r 150 \"$f\" \"$out/p\"" ;;
      esac
      t1=$(now)
      line="$line $tool $(rate "$n" "$t0" "$t1") ($(ls "$out" | wc -l) files);"
    done
    echo "$line"
  done
  # the same files?
  rm -rf "$out"/* && mkdir -p "$out/b" "$out/n"
  "$d/base/pdf2png" -q -r 150 "$f" "$out/b/p"
  "$d/new/pdf2png" -q -r 150 "$f" "$out/n/p"
  same=0 differ=0
  for x in "$out"/b/*.png; do cmp -s "$x" "$out/n/$(basename "$x")" && same=$((same + 1)) || differ=$((differ + 1)); done
  echo "base and new files: $same identical, $differ differ"
  for v in "${variants[@]}"; do
    rm -rf "$out/v" && mkdir -p "$out/v"
    eval "\"$d/new/pdf2png\" -q $v -r 150 \"$f\" \"$out/v/p\""
    same=0 differ=0
    for x in "$out"/b/*.png; do cmp -s "$x" "$out/v/$(basename "$x")" && same=$((same + 1)) || differ=$((differ + 1)); done
    echo "base and new $v files: $same identical, $differ differ"
  done
  for tool in base new "${variants[@]}"; do
    rm -rf "$out/s" && mkdir -p "$out/s"
    case $tool in
      base|new) "$d/$tool/pdf2png" -q --stats -r 150 "$f" "$out/s/p" 2>&1 | grep -E "pages/s|per page" | sed "s/^/$tool: /" ;;
      *) eval "\"$d/new/pdf2png\" -q --stats $tool -r 150 \"$f\" \"$out/s/p\"" 2>&1 | grep -E "pages/s|per page" | sed "s/^/$tool: /" ;;
    esac
  done
done

# The SVG batch: the bench inputs 45 times each and the test SVGs once.
mkdir -p "$scratch/batch"
list=$scratch/list.txt
: > "$list"
for i in $(seq -w 45); do
  for f in tiger boston hawaii reschart; do
    ln -s "$d/svg/$f.svg" "$scratch/batch/${f}_$i.svg"
    printf '%s\t%s\n' "$scratch/batch/${f}_$i.svg" "$out/${f}_$i.png" >> "$list"
  done
done
for f in "$root"/testdata/golden/*.svg; do printf '%s\t%s\n' "$f" "$out/golden_$(basename "$f" .svg).png" >> "$list"; done
n=$(wc -l < "$list")
echo "== svg2png --batch, $n files at 1024 px"
for round in $(seq "$rounds"); do
  line="round $round:"
  for tool in base new "${variants[@]}" mutool; do
    rm -rf "$out"/*
    t0=$(now)
    case $tool in
      base|new) "$d/$tool/svg2png" -q -w 1024 --batch "$list" ;;
      mutool) tr '\t' ' ' < "$list" | xargs -P "$cores" -L 1 sh -c '"$0" draw -q -w 1024 -o "$2" "$1" 2>/dev/null' "$mutool" ;;
      *) eval "\"$d/new/svg2png\" -q $tool -w 1024 --batch \"$list\"" ;;
    esac
    t1=$(now)
    line="$line $tool $(rate "$n" "$t0" "$t1") ($(ls "$out" | wc -l) files);"
  done
  echo "$line"
done
for tool in base new "${variants[@]}"; do
  rm -rf "$out"/*
  case $tool in
    base|new) "$d/$tool/svg2png" -q --stats -w 1024 --batch "$list" 2>&1 | grep -E "files/s|per file" | sed "s/^/$tool: /" ;;
    *) eval "\"$d/new/svg2png\" -q --stats $tool -w 1024 --batch \"$list\"" 2>&1 | grep -E "files/s|per file" | sed "s/^/$tool: /" ;;
  esac
done

if [ "${AB_TESTS:-1}" != 0 ] && [ -x "$d/new/test_gpu" ]; then
  echo "== test_gpu (new)"
  (cd "$root" && MPVG_SOURCE_DIR=$root "$d/new/test_gpu" 2>&1 | tail -6)
fi
