#!/usr/bin/env bash
# One call on a GPU machine (CUDA 13.0, CMake, g++, libpng; no internet, no
# tinyxml2 / FreeType / MuPDF / OpenImageIO): builds the GPU targets, runs the
# whole test suite (GPU tests included), compute-sanitizer memcheck and
# racecheck on one bench input, and the benchmark. What the build lacks
# travels in .deps/ (scripts/gpu-deps.sh). Results go to $OUT (default
# ./gpu-out): ctest.log, sanitizer logs, bench.json, bench.txt.
#
#   scripts/gpu-run.sh [build] [test] [sanitize] [bench] [profile]
#   (default: the first four; profile runs Nsight Compute on the kernels;
#   MPVG_BENCH_ARGS adds mpvg_bench options, e.g. --ramp-lut 256)
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
deps=$root/.deps
out=${OUT:-$root/gpu-out}
build=$root/build-gpu
mkdir -p "$out"
steps=${*:-build test sanitize bench}
export LD_LIBRARY_PATH=$deps/root/usr/lib/x86_64-linux-gnu:${LD_LIBRARY_PATH:-}
export MPVG_BENCH_DIR=$deps/bench
status=0
has() { [[ " $steps " == *" $1 "* ]]; }

if has build; then
  nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,memory.total --format=csv > "$out/gpu.txt" 2>&1
  cat "$out/gpu.txt"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DMPVG_IMAGE_IO=png \
    -DCMAKE_PREFIX_PATH="$deps/root/usr" -DMPVG_CATCH2_V2_INCLUDE="$deps/root/usr/include" \
    -DCMAKE_CUDA_ARCHITECTURES=90 > "$out/configure.log" 2>&1 || { tail -30 "$out/configure.log"; exit 1; }
  t0=$(date +%s)
  cmake --build "$build" -j "$(nproc)" > "$out/build.log" 2>&1 || { grep -E "error" "$out/build.log" | head -30; exit 1; }
  echo "build: $(( $(date +%s) - t0 )) s"
fi
if has test; then
  # A hung test fails after 300 s instead of taking the call with it;
  # MPVG_CTEST_ARGS adds CTest options (e.g. -R / -E).
  (cd "$build" && ctest --output-on-failure --timeout 300 -j 4 ${MPVG_CTEST_ARGS:-} > "$out/ctest.log" 2>&1) || status=1
  grep -E "Test +#|tests passed|FAILED|Skipped" "$out/ctest.log" | tail -15
fi
if has sanitize; then
  for tool in memcheck racecheck; do
    compute-sanitizer --tool $tool --error-exitcode 3 "$build/apps/svg2png" --backend cuda -q -w 512 \
      "$deps/bench/tiger.svg" /tmp/sanitize.png > "$out/sanitizer-$tool.log" 2>&1
    rc=$?
    echo "compute-sanitizer $tool: exit $rc, $(grep -cE 'Invalid|Race|Error' "$out/sanitizer-$tool.log") error lines"
    tail -2 "$out/sanitizer-$tool.log"
    [ $rc = 0 ] || status=1
  done
fi
if has profile; then
  metrics=gpu__time_duration.sum,sm__throughput.avg.pct_of_peak_sustained_elapsed,dram__throughput.avg.pct_of_peak_sustained_elapsed,sm__warps_active.avg.pct_of_peak_sustained_active,smsp__thread_inst_executed_per_inst_executed.ratio,launch__grid_size,launch__registers_per_thread
  for f in tiger hawaii; do
    ncu --clock-control none --csv --metrics "$metrics" \
      -k regex:'k_sample|k_normalize|k_prefilter_lines|k_unit_area_color|k_output|k_split|k_scatter|k_count|k_mark|k_classify|k_compact|k_abstract_write|k_distribute|k_fill_uniform|k_leaf_info' \
      "$build/apps/svg2png" --backend cuda -q -w 1024 "$deps/bench/$f.svg" /tmp/profile.png > "$out/ncu-$f.csv" 2> "$out/ncu-$f.err"
    echo "ncu $f: exit $?, $(grep -c '"' "$out/ncu-$f.csv") rows"
  done
fi
if has bench; then
  "$build/apps/mpvg_bench" --svg2png "$build/apps/svg2png" --json "$out/bench.json" ${MPVG_BENCH_SHAPES:+--shapes "$MPVG_BENCH_SHAPES"} \
    ${MPVG_BENCH_ARGS:-} "$deps/bench/tiger.svg" "$deps/bench/tiger_gradients.svg" "$deps/bench/tiger_groups.svg" "$deps/bench/boston.svg" \
    "$deps/bench/hawaii.svg" "$deps/bench/reschart.svg" \
    | tee "$out/bench.txt" || status=1
fi
exit $status
