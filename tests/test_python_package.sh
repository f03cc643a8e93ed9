#!/usr/bin/env bash
# The Python package as its users install it, by both routes:
#  - Debian's, without pip (scripts/install-python.sh: CMake's "python"
#    component into a scratch prefix), then `import mpvg` with
#    PYTHONPATH=PREFIX from another folder: the installed copy (its own
#    libmpvg, not the build tree's), a render equal to svg2png's pixels
#    through `python -m mpvg`, and the pytest11 entry point in its
#    dist-info;
#  - pip's (pyproject.toml, scikit-build-core): `python3 -m venv v &&
#    v/bin/pip install SOURCE`, the same checks from the venv; skipped,
#    saying why, where venv or a package index (for scikit-build-core and
#    pybind11) is not available. MPVG_PIP_OFFLINE=1: build without an
#    index where scikit-build-core and pybind11 are importable.
#
#   tests/test_python_package.sh SVG2PNG SOURCE_DIR [PYTHON [BUILD_DIR]]
set -uo pipefail
svg2png=$1 src=$2 python=${3:-/usr/bin/python3}
build=${4:-$(cd "$(dirname "$svg2png")/.." && pwd)}
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"  # $tmp, check, pixels
svg=$src/testdata/css/linked-expected.svg
"$svg2png" -q --backend cpu -w 64 "$svg" "$tmp/cli.png"
# Every pixel as R-G-B-A (svg2png writes opaque images as RGB).
rgba() { pixels "$1" all | tr ' ' '\n' | awk -F- 'NR == 1 {print; next} NR > 3 {print NF == 3 ? $0 "-255" : $0}'; }

# checks_for NAME PY [ENV...]: the installed package `import mpvg` finds
# with PY (run from $tmp/elsewhere with the environment ENV), where
# `expect` says it must lie.
checks_for() {
  local name=$1 py=$2 expect=$3
  shift 3
  mkdir -p "$tmp/elsewhere"
  local where
  where=$(cd "$tmp/elsewhere" && env "$@" "$py" -c 'import mpvg, os; print(os.path.realpath(mpvg.__file__))' 2>&1)
  check "$name: import mpvg finds the installed copy ($where)" test "${where#"$expect"}" != "$where"
  # The library the extension loaded: the one installed beside it.
  local lib
  lib=$(cd "$tmp/elsewhere" && env "$@" "$py" -c '
import mpvg
print(next((l.split()[-1] for l in open("/proc/self/maps") if "libmpvg.so" in l), "none"))' 2>&1)
  check "$name: the extension loads the installed libmpvg ($lib)" test "${lib#"$expect"}" != "$lib"
  rm -f "$tmp/mod.png"
  (cd "$tmp/elsewhere" && env "$@" "$py" -m mpvg --backend cpu -w 64 "$svg" "$tmp/mod.png")
  local same
  same=$(test -s "$tmp/mod.png" && test "$(rgba "$tmp/cli.png")" = "$(rgba "$tmp/mod.png")" && echo same || echo differ)
  check "$name: python -m mpvg writes svg2png's pixels ($same)" test "$same" = same
  local plugin
  plugin=$(cd "$tmp/elsewhere" && env "$@" "$py" -c '
from importlib.metadata import entry_points
print([e.value for e in entry_points(group="pytest11") if e.name == "mpvg"])' 2>&1)
  check "$name: the pytest11 entry point mpvg.testing is installed ($plugin)" test "$plugin" = "['mpvg.testing']"
}

# ---- Debian's route: scripts/install-python.sh PREFIX ----
prefix=$tmp/site
ran=0
if ! ls "$build"/python/mpvg/_mpvg*.so > /dev/null 2>&1; then
  echo "test_python_package: Debian route skipped, the build ($build) has no Python module"
elif ran=1 && MPVG_BUILD_DIR=$build "$src/scripts/install-python.sh" "$prefix" > "$tmp/install-python.log" 2>&1; then
  check "install-python.sh: exit 0" true
  check "install-python.sh: the image decoder module beside the library" \
    test -e "$prefix/mpvg/mpvg/mpvg_oiio_decoder.so" -o ! -e "$build/lib/mpvg/mpvg_oiio_decoder.so"
  checks_for "install-python.sh" "$python" "$prefix/mpvg" PYTHONPATH="$prefix"
else
  check "install-python.sh: exit 0" false
  cat "$tmp/install-python.log"
fi

# ---- pip's route: a fresh venv ----
pip_route() {
  if ! "$python" -m venv --system-site-packages "$tmp/v" > "$tmp/venv.log" 2>&1; then
    echo "test_python_package: pip route skipped, $python -m venv fails: $(tail -1 "$tmp/venv.log")"
    return 77
  fi
  local pip=$tmp/v/bin/pip pip_args=()
  if [ "${MPVG_PIP_OFFLINE:-}" = 1 ]; then
    pip_args=(--no-build-isolation --no-index)
    if ! "$tmp/v/bin/python" -c "import scikit_build_core, pybind11" 2>/dev/null; then
      echo "test_python_package: pip route skipped, MPVG_PIP_OFFLINE=1 but scikit_build_core or pybind11 is not importable"
      return 77
    fi
  elif ! timeout 60 "$pip" download -q --no-deps -d "$tmp/probe" scikit-build-core > "$tmp/probe.log" 2>&1; then
    echo "test_python_package: pip route skipped, no package index to get scikit-build-core from ($(grep -m1 -o 'No matching.*\|Failed to establish[^)]*' "$tmp/probe.log"))"
    return 77
  fi
  local t0 rc
  t0=$(date +%s)
  ( cd "$tmp" && "$pip" install -q "${pip_args[@]}" "$src" > "$tmp/install.log" 2>&1 )
  rc=$?
  echo "pip install: exit $rc in $(( $(date +%s) - t0 )) s"
  check "pip install SOURCE into a fresh venv" test "$rc" = 0 || tail -20 "$tmp/install.log"
  checks_for "pip" "$tmp/v/bin/python" "$(realpath "$tmp/v")"
}
pip_route
pip_rc=$?
if [ "$ran" = 0 ] && [ "$pip_rc" = 77 ]; then
  echo "test_python_package: skipped, neither route could run"
  exit 77
fi

echo "$fails failure(s)"
test "$fails" = 0
