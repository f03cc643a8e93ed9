#!/usr/bin/env bash
# libmpvg as a package: installs the build into a scratch prefix, checks
# what is installed and what the library exports, then configures, builds
# and runs tests/consumer/ (a project of its own that only knows the
# prefix), and imports the installed Python module where there is one.
# Then what a user of rsvg-convert or mutool expects of the install
# (README, "Installing"): the programs run from the prefix alone and load
# its own OpenImageIO modules, pkg-config builds a program, the man pages,
# the bash completion, the licence.
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

# ---- the programs (apps/CMakeLists.txt) ----
# Run with LD_LIBRARY_PATH unset: what they need of the prefix they find
# through their RPATH and relative to bin/.
programs="svg2png mpvg-compare"
[ -x "$build/apps/pdf2png" ] && programs="$programs pdf2png"
libdir=$(cd "$(dirname "${lib:-$prefix/lib/none}")" 2>/dev/null && pwd -P)
# (Folders of LD_LIBRARY_PATH outside the build tree and the prefix stay:
# where the system's own libraries are carried so, as on the GPU host.)
outside=$(tr ':' '\n' <<<"${LD_LIBRARY_PATH:-}" | grep -v -e '^$' -e "^$build" -e "^$prefix" | paste -sd: -)
run() { if [ -n "$outside" ]; then env LD_LIBRARY_PATH="$outside" "$@"; else env -u LD_LIBRARY_PATH "$@"; fi; }
for p in $programs; do
  exe=$prefix/bin/$p
  check "bin/$p is installed" test -x "$exe"
  check "bin/$p has an RPATH relative to itself" grep -q 'R.*PATH.*\[\$ORIGIN/' <(readelf -d "$exe" 2>/dev/null)
  check "bin/$p finds every library it needs" test -z "$(run ldd "$exe" | grep 'not found')"
  out=$(run "$exe" --help 2>&1)
  check "$p --help exits 0 and prints the usage" grep -qi "^usage: \(.*/\)\?$p " <<<"$out"
done
for p in svg2png pdf2png; do
  case " $programs " in *" $p "*)
    check "$p --version names mpvg ($(run "$prefix/bin/$p" --version 2>&1))" \
      grep -qx "$p (mpvg) [0-9.]*" <(run "$prefix/bin/$p" --version 2>&1) ;;
  esac
done
# mpvg-compare's --version (once it has one) must say the same.
if run "$prefix/bin/mpvg-compare" --version >"$work/compare-version.txt" 2>&1; then
  check "mpvg-compare --version names mpvg" grep -q "mpvg" "$work/compare-version.txt"
fi

# The same bytes as the build tree's svg2png, on the CPU backend.
svg=$src/testdata/golden/curves.svg
opts=(--backend cpu --aa 1x8 -w 64)
run "$prefix/bin/svg2png" "${opts[@]}" "$svg" "$work/installed.png"
check "the installed svg2png renders a PNG" grep -q PNG <(head -c 8 "$work/installed.png" 2>/dev/null)
"$build/apps/svg2png" "${opts[@]}" "$svg" "$work/built.png"
check "... the same bytes as the build tree's" cmp -s "$work/installed.png" "$work/built.png"
run "$prefix/bin/mpvg-compare" "$work/installed.png" "$work/built.png" >"$work/compare.txt" 2>&1
check "the installed mpvg-compare finds the two equal" test $? = 0
"$build/apps/svg2png" "${opts[@]}" -b black "$svg" "$work/black.png"
run "$prefix/bin/mpvg-compare" -q "$work/installed.png" "$work/black.png"
check "... and one on black different (exit 1)" test $? = 1

