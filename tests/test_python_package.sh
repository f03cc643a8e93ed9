#!/usr/bin/env bash
# The Python package as its users install it (pyproject.toml,
# scikit-build-core): `python3 -m venv v && v/bin/pip install SOURCE` in a
# scratch folder, then `import mpvg` from the venv, a render equal to
# svg2png's pixels, and `python -m mpvg`. Skipped (77), saying why, where
# the venv module or the package index (for scikit-build-core and pybind11)
# is not available.
#
#   tests/test_python_package.sh SVG2PNG SOURCE_DIR [PYTHON]
set -uo pipefail
svg2png=$1 src=$2 python=${3:-/usr/bin/python3}
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"  # $tmp, check, pixels
if ! "$python" -m venv --system-site-packages "$tmp/v" > "$tmp/venv.log" 2>&1; then
  echo "test_python_package: skipped, $python -m venv fails: $(tail -1 "$tmp/venv.log")"
  exit 77
fi
pip=$tmp/v/bin/pip
# MPVG_PIP_OFFLINE=1: no package index; scikit-build-core and pybind11 are
# importable by the system Python already (e.g. a source checkout of
# scikit-build-core on PYTHONPATH, Debian's python3-pybind11): pip builds
# without isolation and fetches nothing.
pip_args=()
if [ "${MPVG_PIP_OFFLINE:-}" = 1 ]; then
  pip_args=(--no-build-isolation --no-index)
  if ! "$tmp/v/bin/python" -c "import scikit_build_core, pybind11" 2>/dev/null; then
    echo "test_python_package: skipped, MPVG_PIP_OFFLINE=1 but scikit_build_core or pybind11 is not importable"
    exit 77
  fi
elif ! timeout 60 "$pip" download -q --no-deps -d "$tmp/probe" scikit-build-core > "$tmp/probe.log" 2>&1; then
  echo "test_python_package: skipped, no package index to get scikit-build-core from ($(grep -m1 -o 'No matching.*\|Failed to establish[^)]*' "$tmp/probe.log"))"
  exit 77
fi
t0=$(date +%s)
( cd "$tmp" && "$pip" install -q "${pip_args[@]}" "$src" > "$tmp/install.log" 2>&1 )
rc=$?
echo "pip install: exit $rc in $(( $(date +%s) - t0 )) s"
check "pip install SOURCE into a fresh venv" test "$rc" = 0 || tail -20 "$tmp/install.log"
py=$tmp/v/bin/python
svg=$src/testdata/css/linked-expected.svg
check "import mpvg from the venv (not the build tree)" \
  test "$(cd "$tmp" && "$py" -c 'import mpvg, os; print(os.path.dirname(mpvg.__file__).startswith(os.path.realpath("'"$tmp"'/v")))')" = True
"$svg2png" -q --backend cpu -w 64 "$svg" "$tmp/cli.png"
(cd "$tmp" && "$py" -m mpvg --backend cpu -w 64 "$svg" "$tmp/mod.png")
# Every pixel as R-G-B-A (svg2png writes opaque images as RGB).
rgba() { pixels "$1" all | tr ' ' '\n' | awk -F- 'NR == 1 {print; next} NR > 3 {print NF == 3 ? $0 "-255" : $0}'; }
same=$(test "$(rgba "$tmp/cli.png")" = "$(rgba "$tmp/mod.png")" && echo same || echo differ)
check "python -m mpvg writes svg2png's pixels ($same)" test "$same" = same
echo "$fails failure(s)"
test "$fails" = 0
