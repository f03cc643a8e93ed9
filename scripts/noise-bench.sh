#!/usr/bin/env bash
# The noise of an antialiasing preset (issue 46): each input rendered with
# two pattern seeds and with a converged reference (the same filter over a
# stratified pattern of 16 x the samples), compared pixel by pixel
# (mpvg-compare: each pixel's largest channel difference in the 8-bit
# output, in 1/255). Prints one line per input: seed 1 vs seed 2, seed 1 and
# seed 2 vs the reference (p99, max and rms of the channels), and the samples
# evaluated per pixel.
#
#   scripts/noise-bench.sh [DIR] (default ../shared/bench/svg)
#   SVG2PNG=path/to/svg2png  MPVG_NOISE_ARGS="--aa 4x4x32"  WIDTH=1024
#   MPVG_NOISE_INPUTS="reschart tiger boston hawaii"
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dir=${1:-$root/../shared/bench/svg}
svg2png=${SVG2PNG:-$root/build/apps/svg2png}
compare=${COMPARE:-$root/build/apps/mpvg-compare}
args=${MPVG_NOISE_ARGS:-}
width=${WIDTH:-1024}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { sed -n "s/.*\"$1\":\([0-9.e+-]*\).*/\1/p"; }
in255() { awk -v v="$1" 'BEGIN { printf "%.0f", v * 255 }'; }
printf '%-10s %18s %18s %18s %12s\n' input "seeds p99/max/rms" "ref p99/max/rms" "ref2 p99/max/rms" "samples/px"
for name in ${MPVG_NOISE_INPUTS:-reschart tiger boston hawaii}; do
  f=$dir/$name.svg
  [ -f "$f" ] || { echo "$name: no $f" >&2; continue; }
  # shellcheck disable=SC2086
  spp=$("$svg2png" -q --backend cpu --stats -w "$width" $args --seed 1 "$f" "$tmp/s1.png" 2>&1 |
    sed -n 's/^samples \([0-9.]*\) per pixel.*/\1/p')
  # shellcheck disable=SC2086
  "$svg2png" -q --backend cpu -w "$width" $args --seed 2 "$f" "$tmp/s2.png"
  # shellcheck disable=SC2086
  "$svg2png" -q --backend cpu -w "$width" $args --pattern stratified --samples 512 "$f" "$tmp/ref.png"
  row=()
  for pair in "s1 s2" "s1 ref" "s2 ref"; do
    set -- $pair
    j=$("$compare" "$tmp/$1.png" "$tmp/$2.png" --json || true)
    rms=$(awk -v v="$(echo "$j" | field rms_difference)" 'BEGIN { printf "%.2f", v * 255 }')
    row+=("$(in255 "$(echo "$j" | field p99_difference)")/$(in255 "$(echo "$j" | field max_difference)")/$rms")
  done
  printf '%-10s %18s %18s %18s %12s\n' "$name" "${row[0]}" "${row[1]}" "${row[2]}" "${spp:-?}"
done