# The OpenImageIO modules (MPVG_IMAGE_IO=oiio): a JPEG in an SVG and a TIFF
# from pdf2png load the prefix's own (LD_DEBUG names each file loaded),
# never the build tree's.
if [ -f "$build/lib/mpvg/mpvg_oiio_decoder.so" ]; then
  check "the decoder module is installed in the libdir's mpvg/" test -f "$libdir/mpvg/mpvg_oiio_decoder.so"
  mkdir -p "$work/jpeg"
  cp "$src/testdata/images/rgb.jpg" "$work/jpeg/"
  echo '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image href="rgb.jpg" width="8" height="8"/></svg>' \
    >"$work/jpeg/doc.svg"
  LD_DEBUG=files run "$prefix/bin/svg2png" --backend cpu "$work/jpeg/doc.svg" "$work/jpeg/out.png" 2>"$work/jpeg/ld.txt"
  check "svg2png loads the installed decoder module" grep -q "file=$libdir/mpvg/mpvg_oiio_decoder.so " "$work/jpeg/ld.txt"
  check "... and no module of the build tree" test -z "$(grep "file=$build/lib/mpvg/" "$work/jpeg/ld.txt")"
  "$build/apps/svg2png" --backend cpu "$work/jpeg/doc.svg" "$work/jpeg/built.png" 2>/dev/null
  check "... and draws the JPEG as the build tree's svg2png does" cmp -s "$work/jpeg/out.png" "$work/jpeg/built.png"
  if [ -x "$prefix/bin/pdf2png" ]; then
    LD_DEBUG=files run "$prefix/bin/pdf2png" --backend cpu -r 36 -tiff "$src/testdata/pdf/red-square.pdf" \
      "$work/page" 2>"$work/page-ld.txt"
    check "pdf2png -tiff writes a TIFF" grep -q 'II\*' <(head -c 4 "$work/page-1.tif" 2>/dev/null)
    check "... with the installed encoder module" grep -q "file=$libdir/mpvg/mpvg_oiio_encoder.so " "$work/page-ld.txt"
  fi
fi
if [ -x "$prefix/bin/pdf2png" ]; then
  run "$prefix/bin/pdf2png" --backend cpu -r 36 "$src/testdata/pdf/red-square.pdf" "$work/pdfpage"
  check "the installed pdf2png renders a page" grep -q PNG <(head -c 8 "$work/pdfpage-1.png" 2>/dev/null)
fi

