#!/usr/bin/env bash
# Prepares .deps/ (ignored by git) for a GPU host that has CUDA, CMake, g++
# and libpng but no internet: Debian's tinyxml2, libdeflate and Catch2 v2 packages
# unpacked under .deps/root, and the bench inputs under .deps/bench (with
# tiger_gradients.svg, scripts/make_gradient_bench.py, and tiger_groups.svg,
# scripts/make_group_bench.py).
# Run on the Debian development machine; then carry .deps with the checkout.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
deps=$root/.deps
bench=${1:-$root/../shared/bench/svg}
mkdir -p "$deps/debs" "$deps/root" "$deps/bench"
(cd "$deps/debs" && apt-get download libtinyxml2-9 libtinyxml2-dev catch2 libdeflate0 libdeflate-dev >/dev/null)
for f in "$deps"/debs/*.deb; do dpkg -x "$f" "$deps/root"; done
cp "$bench"/*.svg "$deps/bench/"
# The gradient-heavy input: tiger with every solid fill a gradient.
python3 "$root/scripts/make_gradient_bench.py" "$bench/tiger.svg" > "$deps/bench/tiger_gradients.svg"
# The group-heavy input: tiger's paths in three levels of masked groups.
python3 "$root/scripts/make_group_bench.py" "$bench/tiger.svg" > "$deps/bench/tiger_groups.svg"
du -sh "$deps"
