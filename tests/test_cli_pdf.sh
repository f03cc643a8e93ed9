#!/usr/bin/env bash
# Command-line behaviour of pdf2png: output names as pdftoppm gives them,
# resolution, --scale-to, crops, --singlefile, and one clear error line with
# a non-zero exit for bad input: broken pages (the others still written),
# truncated and encrypted documents.
# usage: test_cli_pdf.sh PDF2PNG SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
declare -A errors
pdf=$src/testdata/pdf/red-square.pdf   # one 100 x 100 pt page

"$bin" -q --backend cpu "$pdf" "$tmp/p"; rc=$?
check "renders page 1 as PREFIX-1.png at 150 dpi" test "$rc" = 0 -a "$(png_size "$tmp/p-1.png")" = 209x209
"$bin" -q --backend cpu -r 72 "$pdf" "$tmp/r"
check "-r sets the resolution" test "$(png_size "$tmp/r-1.png")" = 100x100
"$bin" -q --backend cpu --scale-to 50 "$pdf" "$tmp/s"
check "--scale-to sets the longer side" test "$(png_size "$tmp/s-1.png")" = 50x50
"$bin" -q --backend cpu -r 72 -x 10 -y 20 -W 30 -H 40 "$pdf" "$tmp/c"
check "-x -y -W -H crop" test "$(png_size "$tmp/c-1.png")" = 30x40
"$bin" -q --backend cpu -r 72 --singlefile "$pdf" "$tmp/one"
check "--singlefile writes PREFIX.png" test -f "$tmp/one.png" -a ! -e "$tmp/one-1.png"
err=$("$bin" -q "$src/testdata/pdf/encrypted-password-secret.pdf" "$tmp/e" 2>&1); rc=$?
check "an encrypted document without its password: exit 1, one line" \
  test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 1 -a -n "$(echo "$err" | grep -e '--password')"
"$bin" -q --backend cpu -r 72 --password secret "$src/testdata/pdf/encrypted-password-secret.pdf" "$tmp/e"
check "--password opens it" test -f "$tmp/e-1.png"
err=$("$bin" -q "$tmp/missing.pdf" "$tmp/m" 2>&1); rc=$?
check "a missing file: exit 1, one line" test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 1
out=$("$bin" --help); rc=$?
check "--help describes pdf2png's own options" \
  test "$rc" = 0 -a -n "$(echo "$out" | grep -e 'OUTPUT-PREFIX')" -a -n "$(echo "$out" | grep -e '--dpi')" \
  -a -z "$(echo "$out" | grep -e '--width')"
err=$("$bin" -q --dpi zero "$pdf" "$tmp/m" 2>&1); rc=$?
check "a bad option value: exit 2" test "$rc" = 2
"$bin" -q --backend cpu -r 72 -f 1 -l 3 "$pdf" "$tmp/l"; rc=$?
check "-l past the last page renders what exists" test "$rc" = 0 -a -f "$tmp/l-1.png"

# Broken pages (testdata/pdf/README.md): the others are still written, the
# broken one reported on one line that names it, exit 1.
# three-pages-bad-page2 fails to load page 2 inside MuPDF.
for broken in three-pages-bad-page2; do
  err=$("$bin" -q --backend cpu -r 72 "$src/testdata/pdf/$broken.pdf" "$tmp/$broken" 2>&1); rc=$?
  check "$broken: pages 1 and 3 written, page 2 not" \
    test -f "$tmp/$broken-1.png" -a ! -e "$tmp/$broken-2.png" -a -f "$tmp/$broken-3.png"
  check "$broken: exit 1, one line naming page 2, then the summary ($err)" \
    test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 2 -a -n "$(echo "$err" | grep -e '^pdf2png: page 2: ')" \
    -a "$(echo "$err" | tail -n 1)" = "pdf2png: 3 pages, 2 written, 1 failed"
  errors[$broken]=$(echo "$err" | head -n 1)
done
check "a page that fails to load: MuPDF's reason" test "${errors[three-pages-bad-page2]}" = "pdf2png: page 2: cycle in page tree"

