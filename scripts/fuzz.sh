#!/usr/bin/env bash
# The fuzz targets of fuzz/ (fuzz/README.md), built with clang under
# libFuzzer, ASan and UBSan in build-fuzz/ (MPVG_FUZZ=ON, no CUDA).
#
#   scripts/fuzz.sh build                 # configure and build every target (-j1 unless JOBS=N)
#   scripts/fuzz.sh seed                  # seed corpora from testdata/ -> build-fuzz/seeds/<target>/
#   scripts/fuzz.sh run TARGET|all SECS   # fuzz (one process, one core, nice 10) for SECS seconds each
#   scripts/fuzz.sh regress               # every target over testdata/fuzz/<target>/ and the
#                                         # regression cases testdata/fuzz/regressions/<target>-*
#   scripts/fuzz.sh merge TARGET          # minimize build-fuzz/corpus + seeds into testdata/fuzz/<target>/
#   scripts/fuzz.sh minimize TARGET FILE  # minimize a crash input (-minimize_crash) to FILE.min
#   scripts/fuzz.sh repro TARGET FILE...  # run inputs once, with the sanitizers' report
#   scripts/fuzz.sh sanitized             # CI's check (scripts/test.sh): the regression runners
#                                         # under ASan and UBSan, no libFuzzer, in build-asan/
#                                         # (MPVG_SANITIZE=ON, -O1, -j nproc unless JOBS=N), and
#                                         # their CTest tests over the same corpora and cases
#
# Targets: svg css path_data pdf image. `run` builds and seeds first; it
# writes new inputs to build-fuzz/corpus/<target>/, crashes to
# build-fuzz/artifacts/<target>/, the log to build-fuzz/logs/<target>.log,
# and prints libFuzzer's status lines and final stats.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bd="$root/build-fuzz"
all_targets=(svg css path_data pdf image)
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

max_len() {
  case "$1" in
    svg) echo 65536 ;; css) echo 16384 ;; path_data) echo 4096 ;; pdf) echo 131072 ;; image) echo 65536 ;;
  esac
}
dict() {
  case "$1" in
    svg) echo "$root/fuzz/svg.dict" ;; css) echo "$root/fuzz/css.dict" ;; path_data) echo "$root/fuzz/path.dict" ;;
    pdf) echo "$root/fuzz/pdf.dict" ;; *) echo "" ;;
  esac
}
common_flags() {
  local d
  d=$(dict "$1")
  echo "-timeout=10 -rss_limit_mb=2048 -max_len=$(max_len "$1") ${d:+-dict=$d}"
}
targets() { if [ "$1" = all ]; then echo "${all_targets[@]}"; else echo "$1"; fi; }

