#!/usr/bin/env bash
# Installs what is missing (scripts/setup-debian.sh), then configures and
# builds mpvg in ./build (Release). Incremental: a warm rebuild only
# recompiles what changed. Extra arguments go to the CMake configure step.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup-debian.sh"
jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f "$root/build/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
cmake --build "$root/build" -j "$jobs"