# A truncated document (no xref, no trailer, page 3's content cut): MuPDF
# repairs it; every page it finds is written, the first two intact.
"$bin" -q --backend cpu -r 72 "$src/testdata/pdf/truncated.pdf" "$tmp/t"; rc=$?
"$bin" -q --backend cpu -r 72 "$src/testdata/pdf/three-pages.pdf" "$tmp/full"
check "truncated: repaired, three pages, exit 0" test "$rc" = 0 -a -f "$tmp/t-3.png"
same_pages_1_2() { cmp -s "$tmp/t-1.png" "$tmp/full-1.png" && cmp -s "$tmp/t-2.png" "$tmp/full-2.png"; }
check "truncated: pages 1 and 2 as in the intact document" same_pages_1_2
# Cuts of the intact document every 100 bytes: what is recovered is
# written, anything else is an error line and exit 1 (MuPDF 1.21 gives up
# on a cut inside some dictionaries: "invalid key in dict"); never a crash.
size=$(wc -c < "$src/testdata/pdf/three-pages.pdf")
bad_cuts=""
for ((n = 0; n < size; n += 100)); do
  head -c "$n" "$src/testdata/pdf/three-pages.pdf" > "$tmp/cut.pdf"
  err=$("$bin" -q --backend cpu -r 10 "$tmp/cut.pdf" "$tmp/cut" 2>&1); rc=$?
  if ! { test "$rc" = 0 -a -z "$err" || test "$rc" = 1 -a -n "$err" -a -z "$(echo "$err" | grep -v '^pdf2png: ')"; }; then
    bad_cuts="$bad_cuts $n(rc $rc)"
  fi
done
check "truncated anywhere: output or an error line with exit 1, never a crash${bad_cuts:+ (failed at$bad_cuts)}" \
  test -z "$bad_cuts"

# A page tree that claims 2e9 pages and holds three: three pages, named
# with one digit, at once (MuPDF's /Count alone made 2e9 attempts).
err=$("$bin" -q --backend cpu -r 10 "$src/testdata/pdf/three-pages-count-2e9.pdf" "$tmp/c" 2>&1); rc=$?
check "a lying /Count: the three pages there are, exit 0" \
  test "$rc" = 0 -a -z "$err" -a "$(cd "$tmp" && echo c-*.png)" = "c-1.png c-2.png c-3.png"
# No page to render is an error, as for pdftoppm.
err=$("$bin" -q --backend cpu "$src/testdata/pdf/no-page-tree.pdf" "$tmp/n" 2>&1); rc=$?
check "no page tree: exit 1, one line ($err)" \
  test "$rc" = 1 -a "$err" = "pdf2png: '$src/testdata/pdf/no-page-tree.pdf' has no pages"
err=$("$bin" -q --backend cpu -f 5 "$src/testdata/pdf/three-pages.pdf" "$tmp/f" 2>&1); rc=$?
check "-f past the last page: exit 1, one line ($err)" \
  test "$rc" = 1 -a "$err" = "pdf2png: the first page (5) is past the last page (3)" -a ! -e "$tmp/f-5.png"
err=$("$bin" -q --backend cpu -f 3 -l 2 "$src/testdata/pdf/three-pages.pdf" "$tmp/f" 2>&1); rc=$?
check "-l before -f: exit 1, one line ($err)" test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 1

"$bin" -q --backend cpu -r 72 - "$tmp/in" < "$pdf"
check "- reads the document from stdin, the same image" cmp -s "$tmp/r-1.png" "$tmp/in-1.png"

# Forest frames (core/forest.h): pages rendered together as they queue up,
# the same bytes as a frame per page.
"$bin" -q --backend cpu -r 72 --render-threads 1 --threads 3 --frame-scenes 3 "$src/testdata/pdf/three-pages.pdf" "$tmp/fr3"
"$bin" -q --backend cpu -r 72 --render-threads 1 --frame-scenes 1 "$src/testdata/pdf/three-pages.pdf" "$tmp/fr1"
same_frames() { for k in 1 2 3; do cmp -s "$tmp/fr1-$k.png" "$tmp/fr3-$k.png" || return 1; done; }
check "--frame-scenes 3: the same pages as a frame each" same_frames
err=$("$bin" -q --backend cpu -r 72 --frame-scenes 0 "$pdf" "$tmp/fr0" 2>&1); rc=$?
check "--frame-scenes 0: exit 2" test "$rc" = 2
"$bin" -q --backend cpu -r 72 --devices 0,1 "$pdf" "$tmp/dv"; rc=$?
check "--devices: accepted (the CPU backend renders anyway)" test "$rc" = 0 -a -f "$tmp/dv-1.png"
err=$("$bin" -q --backend cpu -r 72 --devices x "$pdf" "$tmp/dvx" 2>&1); rc=$?
check "--devices x: exit 2" test "$rc" = 2

echo "$fails failure(s)"
test "$fails" = 0