build() {
  if [ ! -f "$bd/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$bd" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DMPVG_ENABLE_CUDA=OFF -DMPVG_FUZZ=ON -DMPVG_BUILD_TESTS=OFF >/dev/null
  fi
  local t list=()
  for t in "${all_targets[@]}"; do
    # fuzz_pdf where MuPDF was found (as pdf2png)
    if [ "$t" != pdf ] || grep -q '^MUPDF_LIBRARY:FILEPATH=/' "$bd/CMakeCache.txt"; then
      list+=("fuzz_$t")
    fi
  done
  nice -n 10 cmake --build "$bd" -j "${JOBS:-1}" --target "${list[@]}"
}

seed() { python3 "$root/fuzz/make_seeds.py" "$bd/seeds"; }

# The sanitized regressions: build-fuzz/'s flags without libFuzzer, so no
# coverage instrumentation and only the fuzz_regress target (the runners and
# the libraries they link, not the applications or the test suite). -O1
# instead of Release's -O3, as ASan's documentation suggests: less inlining,
# so that a report's stack names the function that went wrong even where
# only addr2line symbolizes it (CI: no llvm-symbolizer), for about the same
# compile time (BENCHMARKS.md). Incremental, as build/ is.
sanitized() {
  local sd="$root/build-asan"
  if [ ! -f "$sd/CMakeCache.txt" ]; then
    CC=clang CXX=clang++ cmake -S "$root" -B "$sd" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      "-DCMAKE_C_FLAGS_RELEASE=-O1 -DNDEBUG" "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" \
      -DMPVG_ENABLE_CUDA=OFF -DMPVG_SANITIZE=ON -DMPVG_BUILD_TESTS=OFF >/dev/null
  fi
  cmake --build "$sd" -j "${JOBS:-$(nproc 2>/dev/null || echo 2)}" --target fuzz_regress
  (cd "$sd" && ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)")
}

corpora() {  # the writable corpus first, then the read-only ones
  local t=$1 dirs=("$bd/corpus/$t")
  mkdir -p "$bd/corpus/$t"
  [ -d "$bd/seeds/$t" ] && dirs+=("$bd/seeds/$t")
  [ -d "$root/testdata/fuzz/$t" ] && dirs+=("$root/testdata/fuzz/$t")
  echo "${dirs[@]}"
}

mode=${1:-}
case "$mode" in
  build) build ;;
  seed) seed ;;
  sanitized) sanitized ;;
  run)
    [ $# -eq 3 ] || { echo "usage: $0 run TARGET|all SECONDS" >&2; exit 2; }
    build
    seed >/dev/null
    status=0
    for t in $(targets "$2"); do
      mkdir -p "$bd/artifacts/$t" "$bd/logs"
      echo "== fuzz_$t for $3 s"
      # shellcheck disable=SC2046
      (cd "$bd/artifacts/$t" && nice -n 10 "$bd/fuzz/fuzz_$t" $(common_flags "$t") -max_total_time="$3" \
        -print_final_stats=1 -artifact_prefix="$bd/artifacts/$t/" $(corpora "$t")) 2>&1 |
        tee "$bd/logs/$t.log" | grep -E '^#[0-9]+.*(pulse|DONE|INITED|REDUCE|NEW)|^stat::|ERROR|SUMMARY|Test unit written|Done' |
        grep -vE 'NEW|REDUCE' || true
      grep -q 'Test unit written\|ERROR: libFuzzer\|SUMMARY: ' "$bd/logs/$t.log" && status=1
    done
    exit $status
    ;;
  regress)
    build
    status=0
    for t in "${all_targets[@]}"; do
      [ -x "$bd/fuzz/fuzz_$t" ] || continue
      echo "== fuzz_$t"
      if [ -d "$root/testdata/fuzz/$t" ]; then
        # shellcheck disable=SC2046
        if "$bd/fuzz/fuzz_$t" $(common_flags "$t") -runs=0 "$root/testdata/fuzz/$t" > "$bd/regress-$t-corpus.log" 2>&1; then
          grep -E 'INITED' "$bd/regress-$t-corpus.log" || true
        else
          cat "$bd/regress-$t-corpus.log"; status=1
        fi
      fi
      shopt -s nullglob
      cases=("$root/testdata/fuzz/regressions/$t"-*)
      shopt -u nullglob
      if [ ${#cases[@]} -gt 0 ]; then
        # shellcheck disable=SC2046
        if "$bd/fuzz/fuzz_$t" $(common_flags "$t") "${cases[@]}" > "$bd/regress-$t.log" 2>&1; then
          echo "${#cases[@]} regression cases pass"
        else
          cat "$bd/regress-$t.log"; status=1
        fi
      fi
    done
    exit $status
    ;;
  merge)
    [ $# -eq 2 ] || { echo "usage: $0 merge TARGET" >&2; exit 2; }
    t=$2
    mkdir -p "$root/testdata/fuzz/$t"
    # shellcheck disable=SC2046
    nice -n 10 "$bd/fuzz/fuzz_$t" $(common_flags "$t") -merge=1 "$root/testdata/fuzz/$t" $(corpora "$t") 2>&1 | grep -E 'MERGE-OUTER|ERROR' || true
    echo "testdata/fuzz/$t: $(find "$root/testdata/fuzz/$t" -type f | wc -l) files, $(du -sb "$root/testdata/fuzz/$t" | cut -f1) bytes"
    ;;
  minimize)
    [ $# -eq 3 ] || { echo "usage: $0 minimize TARGET FILE" >&2; exit 2; }
    # shellcheck disable=SC2046
    nice -n 10 "$bd/fuzz/fuzz_$2" $(common_flags "$2") -minimize_crash=1 -max_total_time=120 \
      -exact_artifact_path="$3.min" "$3" 2>&1 | grep -E 'CRASH_MIN|ERROR|SUMMARY' || true
    ls -l "$3.min"
    ;;
  repro)
    [ $# -ge 3 ] || { echo "usage: $0 repro TARGET FILE..." >&2; exit 2; }
    t=$2; shift 2
    # shellcheck disable=SC2046
    exec "$bd/fuzz/fuzz_$t" $(common_flags "$t") "$@"
    ;;
  *) sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
