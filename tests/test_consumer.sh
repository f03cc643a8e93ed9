#!/usr/bin/env bash
# libmpvg as a package: installs the build into a scratch prefix, checks
# what is installed and what the library exports, then configures, builds
# and runs tests/consumer/ (a project of its own that only knows the
# prefix), and imports the installed Python module where there is one.
# usage: test_consumer.sh BUILD_DIR SOURCE_DIR CMAKE CXX_COMPILER [PYTHON PYTHON_INSTALL_DIR]
set -u
build=$1
src=$2
cmake=$3
cxx=$4
python=${5:-}
pydir=${6:-}
work=$build/consumer
prefix=$work/prefix
failures=0
check() {  # check DESCRIPTION COMMAND...
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAILED: $what"; failures=$((failures + 1)); fi
}

rm -rf "$work"
mkdir -p "$work"
if ! "$cmake" --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1; then
  cat "$work/install.log"
  echo "FAILED: cmake --install"
  exit 1
fi
lib=$(find "$prefix" -name 'libmpvg.so.*.*' -type f | head -n 1)
check "libmpvg.so is installed" test -n "$lib"
check "the header is installed" test -f "$prefix/include/mpvg/mpvg.h"
check "the package files are installed" test -n "$(find "$prefix" -name mpvgConfig.cmake)" -a \
  -n "$(find "$prefix" -name mpvgConfigVersion.cmake)" -a -n "$(find "$prefix" -name 'mpvgTargets*.cmake')"
check "the header includes standard headers only" \
  test -z "$(grep -E '^\s*#\s*include' "$prefix/include/mpvg/mpvg.h" | grep -vE '<(cstddef|cstdint|functional|memory|optional|stdexcept|string|string_view|utility|vector)>')"
check "the package asks for no dependency" test -z "$(grep -rl find_dependency "$prefix" --include='*.cmake')"

# Only the public API is exported: every defined dynamic symbol that names
# mpvg belongs to a public class, and nothing of the parser, tinyxml2, the
# CUDA runtime or the internal pipeline shows.
if [ -n "$lib" ]; then
  nm -DC --defined-only "$lib" | sed 's/^[0-9a-f]* [A-Za-z] //' >"$work/exports.txt"
  check "the library exports the public API" grep -q '^mpvg::Renderer::render(mpvg::SvgDocument const&' "$work/exports.txt"
  public='^(mpvg::(Renderer|SvgDocument|PdfDocument|Color)::|mpvg::(download|read_png|write_png|compare)\(mpvg::[A-Za-z]+ const&|mpvg::(read_png|write_png)\(std::|(typeinfo|typeinfo name|vtable) for mpvg::(Renderer|SvgDocument|PdfDocument|Color)$)'
  check "the library exports nothing internal" \
    test -z "$(grep -iE 'mpvg|tinyxml|cuda|svg::|stroke' "$work/exports.txt" | grep -vE "$public")"
  grep -iE 'mpvg|tinyxml|cuda|svg::|stroke' "$work/exports.txt" | grep -vE "$public"
fi

if "$cmake" -S "$src/tests/consumer" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
     -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/configure.log" 2>&1 &&
   "$cmake" --build "$work/build" >"$work/build.log" 2>&1; then
  check "find_package found the installed package" grep -q "mpvg package: $prefix/" "$work/configure.log"
  check "the program runs against the installed library" \
    grep -q "libmpvg.so.* => $prefix/" <(ldd "$work/build/mpvg_consumer")
  "$work/build/mpvg_consumer" "$src"
  check "the consumer's checks pass" test $? = 0
else
  cat "$work/configure.log" "$work/build.log" 2>/dev/null | tail -n 40
  check "the consumer configures and builds against the installed package" false
fi

if [ -n "$python" ]; then
  out=$(PYTHONPATH="$prefix/$pydir" "$python" -c \
    'import mpvg; a = mpvg.Renderer("cpu").render_svg(b"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"3\" height=\"2\"/>", aa="1x8"); print(mpvg.__file__, a.shape)' 2>&1)
  check "the installed Python module imports and renders ($out)" grep -q "^$prefix/.* (2, 3, 4)$" <<<"$out"
fi

echo "$failures failure(s)"
[ "$failures" = 0 ]
