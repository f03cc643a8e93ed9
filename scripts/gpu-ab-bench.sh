#!/usr/bin/env bash
# A/B on the GPU host: the working tree's build (build-gpu, made by
# scripts/gpu-run.sh build) against a baseline commit, in the same call, as
# every performance claim needs. Prepare the baseline here first:
#   git archive --format=tar BASE > .deps/base-src.tar
# then on the device (carry .deps): scripts/gpu-run.sh build; scripts/gpu-ab-bench.sh
# Prints mpvg_bench for both, the CPU backend's svg2png --stats times (best
# of 5, 4x4x32 and 1x32) and the CUDA samples per pixel. RUNS: mpvg_bench runs.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd); deps=$root/.deps; out=${OUT:-$root/gpu-out}
mkdir -p "$out"
export LD_LIBRARY_PATH=$deps/root/usr/lib/x86_64-linux-gnu:${LD_LIBRARY_PATH:-}
mkdir -p /tmp/basesrc && tar -xf "$deps/base-src.tar" -C /tmp/basesrc
t0=$(date +%s)
cmake -S /tmp/basesrc -B /tmp/basebuild -DCMAKE_BUILD_TYPE=Release -DMPVG_IMAGE_IO=png -DMPVG_BUILD_TESTS=OFF \
  -DCMAKE_PREFIX_PATH="$deps/root/usr" -DMPVG_CATCH2_V2_INCLUDE="$deps/root/usr/include" \
  -DCMAKE_CUDA_ARCHITECTURES=90 > "$out/base-configure.log" 2>&1 || { tail -20 "$out/base-configure.log"; exit 1; }
cmake --build /tmp/basebuild -j "$(nproc)" --target svg2png mpvg_bench > "$out/base-build.log" 2>&1 || { grep error "$out/base-build.log" | head; exit 1; }
echo "base build: $(( $(date +%s) - t0 )) s"
B=$deps/bench
for bin in base new; do
  d=/tmp/basebuild/apps; [ $bin = new ] && d=$root/build-gpu/apps
  echo "== mpvg_bench $bin"
  "$d/mpvg_bench" --runs ${RUNS:-20} "$B/tiger.svg" "$B/boston.svg" "$B/hawaii.svg" "$B/reschart.svg" 2>&1 | tail -${BENCH_TAIL:-30}
done
echo "== CPU backend (16 cores), svg2png --stats, best of 5 sample+integrate / total ms"
for aa in 4x4x32 1x32; do for f in tiger boston hawaii reschart; do for bin in base new; do
  d=/tmp/basebuild/apps; [ $bin = new ] && d=$root/build-gpu/apps
  best=1e9; bt=1e9
  for i in 1 2 3 4 5; do
    o=$("$d/svg2png" -q --backend cpu --stats --aa $aa -w 1024 "$B/$f.svg" /tmp/ab.png 2>&1)
    s=$(echo "$o" | sed -n 's/^sample+integrate \([0-9.]*\) ms/\1/p'); t=$(echo "$o" | sed -n 's/^total \([0-9.]*\) ms/\1/p')
    best=$(awk -v a="$s" -v b="$best" 'BEGIN{print (a<b)?a:b}'); bt=$(awk -v a="$t" -v b="$bt" 'BEGIN{print (a<b)?a:b}')
  done
  echo "cpu $aa $f $bin: sample+integrate $best ms, total $bt ms"
done; done; done
echo "== GPU svg2png --stats samples per pixel (new)"
for f in tiger boston hawaii reschart; do echo "$f: $($root/build-gpu/apps/svg2png -q --backend cuda --stats -w 1024 "$B/$f.svg" /tmp/ab.png 2>&1 | grep -E '^samples')"; done