# ---- pkg-config (lib/mpvg.pc.in) ----
pcdir=$(dirname "$(find "$prefix" -name mpvg.pc | head -n 1)")
version=$(sed -n 's/^project(mpvg VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
export PKG_CONFIG_PATH=$pcdir
check "pkg-config knows mpvg $version" test "$(pkg-config --modversion mpvg 2>&1)" = "$version"
flags=$(pkg-config --cflags --libs mpvg 2>&1 | xargs)  # (xargs: without the trailing blank)
check "pkg-config --cflags --libs mpvg ($flags)" \
  test "$flags" = "-I$prefix/include -L$(dirname "$lib") -lmpvg"
# shellcheck disable=SC2086  # the flags are words
if "$cxx" -std=c++17 -o "$work/pkg_config_main" "$src/tests/consumer/pkg_config_main.cpp" $flags \
     -Wl,-rpath,"$(dirname "$lib")" >"$work/pkg-config-build.log" 2>&1; then
  out=$(run "$work/pkg_config_main" 2>&1)
  check "a program built with pkg-config's flags renders ($out)" test "$out" = "3x2 255,0,0,255"
else
  cat "$work/pkg-config-build.log"
  check "a program builds with pkg-config's flags" false
fi
unset PKG_CONFIG_PATH

# ---- man pages (packaging/man/), where help2man was found ----
if grep -q '^HELP2MAN_EXECUTABLE:FILEPATH=/' "$build/CMakeCache.txt"; then
  for p in $programs; do
    page=$prefix/share/man/man1/$p.1
    upper=$(tr a-z A-Z <<<"$p")
    check "man page $p.1 is installed" grep -q "^\.TH \"*$upper\"* \"*1\"*" "$page"
    check "... named $p" grep -qF "$p \- " "$page"
    missing=$(run "$prefix/bin/$p" --help | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u |
      while read -r o; do grep -qF -- "${o//-/\\-}" "$page" || echo "$o"; done)
    check "... documents every long option of --help${missing:+ (not: $missing)}" test -z "$missing"
    check "... with mpvg's licence" grep -q 'AGPL-3.0-or-later' "$page"
  done
else
  echo "skipped: man pages (help2man was not found when configuring)"
fi

# ---- bash completion (packaging/bash-completion/mpvg) ----
completions=$prefix/share/bash-completion/completions
for p in $programs; do
  check "completion file $p is installed" test -f "$completions/$p"
  out=$(bash --norc --noprofile -c "source '$completions/$p' && complete -p $p" 2>&1)
  check "sourcing it registers $p ($out)" test "$out" = "complete -F _mpvg_complete $p"
done
# tab WORD...: what Tab offers for the last word (empty: a new word)
# in $work/tab, sorted and on one line; the programs come from the prefix.
mkdir -p "$work/tab/sub"
touch "$work/tab/a.svg" "$work/tab/B.SVG" "$work/tab/c.png" "$work/tab/d.pdf"
tab() {
  (cd "$work/tab" && PATH="$prefix/bin:$PATH" run bash --norc --noprofile -c '
    source "$0"
    COMP_WORDS=("$@")
    COMP_CWORD=$(($# - 1))
    _mpvg_complete "$1" 2>/dev/null
    printf "%s\n" "${COMPREPLY[@]}" | LC_ALL=C sort | tr "\n" " " | sed "s/ $//"' "$completions/svg2png" "$@")
}
expect() {  # expect "OFFERED" WORD...
  local want=$1 got
  shift
  got=$(tab "$@")
  check "Tab after '$*' offers '$want'" test "$got" = "$want"
  [ "$got" = "$want" ] || echo "  got '$got'"
}
expect "--backend --background --batch" svg2png --ba
expect "1x32 1x8 4x4x32" svg2png --aa ""
expect "1x32 1x8" svg2png --aa = 1x
expect "B.SVG a.svg sub" svg2png ""
expect "c.png sub" svg2png a.svg ""
expect "c.png sub" svg2png -w 100 --aa = 1x8 a.svg ""  # --aa=1x8, as bash splits it
expect "B.SVG a.svg sub" svg2png -o out a.svg ""
expect "auto cpu cuda" svg2png --backend ""
expect "c.png sub" mpvg-compare ""
expect "c.png sub" mpvg-compare --aa ""
expect "--hardfail --hardwarn" mpvg-compare --hard
expect "c.png sub" mpvg-compare --diff ""
if [ -x "$prefix/bin/pdf2png" ]; then
  expect "d.pdf sub" pdf2png ""
  expect "-singlefile" pdf2png -single
  expect "art bleed crop media trim" pdf2png --box ""
  expect "deflate jpeg lzw none packbits" pdf2png -tiffcompression ""
  expect "B.SVG a.svg c.png d.pdf sub" pdf2png -r 72 d.pdf ""
fi
# Every option svg2png --help names is offered after '-'.
missing=$(comm -23 <(run "$prefix/bin/svg2png" --help | grep -oE -- '--[a-z][a-z0-9-]*' | LC_ALL=C sort -u) \
                   <(tab svg2png - | tr ' ' '\n' | LC_ALL=C sort -u))
check "Tab after 'svg2png -' offers every option of --help${missing:+ (not: $missing)}" test -z "$missing"
# bash-completion's own loader finds the files under PREFIX/share.
if [ -f /usr/share/bash-completion/bash_completion ]; then
  out=$(XDG_DATA_DIRS=$prefix/share bash --norc --noprofile -c \
    'source /usr/share/bash-completion/bash_completion; __load_completion mpvg-compare && complete -p mpvg-compare' 2>&1)
  check "bash-completion loads mpvg-compare's from XDG_DATA_DIRS=PREFIX/share ($out)" \
    test "$out" = "complete -F _mpvg_complete mpvg-compare"
fi

# ---- the licence ----
check "LICENSE is in share/doc/mpvg" cmp -s "$src/LICENSE" "$prefix/share/doc/mpvg/LICENSE"
check "THIRD_PARTY.md is in share/doc/mpvg" cmp -s "$src/THIRD_PARTY.md" "$prefix/share/doc/mpvg/THIRD_PARTY.md"
check "LICENSE is in the CMake package" cmp -s "$src/LICENSE" "$(dirname "$(find "$prefix" -name mpvgConfig.cmake | head -n 1)")/LICENSE"
check "LICENSE is the GNU AGPL v3" grep -q 'GNU AFFERO GENERAL PUBLIC LICENSE' "$prefix/share/doc/mpvg/LICENSE"

echo "$failures failure(s)"
[ "$failures" = 0 ]
