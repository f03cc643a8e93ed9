#!/usr/bin/env bash
# Builds mpvg (installing what is missing) and runs the whole test suite:
# first the fuzz targets' regression runs under ASan and UBSan (clang, in
# build-asan/: scripts/fuzz.sh sanitized), then CTest in build/. GPU tests
# are reported as skipped where no CUDA device exists. The main suite's
# CTest summary is the last thing printed, followed by one line only when
# the sanitized runs failed; the exit status is non-zero if either failed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/build.sh"
echo "== sanitized fuzz regressions (build-asan/: clang, ASan + UBSan)"
sanitized=0
"$root/scripts/fuzz.sh" sanitized || sanitized=$?
echo "== test suite (build/)"
cd "$root/build"
status=0
ctest --output-on-failure --timeout 900 -j "$(nproc 2>/dev/null || echo 2)" || status=$?
if [ "$sanitized" -ne 0 ]; then
  echo "scripts/test.sh: the sanitized fuzz regressions failed (their output is above the test suite's)" >&2
  [ "$status" -ne 0 ] || status=$sanitized
fi
exit "$status"
