#!/usr/bin/env bash
# Writes the expected dump of a new scene-dump case (testdata/svg-dumps/NAME.svg
# -> NAME.dump) with the svg_dump tool of build/. Never overwrites: an
# expected dump is written once, read through line by line against the
# case's comment, and committed; a later difference is a change to review.
#
#   scripts/new-svg-dump.sh testdata/svg-dumps/NAME.svg [BUILD_DIR]
set -euo pipefail
svg=$1
build=${2:-build}
out=${svg%.svg}.dump
if [ -e "$out" ]; then
  echo "new-svg-dump: $out exists; read the test's difference instead of regenerating it" >&2
  exit 1
fi
"$build/tests/svg_dump" "$svg" > "$out"
echo "wrote $out: read it before committing"
