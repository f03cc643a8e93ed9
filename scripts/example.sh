#!/usr/bin/env bash
# Renders testdata/example.svg to example.png (installing and building as
# needed), with the CPU backend unless a CUDA device is available.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
"$root/build/apps/svg2png" --stats -w 800 "$root/testdata/example.svg" "$root/example.png"
echo "wrote $root/example.png"
