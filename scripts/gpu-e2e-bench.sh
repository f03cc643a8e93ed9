#!/usr/bin/env bash
# End to end on the GPU host (issue 12's yardstick): svg2png from command to
# file against `mutool draw`, the four bench inputs at 1024 px, default
# quality, interleaved runs, medians. Needs build-gpu/ (scripts/gpu-run.sh
# build) and, for mutool, .deps/pdf.tar.xz (scripts/gpu-pdf-deps.sh).
#
#   scripts/gpu-e2e-bench.sh [rounds]     (default 7)
#   MPVG_E2E_VARIANTS="..." extra svg2png option sets, ';'-separated
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rounds=${1:-7}
svg2png=$root/build-gpu/apps/svg2png
bench=$root/.deps/bench
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mutool=""
if [ -f "$root/.deps/pdf.tar.xz" ]; then
  tar -C "$scratch" -xJf "$root/.deps/pdf.tar.xz"
  mutool=$scratch/pdf/bin/mutool
  mutool_libs=$scratch/pdf/lib
fi
now() { date +%s%N; }
printf '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect width="10" height="5" fill="red"/></svg>' > "$scratch/tiny.svg"
echo "host: $(nvidia-smi --query-gpu=name --format=csv,noheader), $(nproc) cores"

# One line per tool and input: the median and the spread of `rounds` runs,
# interleaved (every tool runs once per input per round).
declare -A times
tools=("auto" "cuda" "cpu")
[ -n "$mutool" ] && tools+=("mutool")
IFS=';' read -r -a variants <<< "${MPVG_E2E_VARIANTS:-}"
for v in "${variants[@]}"; do [ -n "$v" ] && tools+=("v:$v"); done
run_tool() {  # tool input
  local tool=$1 in=$2 w=1024
  [ "$(basename "$in")" = tiny.svg ] && w=10
  case $tool in
    auto|cuda|cpu) "$svg2png" -q --backend "$tool" -w $w "$in" "$scratch/o.png" ;;
    mutool) LD_LIBRARY_PATH=$mutool_libs "$mutool" draw -q -w $w -o "$scratch/m.png" "$in" 2>/dev/null ;;
    v:*) eval "\"$svg2png\" -q ${tool#v:} -w $w \"$in\" \"$scratch/o.png\"" ;;
  esac
}
inputs=("$bench/tiger.svg" "$bench/boston.svg" "$bench/hawaii.svg" "$bench/reschart.svg" "$scratch/tiny.svg")
for r in $(seq "$rounds"); do
  for in in "${inputs[@]}"; do
    for tool in "${tools[@]}"; do
      t0=$(now); run_tool "$tool" "$in"; t1=$(now)
      times["$tool|$(basename "$in" .svg)"]+="$(( (t1 - t0) / 1000 )) "
    done
  done
done
t0=$(now); for i in $(seq 20); do /bin/true; done; t1=$(now)
echo "process start and exit of /bin/true: $(( (t1 - t0) / 20000 )) us"
echo "== wall, ms: median [min-max] of $rounds interleaved runs"
for in in "${inputs[@]}"; do
  name=$(basename "$in" .svg)
  for tool in "${tools[@]}"; do
    echo "${times["$tool|$name"]}" | tr ' ' '\n' | grep . | sort -n |
      awk -v t="$tool" -v n="$name" '{a[NR]=$1} END {printf "%-10s %-28s %8.1f [%.1f-%.1f]\n", n, t, a[int((NR+1)/2)]/1000, a[1]/1000, a[NR]/1000}'
  done
done
echo "== breakdown (--stats), one run each after the rounds above"
for in in "${inputs[@]}"; do
  for b in auto cuda; do
    echo "-- $(basename "$in") --backend $b"
    w=1024; [ "$(basename "$in")" = tiny.svg ] && w=10
    MPVG_T0=$(now) "$svg2png" --stats --backend $b -w $w "$in" "$scratch/o.png" 2>&1 | grep -vE "^(input segments|abstract|subdivide|prune|schedule) "
  done
done

# The persistent renderer: a server started by the first call (not timed),
# then interleaved rounds as above.
export MPVG_SERVER_DIR=$scratch/sock MPVG_SERVER_IDLE=120
mkdir -m 700 "$MPVG_SERVER_DIR"
"$svg2png" --server -q -w 1024 "$bench/tiger.svg" "$scratch/o.png"
declare -A stimes
for r in $(seq "$rounds"); do
  for in in "${inputs[@]}"; do
    w=1024; [ "$(basename "$in")" = tiny.svg ] && w=10
    t0=$(now); "$svg2png" --server -q -w $w "$in" "$scratch/o.png"; t1=$(now)
    stimes["$(basename "$in" .svg)"]+="$(( (t1 - t0) / 1000 )) "
    if [ -n "$mutool" ]; then
      t0=$(now); run_tool mutool "$in"; t1=$(now)
      stimes["m|$(basename "$in" .svg)"]+="$(( (t1 - t0) / 1000 )) "
    fi
  done
done
echo "== persistent renderer (svg2png --server), wall ms: median [min-max], with mutool interleaved"
for in in "${inputs[@]}"; do
  name=$(basename "$in" .svg)
  for k in "$name" "m|$name"; do
    [ -z "${stimes[$k]:-}" ] && continue
    echo "${stimes[$k]}" | tr ' ' '\n' | grep . | sort -n |
      awk -v t="$k" '{a[NR]=$1} END {printf "%-28s %8.1f [%.1f-%.1f]\n", t, a[int((NR+1)/2)]/1000, a[1]/1000, a[NR]/1000}'
  done
done
"$svg2png" --server --stats -w 1024 "$bench/tiger.svg" "$scratch/o.png" 2>&1 | grep -E "persistent|^wall|^render|^PNG|^parse|^auto"
pkill -f -- "--serve-internal"

# Batch: the bench inputs 45 times each and the test SVGs once, at 1024 px.
mkdir -p "$scratch/bout" "$scratch/mout"
list=$scratch/list.txt
source "$root/scripts/svg-batch-list.sh"
svg_batch_list "$bench" "$scratch/batch" "$scratch/bout" "$root" > "$list"
n=$(wc -l < "$list")
echo "== batch of $n files at 1024 px"
for round in 1 2 3; do
  rm -f "$scratch"/bout/*
  t0=$(now)
  "$svg2png" -q -w 1024 --stats --batch "$list" 2>&1 | grep -E "files/s|per file"
  t1=$(now)
  echo "svg2png batch: $(awk "BEGIN{printf \"%.1f\", $n / (($t1 - $t0) / 1e9)}") files/s wall, $(ls "$scratch/bout" | wc -l) files"
done
if [ -n "$mutool" ]; then
  for round in 1 2 3; do
    rm -f "$scratch"/mout/*
    t0=$(now)
    sed "s#$scratch/bout/#$scratch/mout/#" "$list" | tr '\t' ' ' |
      LD_LIBRARY_PATH=$mutool_libs xargs -P "$(nproc)" -L 1 sh -c '"$0" draw -q -w 1024 -o "$2" "$1" 2>/dev/null' "$mutool"
    t1=$(now)
    echo "mutool draw, xargs -P $(nproc): $(awk "BEGIN{printf \"%.1f\", $n / (($t1 - $t0) / 1e9)}") files/s wall, $(ls "$scratch/mout" | wc -l) files"
  done
fi
