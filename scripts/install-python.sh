#!/usr/bin/env bash
# Installs the Python package from a CMake build without pip (Debian's
# route: python3-numpy from apt, no package index): CMake's "python"
# component (python/CMakeLists.txt), the wheel's layout, into a
# site-packages folder, so that `python3 -c 'import mpvg'` works afterwards.
#
#   scripts/install-python.sh [PREFIX]
#
# PREFIX: the folder the package goes into (PREFIX/mpvg/ and its
# dist-info, whose entry points load the pytest plugin); default the user
# site of the Python the build's module is for (python3 -m site
# --user-site, on sys.path by default). Another folder needs
# PYTHONPATH=PREFIX. MPVG_BUILD_DIR: the build (default ./build, made by
# scripts/build.sh).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${MPVG_BUILD_DIR:-$root/build}
if [ ! -f "$build/CMakeCache.txt" ]; then
  echo "install-python: no CMake build in $build: run scripts/build.sh first (or set MPVG_BUILD_DIR)" >&2
  exit 1
fi
# The interpreter the extension was built for (its ABI tag is in the name).
python=$(sed -n 's/^MPVG_PYTHON_EXECUTABLE:INTERNAL=//p' "$build/CMakeCache.txt")
if [ -z "$python" ]; then
  echo "install-python: $build has no Python module (python3-dev and pybind11-dev were missing at configure)" >&2
  exit 1
fi
if ! ls "$build"/python/mpvg/_mpvg*.so > /dev/null 2>&1; then
  echo "install-python: the module is not built yet: cmake --build $build --target mpvg_python" >&2
  exit 1
fi
prefix=${1:-$("$python" -m site --user-site)}
mkdir -p "$prefix"
prefix=$(cd "$prefix" && pwd)
cmake --install "$build" --component python --prefix "$prefix" > /dev/null
echo "install-python: mpvg installed in $prefix/mpvg for $python"
on_path=$("$python" -c 'import sys; print(sys.argv[1] in [p.rstrip("/") for p in sys.path])' "$prefix")
if [ "$on_path" != True ]; then
  echo "install-python: $prefix is not on $python's path: PYTHONPATH=$prefix $python -c 'import mpvg'"
fi
