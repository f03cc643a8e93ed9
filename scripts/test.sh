#!/usr/bin/env bash
# Builds mpvg (installing what is missing) and runs the whole test suite.
# GPU tests are reported as skipped where no CUDA device exists. CTest's
# summary is the last thing printed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/build.sh"
cd "$root/build"
exec ctest --output-on-failure --timeout 900 -j "$(nproc 2>/dev/null || echo 2)"
