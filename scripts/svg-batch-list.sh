# The SVG batch of the GPU benchmarks (issue 12's, scripts/gpu-e2e-bench.sh
# and scripts/gpu-pdf-ab.sh): the bench inputs 45 times each (links in
# LINKS) and the golden test SVGs once, one "input<TAB>output" line each
# for svg2png --batch, outputs in OUT. Sourced:
#   svg_batch_list BENCH LINKS OUT ROOT > list
svg_batch_list() {
  local bench=$1 links=$2 out=$3 root=$4 i f
  mkdir -p "$links"
  for i in $(seq -w 45); do
    for f in tiger boston hawaii reschart; do
      ln -sf "$bench/$f.svg" "$links/${f}_$i.svg"
      printf '%s\t%s\n' "$links/${f}_$i.svg" "$out/${f}_$i.png"
    done
  done
  for f in "$root"/testdata/golden/*.svg; do
    printf '%s\t%s\n' "$f" "$out/golden_$(basename "$f" .svg).png"
  done
}
