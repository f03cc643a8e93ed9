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
