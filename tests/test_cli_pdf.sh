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
check "a bad option value: exit 99, as pdftoppm's usage errors" test "$rc" = 99
# svg2png's options are refused, not ignored (issue 47): exit 99, one line
# that names the option, and no page written.
for opt in "-w 100" "--width 100" "--height 100" "-z 3" "-b red" "-a" "--server" "--shard 0/2" \
  "--font-dir $tmp" "--languages de" "--allow-read $tmp" "--batch $tmp/list"; do
  err=$("$bin" -q $opt "$pdf" "$tmp/svgopt" 2>&1); rc=$?
  check "pdf2png refuses svg2png's ${opt%% *}" \
    test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a -n "$(echo "$err" | grep -e "${opt%% *} is an svg2png option")" \
    -a ! -e "$tmp/svgopt-1.png"
done
err=$("$bin" -q --output "$tmp/two" "$pdf" "$pdf" 2>&1); rc=$?
check "two documents are a usage error, not the first one rendered" \
  test "$rc" = 99 -a -n "$(echo "$err" | grep -e 'one document a run')" -a ! -e "$tmp/two-1.png"
for h in -h -help; do
  out=$("$bin" $h); rc=$?
  check "pdftoppm's $h prints the help" test "$rc" = 0 -a -n "$(echo "$out" | grep -e 'OUTPUT-PREFIX')"
done
"$bin" -q --backend cpu -r 72 -f 1 -l 3 "$pdf" "$tmp/l"; rc=$?
check "-l past the last page renders what exists" test "$rc" = 0 -a -f "$tmp/l-1.png"

# Broken pages (testdata/pdf/README.md): the others are still written, the
# broken one reported on one line that names it, exit 1.
# three-pages-bad-page2 fails to load page 2 inside MuPDF.
for broken in three-pages-bad-page2; do
  err=$("$bin" -q --backend cpu -r 72 "$src/testdata/pdf/$broken.pdf" "$tmp/$broken" 2>&1); rc=$?
  check "$broken: pages 1 and 3 written, page 2 not" \
    test -f "$tmp/$broken-1.png" -a ! -e "$tmp/$broken-2.png" -a -f "$tmp/$broken-3.png"
  check "$broken: exit 99 (pdftoppm's other error), one line naming page 2, then the summary ($err)" \
    test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 2 -a -n "$(echo "$err" | grep -e '^pdf2png: page 2: ')" \
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
# written, anything else is an error line and exit 1 (the document cannot
# be opened) or 99 (pages that fail) (MuPDF 1.21 gives up
# on a cut inside some dictionaries: "invalid key in dict"); never a crash.
size=$(wc -c < "$src/testdata/pdf/three-pages.pdf")
bad_cuts=""
for ((n = 0; n < size; n += 100)); do
  head -c "$n" "$src/testdata/pdf/three-pages.pdf" > "$tmp/cut.pdf"
  err=$("$bin" -q --backend cpu -r 10 "$tmp/cut.pdf" "$tmp/cut" 2>&1); rc=$?
  if ! { test "$rc" = 0 -a -z "$err" || { test "$rc" = 1 -o "$rc" = 99 && test -n "$err" -a -z "$(echo "$err" | grep -v '^pdf2png: ')"; }; }; then
    bad_cuts="$bad_cuts $n(rc $rc)"
  fi
done
check "truncated anywhere: output or an error line with exit 1 or 99, never a crash${bad_cuts:+ (failed at$bad_cuts)}" \
  test -z "$bad_cuts"

# A page tree that claims 2e9 pages and holds three: three pages, named
# with one digit, at once (MuPDF's /Count alone made 2e9 attempts).
err=$("$bin" -q --backend cpu -r 10 "$src/testdata/pdf/three-pages-count-2e9.pdf" "$tmp/c" 2>&1); rc=$?
check "a lying /Count: the three pages there are, exit 0" \
  test "$rc" = 0 -a -z "$err" -a "$(cd "$tmp" && echo c-*.png)" = "c-1.png c-2.png c-3.png"
# No page to render is an error, as for pdftoppm.
err=$("$bin" -q --backend cpu "$src/testdata/pdf/no-page-tree.pdf" "$tmp/n" 2>&1); rc=$?
check "no page tree: exit 99, one line ($err)" \
  test "$rc" = 99 -a "$err" = "pdf2png: '$src/testdata/pdf/no-page-tree.pdf' has no pages"
err=$("$bin" -q --backend cpu -f 5 "$src/testdata/pdf/three-pages.pdf" "$tmp/f" 2>&1); rc=$?
check "-f past the last page: exit 99, one line ($err)" \
  test "$rc" = 99 -a "$err" = "pdf2png: the first page (5) is past the last page (3)" -a ! -e "$tmp/f-5.png"
err=$("$bin" -q --backend cpu -f 3 -l 2 "$src/testdata/pdf/three-pages.pdf" "$tmp/f" 2>&1); rc=$?
check "-l before -f: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1

# pdftoppm's spellings and meanings (issue 47).
three=$src/testdata/pdf/three-pages.pdf
boxes=$src/testdata/pdf/page-boxes.pdf
names() { (cd "$tmp" && ls | grep "^$1" | tr '\n' ' '); }
"$bin" -q --backend cpu -r 10 -o "$three" "$tmp/odd"
"$bin" -q --backend cpu -r 10 -e "$three" "$tmp/even"
check "-o and -e: odd and even pages (pdftoppm's meaning)" \
  test "$(names odd)$(names even)" = "odd-1.png odd-3.png even-2.png "
err=$("$bin" -q -o -e "$three" "$tmp/oe" 2>&1); rc=$?
check "-o with -e: exit 99, one line" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1
err=$("$bin" -q -e "$pdf" "$tmp/noeven" 2>&1); rc=$?
check "-e on a one-page document: no page, exit 99 ($err)" test "$rc" = 99 -a -n "$(echo "$err" | grep 'no even page')"
"$bin" -q --backend cpu -r 10 --pages 3-2 "$three" "$tmp/back"
"$bin" -q --backend cpu -r 10 --pages 1,N -f 1 "$three" "$tmp/bad" 2>/dev/null; rc=$?
check "--pages with -f: exit 99" test "$rc" = 99
"$bin" -q --backend cpu -r 10 --pages 1,N "$three" "$tmp/list"
"$bin" -q --backend cpu -r 10 --pages 2-N -o "$three" "$tmp/lodd"
check "--pages 3-2, 1,N, and 2-N with -o: the pages asked for" \
  test "$(names back)$(names list)$(names lodd)" = "back-2.png back-3.png list-1.png list-3.png lodd-3.png "
check "--pages: the same page as -f/-l gives" cmp -s "$tmp/list-3.png" "$tmp/lodd-3.png"
for bad in "1,1" "2-3,3" "0" "4" "1-x" "-2" ","; do
  err=$("$bin" -q --backend cpu -r 10 --pages "$bad" "$three" "$tmp/pl" 2>&1); rc=$?
  check "--pages '$bad': exit 99, one line, nothing written ($err)" \
    test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a -z "$(names pl)"
done
"$bin" -q --backend cpu -r 10 -singlefile -f 2 "$three" "$tmp/sf"
"$bin" -q --backend cpu -r 10 --singlefile -forcenum -f 2 "$three" "$tmp/fn"
"$bin" -q --backend cpu -r 10 -sep _ -f 3 "$three" "$tmp/sep"
check "-singlefile (one dash), -forcenum, -sep _" test "$(names sf)$(names fn)$(names sep)" = "sf.png fn-2.png sep_3.png "
err=$("$bin" -q -sep ab "$three" "$tmp/sep2" 2>&1); rc=$?
check "-sep of two characters: exit 99" test "$rc" = 99
err=$("$bin" --backend cpu -r 10 -progress "$three" "$tmp/pg" 2>&1 >/dev/null | grep -v summary | grep -v '^pdf2png')
check "-progress: 'PAGE LAST FILE' a page, as pdftoppm ($err)" \
  test "$(echo "$err" | sort)" = "$(printf '1 3 %s\n2 3 %s\n3 3 %s' "$tmp/pg-1.png" "$tmp/pg-2.png" "$tmp/pg-3.png")"
"$bin" -q --backend cpu -r 72 -singlefile "$pdf" > "$tmp/stdout.png"; rc=$?
check "no OUTPUT-PREFIX: the page to standard output, as pdftoppm" test "$rc" = 0 -a "$(png_size "$tmp/stdout.png")" = 100x100
"$bin" -q --backend cpu -r 72 -singlefile "$pdf" - > "$tmp/dash.png"
check "OUTPUT-PREFIX '-': standard output, the same bytes as a file" cmp -s "$tmp/dash.png" "$tmp/r-1.png"
check "... and no file named '-.png'" test ! -e ./-.png -a ! -e "$tmp/-.png"
err=$("$bin" -q --backend cpu -r 10 "$three" 2>&1 > "$tmp/three-out.png"); rc=$?
check "three pages to standard output: exit 99, one line, nothing written ($err)" \
  test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a ! -s "$tmp/three-out.png"
if command -v script > /dev/null; then
  err=$(script -qec "'$bin' -q --backend cpu -singlefile '$pdf'" /dev/null 2>&1 | tr -d '\r'); rc=$?
  check "standard output a terminal: refused with one line ($err)" test -n "$(echo "$err" | grep 'is a terminal')"
fi
# Sizes as pdftoppm 22.12 gives them for this page of 300 x 200 pt (its
# MediaBox): -scale-to-x alone keeps -r's resolution down, -1 the aspect.
for case in "-scale-to 100:100x67" "-scale-to-x 100:100x417" "-scale-to-y 100:625x100" \
  "-scale-to-x 100 -scale-to-y -1:100x67" "-scale-to-x -1 -scale-to-y 100:150x100" \
  "-scale-to-x 100 -scale-to-y 50:100x50" "-rx 72 -ry 36:300x100" "--scale-to 100 -r 300:100x67"; do
  "$bin" -q --backend cpu --box media ${case%%:*} -singlefile "$boxes" "$tmp/sz"
  check "${case%%:*}: ${case##*:}, as pdftoppm" test "$(png_size "$tmp/sz.png")" = "${case##*:}"
done
"$bin" -q --backend cpu --box media -rx 72 -ry 36 -singlefile "$boxes" "$tmp/phys"
check "the PNG records its resolution (pHYs, per metre, as pdftoppm's): $(phys "$tmp/phys.png")" \
  test "$(phys "$tmp/phys.png")" = "2835 1417 1"
"$bin" -q --backend cpu -r 72 -upw secret "$src/testdata/pdf/encrypted-password-secret.pdf" "$tmp/upw"
"$bin" -q --backend cpu -r 72 -opw secret "$src/testdata/pdf/encrypted-password-secret.pdf" "$tmp/opw"
check "-upw and -opw: the password" test -f "$tmp/upw-1.png" -a -f "$tmp/opw-1.png"
out=$("$bin" -v); rc=$?
check "-v: the version, exit 0" test "$rc" = 0 -a -n "$(echo "$out" | grep mpvg)"
err=$("$bin" -q --backend cpu -r 10 "$three" "$tmp/nodir/x" 2>&1); rc=$?
check "an output that cannot be written: exit 2, as pdftoppm" test "$rc" = 2
"$bin" -q --backend cpu -r 10 --report "$tmp/report.jsonl" "$src/testdata/pdf/three-pages-bad-page2.pdf" "$tmp/rep"; rc=$?
got=$(python3 -c "
import json, sys
for line in open(sys.argv[1]):
    r = json.loads(line)
    print(r['input'].rsplit('/', 1)[1], r['output'].rsplit('/', 1)[1], r['status'], type(r['ms']).__name__, r['warnings'], 'error' in r)
" "$tmp/report.jsonl" | sort | tr '\n' ';')
check "--report: a JSON line a page, the failed one with its error ($got)" \
  test "$rc" = 99 -a "$got" = "three-pages-bad-page2.pdf:1 rep-1.png ok float [] False;three-pages-bad-page2.pdf:2 rep-2.png failed float [] True;three-pages-bad-page2.pdf:3 rep-3.png ok float [] False;"

"$bin" -q --backend cpu -r 72 - "$tmp/in" < "$pdf"
check "- reads the document from stdin, the same image" cmp -s "$tmp/r-1.png" "$tmp/in-1.png"

# Forest frames (frame/forest.h): pages rendered together as they queue up,
# the same bytes as a frame per page.
"$bin" -q --backend cpu -r 72 --render-threads 1 --threads 3 --frame-scenes 3 "$src/testdata/pdf/three-pages.pdf" "$tmp/fr3"
"$bin" -q --backend cpu -r 72 --render-threads 1 --frame-scenes 1 "$src/testdata/pdf/three-pages.pdf" "$tmp/fr1"
same_frames() { for k in 1 2 3; do cmp -s "$tmp/fr1-$k.png" "$tmp/fr3-$k.png" || return 1; done; }
check "--frame-scenes 3: the same pages as a frame each" same_frames
err=$("$bin" -q --backend cpu -r 72 --frame-scenes 0 "$pdf" "$tmp/fr0" 2>&1); rc=$?
check "--frame-scenes 0: exit 99" test "$rc" = 99
"$bin" -q --backend cpu -r 72 --devices 0,1 "$pdf" "$tmp/dv"; rc=$?
check "--devices: accepted (the CPU backend renders anyway)" test "$rc" = 0 -a -f "$tmp/dv-1.png"
err=$("$bin" -q --backend cpu -r 72 --devices x "$pdf" "$tmp/dvx" 2>&1); rc=$?
check "--devices x: exit 99" test "$rc" = 99

# Page boxes (--box; scripts/make_pdf_features.py page_boxes): sizes at
# 72 dpi and, at each box's lower-left corner, the square of its colour
# (as pdftoppm -r 72 draws the MediaBox and, with -cropbox, the CropBox).
# MediaBox and CropBox are inherited from the page tree; the ArtBox
# reaches past the MediaBox (intersected: 250 x 120); page 2 is turned by
# /Rotate 90 and has no boxes of its own (TrimBox = CropBox).
near() {  # the same words, numbers (split at '-' and 'x') within 2
  python3 - "$1" "$2" <<'PY'
import re, sys
a, b = (re.split(r"[-x ]+", s.strip()) for s in sys.argv[1:3])
sys.exit(len(a) != len(b) or any(abs(int(p) - int(q)) > 2 for p, q in zip(a, b)))
PY
}
boxes=$src/testdata/pdf/page-boxes.pdf
for case in "media 300x200 5,195 255-0-0" "crop 260x180 5,175 0-255-0" "bleed 240x160 5,155 0-0-255" \
  "trim 220x140 5,135 0-0-0" "art 250x120 5,115 255-0-255"; do
  set -- $case
  "$bin" -q --backend cpu -r 72 -f 1 -l 1 --box "$1" "$boxes" "$tmp/box-$1"
  got=$(pixels "$tmp/box-$1-1.png" "$3" 15,15)
  check "--box $1: $2, its corner square at the bottom left ($got)" near "$got" "$2 8 2 $4 229-229-229"
done
"$bin" -q --backend cpu -r 72 "$boxes" "$tmp/box-default"
"$bin" -q --backend cpu -r 72 -cropbox "$boxes" "$tmp/box-cropbox"
same_crop() {
  cmp -s "$tmp/box-default-1.png" "$tmp/box-crop-1.png" && cmp -s "$tmp/box-cropbox-1.png" "$tmp/box-crop-1.png" &&
    cmp -s "$tmp/box-default-2.png" "$tmp/box-cropbox-2.png"
}
check "the default box is the CropBox, -cropbox too" same_crop
"$bin" -q --backend cpu -r 72 -f 2 --box media "$boxes" "$tmp/rot-media"
"$bin" -q --backend cpu -r 72 -f 2 --box trim "$boxes" "$tmp/rot-trim"
got="$(pixels "$tmp/rot-media-2.png" 5,5) / $(pixels "$tmp/box-default-2.png" 5,5) / $(pixels "$tmp/rot-trim-2.png" 5,5)"
check "/Rotate 90: the MediaBox 200x300 and the CropBox 180x260, their corners at the top left; TrimBox = CropBox ($got)" \
  near "${got//\//}" "200x300 8 2 255-0-0 180x260 8 2 0-255-0 180x260 8 2 0-255-0"
"$bin" -q --backend cpu -r 144 --box art -f 1 -l 1 "$boxes" "$tmp/art144"
check "--box art at 144 dpi: 500x240" test "$(png_size "$tmp/art144-1.png")" = 500x240

# -gray and -mono (lib/output/png_writer.h): colour type and depth from the
# header, grey = round(0.30 R + 0.59 G + 0.11 B) of the RGB output of the
# same page, mono = that grey against the thresholds of
# poppler's SplashScreen below 300 dpi, a 4x4 dispersed-dot matrix (white
# where grey >= its threshold; pdftoppm 22.12 -mono makes every pixel of
# this page so from its -gray output).
ramp=$src/testdata/pdf/grey-ramp.pdf
"$bin" -q --backend cpu -r 72 "$ramp" "$tmp/ramp-rgb"
"$bin" -q --backend cpu -r 72 -gray "$ramp" "$tmp/ramp-gray"
"$bin" -q --backend cpu -r 72 --gray --bits 16 "$ramp" "$tmp/ramp-gray16"
"$bin" -q --backend cpu -r 72 -gray --transparent "$ramp" "$tmp/ramp-grayt"
"$bin" -q --backend cpu -r 72 -mono "$ramp" "$tmp/ramp-mono"
"$bin" -q --backend cpu -r 72 --mono --compression 1 "$ramp" "$tmp/ramp-mono1"
"$bin" -q --backend cpu -r 72 -gray --compression 0 "$ramp" "$tmp/ramp-gray0"
header() { echo "$(od -An -tu1 -j24 -N2 "$1" | tr -s ' ')"; }
check "-gray: 8-bit grey (depth 8, colour type 0)" test "$(header "$tmp/ramp-gray-1.png")" = " 8 0"
check "-gray --bits 16: depth 16, colour type 0" test "$(header "$tmp/ramp-gray16-1.png")" = " 16 0"
check "-gray --transparent (a page not covered): grey and alpha, colour type 4" \
  test "$(header "$tmp/ramp-grayt-1.png")" = " 8 4"
check "-mono: depth 1, colour type 0" test "$(header "$tmp/ramp-mono-1.png")" = " 1 0"
pixels "$tmp/ramp-rgb-1.png" all > "$tmp/ramp-rgb.txt"
pixels "$tmp/ramp-gray-1.png" all > "$tmp/ramp-gray.txt"
pixels "$tmp/ramp-gray16-1.png" all > "$tmp/ramp-gray16.txt"
pixels "$tmp/ramp-grayt-1.png" all > "$tmp/ramp-grayt.txt"
pixels "$tmp/ramp-mono-1.png" all > "$tmp/ramp-mono.txt"
pixels "$tmp/ramp-mono1-1.png" all > "$tmp/ramp-mono1.txt"
pixels "$tmp/ramp-gray0-1.png" all > "$tmp/ramp-gray0.txt"
compare_grey() {  # RGB text, grey text, scale of grey (1 or 257), "mono"|"grey"
  python3 - "$@" <<'PY'
import sys
rgb = open(sys.argv[1]).read().split()
grey = open(sys.argv[2]).read().split()
scale, mode = int(sys.argv[3]), sys.argv[4]
w, h = map(int, rgb[0].split("x"))
if grey[0] != rgb[0] or len(rgb) != len(grey):
    sys.exit("sizes differ")
worst, bad, levels = 0, 0, set()
for i, (a, b) in enumerate(zip(rgb[3:], grey[3:])):
    r, g, bl = map(int, a.split("-"))
    v = int(b.split("-")[0])
    want = 0.30 * r + 0.59 * g + 0.11 * bl
    if mode == "grey":
        worst = max(worst, abs(v / scale - want))
    else:
        x, y = i % w, i // w
        t = [[17, 255, 34, 204], [153, 85, 170, 102], [51, 221, 1, 238], [187, 119, 136, 68]][y & 3][x & 3]
        bad += v != (1 if (30 * r + 59 * g + 11 * bl + 50) // 100 >= t else 0)
        levels.add(v)
if mode == "grey":
    print("ok" if worst <= 1 else "off by %.2f" % worst)
else:
    print("ok" if bad == 0 and levels == {0, 1} else "%d pixels differ, values %s" % (bad, sorted(levels)))
PY
}
got=$(compare_grey "$tmp/ramp-rgb.txt" "$tmp/ramp-gray.txt" 1 grey)
check "-gray: each pixel the weighted grey of the RGB output within 1/255 ($got)" test "$got" = ok
got=$(compare_grey "$tmp/ramp-rgb.txt" "$tmp/ramp-gray16.txt" 257 grey)
check "-gray --bits 16: the same within 1/255 ($got)" test "$got" = ok
check "-gray --compression 0: the same pixels" cmp -s "$tmp/ramp-gray.txt" "$tmp/ramp-gray0.txt"
check "-gray --transparent: transparent where the page is empty" \
  test "$(pixels "$tmp/ramp-grayt-1.png" 250,35 5,35 | sed -E 's/ [0-9]+-/ /g')" = "256x40 8 4 0 255"
got=$(compare_grey "$tmp/ramp-rgb.txt" "$tmp/ramp-mono.txt" 1 mono)
check "-mono: 0/1, the RGB output's grey dithered by the 4x4 thresholds ($got)" test "$got" = ok
check "-mono --compression 1: the same pixels" cmp -s "$tmp/ramp-mono.txt" "$tmp/ramp-mono1.txt"

err=$("$bin" -q -gray -mono "$ramp" "$tmp/u" 2>&1); rc=$?
check "-gray with -mono: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1
err=$("$bin" -q -mono --bits 16 "$ramp" "$tmp/u" 2>&1); rc=$?
check "-mono with --bits 16: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1
err=$("$bin" -q --box paper "$ramp" "$tmp/u" 2>&1); rc=$?
check "--box paper: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a ! -e "$tmp/u-1.png"
err=$("$bin" -q "$ramp" "$tmp/u" --box 2>&1); rc=$?
check "--box without a value: exit 99" test "$rc" = 99
# Annotations (testdata/pdf/features/annotations.pdf, 200 x 200 pt on a 0.9
# grey page): a printable green square annotation at 20..90, a hidden red
# one (/F 2) at 110..180, a printable blue one at the top. Drawn as printed
# by default; -hide-annotations leaves them all out (the page's own red
# outline at 110..180 stays).
annots=$src/testdata/pdf/features/annotations.pdf
"$bin" -q --backend cpu -r 72 --aa 1x32 "$annots" "$tmp/an"
"$bin" -q --backend cpu -r 72 --aa 1x32 -hide-annotations "$annots" "$tmp/ah"
"$bin" -q --backend cpu -r 72 --aa 1x32 -png "$annots" "$tmp/ap"
check "annotations drawn as printed by default: green square, hidden one not drawn" \
  test "$(pixels "$tmp/an-1.png" 30,170 145,145 100,45)" = "200x200 8 2 0-153-0 230-230-230 0-0-204"
check "-hide-annotations: the page alone" \
  test "$(pixels "$tmp/ah-1.png" 30,170 145,145 100,45)" = "200x200 8 2 230-230-230 230-230-230 230-230-230"
check "-png is accepted (PNG is the format): the same bytes" cmp -s "$tmp/an-1.png" "$tmp/ap-1.png"

# Thin lines (testdata/pdf/thin-rules.pdf at 150 dpi, column x = 100 px,
# which crosses every horizontal rule: 20 strokes of 0.1, 0.25, 0.4, 0.6,
# 1 pt, four each at different offsets from the grid, and 5 filled rules
# of the same widths above them; top first: the filled ones from 1 pt
# down, then the strokes from 1 pt down). --thin-lines snap: every pixel black or
# white, 25 runs, each max(1, round(width x 150/72)) pixels long (1 for
# all but the 1 pt ones: 2); pdftoppm 22.12 draws this column the same.
# The default (exact coverage, integrated in sRGB values): each run's ink
# (the sum of 1 - grey) is its width in pixels within 0.06 (32 samples a
# pixel: each edge pixel within 1/32).
thin=$src/testdata/pdf/thin-rules.pdf
"$bin" -q --backend cpu --aa 1x32 --thin-lines snap "$thin" "$tmp/ts"
"$bin" -q --backend cpu --aa 1x32 "$thin" "$tmp/te"
"$bin" -q --backend cpu --aa 1x32 --gamma linear "$thin" "$tmp/tl"
column() { pixels "$1" $(seq -f "100,%g" 0 354); }
runs() {  # column text -> "length:ink" per run of non-white pixels, top first
  python3 - "$@" <<'PY'
import sys
vals = [int(v.split("-")[0]) for v in sys.argv[1].split()[3:]]
runs, cur = [], []
for v in vals + [255]:
    if v < 255:
        cur.append(v)
    elif cur:
        runs.append("%d:%.2f:%s" % (len(cur), sum(255 - c for c in cur) / 255, "crisp" if set(cur) == {0} else "soft"))
        cur = []
print(" ".join(runs))
PY
}
snap=$(runs "$(column "$tmp/ts-1.png")")
want="2:2.00:crisp $(printf '1:1.00:crisp %.0s' 1 2 3 4)$(printf '2:2.00:crisp %.0s' 1 2 3 4)$(printf '1:1.00:crisp %.0s' $(seq 16))"
check "--thin-lines snap: 25 crisp rules, 1 px (2 px at 1 pt) each ($snap)" test "$snap" = "${want% }"
ink() {  # runs text, expected ink per rule (top first) -> ok or the first miss
  python3 - "$@" <<'PY'
import sys
got = [float(r.split(":")[1]) for r in sys.argv[1].split()]
want = [float(w) for w in sys.argv[2].split()]
if len(got) != len(want):
    sys.exit("%d runs" % len(got))
for g, w in zip(got, want):
    if abs(g - w) > 0.06:
        print("ink %.2f for %.2f" % (g, w)); sys.exit()
print("ok")
PY
}
px() { python3 -c "import sys; print(' '.join('%.4f' % (float(w) * 150 / 72) for w in sys.argv[1:]))" "$@"; }
exact_want="$(px 1 0.6 0.4 0.25 0.1) $(px $(for w in 1 0.6 0.4 0.25 0.1; do echo $w $w $w $w; done))"
got=$(ink "$(runs "$(column "$tmp/te-1.png")")" "$exact_want")
check "--thin-lines exact (default): each rule's ink is its width in pixels ($got)" test "$got" = ok
got=$(ink "$(runs "$(column "$tmp/tl-1.png")")" "$exact_want")
check "--gamma linear loses thin rules' darkness (not the default: $got)" test "$got" != ok
"$bin" -q --thin-lines fuzzy "$thin" "$tmp/tx" 2>/dev/null; rc=$?
check "--thin-lines fuzzy: exit 99" test "$rc" = 99

# ICC colour management: a build of MuPDF without it (Debian 12's: mutool
# says "ICC support is not available") draws ICC-based colours through
# their alternates, with one warning on such a page and none on others.
err=$("$bin" --backend cpu -r 36 "$src/testdata/pdf/features/colorspace-iccbased.pdf" "$tmp/icc" 2>&1)
plain=$("$bin" --backend cpu -r 36 "$src/testdata/pdf/red-square.pdf" "$tmp/noicc" 2>&1)
check "no ICC warning on a page without ICC colours ($plain)" test -z "$(echo "$plain" | grep ICC)"
if command -v mutool > /dev/null && mutool draw -o "$tmp/mu.png" "$src/testdata/pdf/red-square.pdf" 2>&1 | grep -q "ICC support is not available"; then
  check "ICC-based colours without ICC support: one warning ($err)" test "$(echo "$err" | grep -c 'no ICC colour management')" = 1
else
  echo "skip the ICC warning check: MuPDF's ICC support unknown (no mutool) or present"
fi
out=$("$bin" --help)
check "--help lists --box, -cropbox, -hide-annotations, -gray, -mono and --thin-lines" \
  test -n "$(echo "$out" | grep -e '--box B')" -a -n "$(echo "$out" | grep -e '-cropbox')" \
  -a -n "$(echo "$out" | grep -e '-hide-annotations')" \
  -a -n "$(echo "$out" | grep -e '-gray, --gray')" -a -n "$(echo "$out" | grep -e '-mono, --mono')" -a -n "$(echo "$out" | grep -e '--thin-lines M')"

# -tiff and -jpeg (lib/output/image_writer.h: OpenImageIO's module). A TIFF is
# read here (python3's zlib: none, packbits or deflate, the horizontal
# predictor) and must hold the PNG's samples exactly; a JPEG's header its
# size, density and scan type (tests/test_image_writer.cpp reads both back
# through OpenImageIO). Where the module is missing (MPVG_IMAGE_IO=png):
# one line, exit 99, nothing rendered, and the rest is skipped.
tiff_pixels() {  # TIFF [all]: "WxH bits samples photometric" and each pixel's samples
  python3 - "$@" <<'PY'
import struct, sys, zlib
d = open(sys.argv[1], "rb").read()
e = {b"II*\0": "<", b"MM\0*": ">"}.get(d[:4])
if not e:
    sys.exit("not a TIFF")
at = struct.unpack(e + "I", d[4:8])[0]
tags = {}
for k in range(struct.unpack(e + "H", d[at:at + 2])[0]):
    tag, typ, n, v = struct.unpack(e + "HHI4s", d[at + 2 + 12 * k:at + 14 + 12 * k])
    size = {3: 2, 4: 4}.get(typ, 1)
    raw = v if n * size <= 4 else d[struct.unpack(e + "I", v)[0]:][:n * size]
    tags[tag] = [int.from_bytes(raw[i * size:(i + 1) * size], "little" if e == "<" else "big") for i in range(n)]
w, h, spp = tags[256][0], tags[257][0], tags.get(277, [1])[0]
bits, comp, pred = tags.get(258, [1])[0], tags.get(259, [1])[0], tags.get(317, [1])[0]
data = b""
for off, n in zip(tags[273], tags[279]):
    s = d[off:off + n]
    if comp in (8, 32946):
        s = zlib.decompress(s)
    elif comp == 32773:  # packbits
        out, i = bytearray(), 0
        while i < len(s):
            c = s[i] - 256 if s[i] > 127 else s[i]
            if c >= 0:
                out += s[i + 1:i + 2 + c]; i += 2 + c
            elif c > -128:
                out += s[i + 1:i + 2] * (1 - c); i += 2
            else:
                i += 1
        s = bytes(out)
    elif comp != 1:
        sys.exit("compression %d not read here" % comp)
    data += s
stride = (w * spp * bits + 7) // 8
rows = []
for y in range(h):
    r = data[y * stride:(y + 1) * stride]
    if bits == 16:
        v = list(struct.unpack(e + "%dH" % (w * spp), r))
    elif bits == 8:
        v = list(r)
    else:
        v = [(r[x >> 3] >> (7 - (x & 7))) & 1 for x in range(w)]
    if pred == 2:
        for i in range(spp, w * spp):
            v[i] = (v[i] + v[i - spp]) & (0xFFFF if bits == 16 else 0xFF)
    rows.append(v)
out = ["%dx%d %d %d %d" % (w, h, bits, spp, tags[262][0])]
if sys.argv[2:] == ["all"]:
    out += ["-".join(map(str, rows[y][x * spp:(x + 1) * spp])) for y in range(h) for x in range(w)]
print(" ".join(out))
PY
}
jpeg_header() {  # JPEG: "WxH components density-unit xdensity scan" (scan: baseline or progressive)
  python3 - "$1" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
if d[:3] != b"\xff\xd8\xff":
    sys.exit("not a JPEG")
i, unit, dens, out = 2, 0, 0, "no frame"
while i + 4 <= len(d) and d[i] == 0xFF:
    m, n = d[i + 1], struct.unpack(">H", d[i + 2:i + 4])[0]
    if m == 0xE0 and d[i + 4:i + 9] == b"JFIF\0":
        unit, dens = d[i + 11], struct.unpack(">H", d[i + 12:i + 14])[0]
    if m in (0xC0, 0xC1, 0xC2):
        hh, ww = struct.unpack(">HH", d[i + 5:i + 9])
        out = "%dx%d %d" % (ww, hh, d[i + 9])
        scan = "progressive" if m == 0xC2 else "baseline"
        break
    i += 2 + n
print(out, unit, dens, scan)
PY
}
err=$("$bin" -q --backend cpu -r 72 -tiff "$pdf" "$tmp/tif" 2>&1); rc=$?
if [ "$rc" = 99 ] && echo "$err" | grep -q 'needs OpenImageIO'; then
  check "-tiff without OpenImageIO's module: exit 99, one line, nothing written ($err)" \
    test "$(echo "$err" | wc -l)" = 1 -a ! -e "$tmp/tif-1.tif" -a ! -e "$tmp/tif-1.png"
  err=$("$bin" -q --backend cpu -r 72 -jpeg "$pdf" "$tmp/jpg" 2>&1); rc=$?
  check "-jpeg without it: exit 99 ($err)" test "$rc" = 99 -a ! -e "$tmp/jpg-1.jpg"
  echo "skip -tiff and -jpeg output: ${err#pdf2png: }"
else
  check "-tiff: PREFIX-1.tif, exit 0 ($err)" test "$rc" = 0 -a -f "$tmp/tif-1.tif" -a ! -e "$tmp/tif-1.png"
  check "-tiff: TIFF magic" test "$(head -c 4 "$tmp/tif-1.tif" | od -An -c | tr -d ' ')" = 'II*\0' -o \
    "$(head -c 4 "$tmp/tif-1.tif" | od -An -c | tr -d ' ')" = 'MM\0*'
  got=$(tiff_pixels "$tmp/tif-1.tif")
  check "-tiff: 100x100 RGB at 72 dpi, 8 bits ($got)" test "$got" = "100x100 8 3 2"
  same_samples() {  # PNG, TIFF: the same pixels, sample for sample
    test "$(pixels "$1" all | cut -d' ' -f4-)" = "$(tiff_pixels "$2" all | cut -d' ' -f5-)"
  }
  check "-tiff: the PNG's pixels exactly" same_samples "$tmp/r-1.png" "$tmp/tif-1.tif"
  for c in none packbits deflate lzw jpeg; do
    "$bin" -q --backend cpu -r 72 -tiff -tiffcompression "$c" "$pdf" "$tmp/tc-$c"; rc=$?
    check "-tiffcompression $c: written" test "$rc" = 0 -a -f "$tmp/tc-$c-1.tif"
  done
  check "-tiffcompression none and packbits: the PNG's pixels" \
    eval 'same_samples "$tmp/r-1.png" "$tmp/tc-none-1.tif" && same_samples "$tmp/r-1.png" "$tmp/tc-packbits-1.tif"'
  # Grey, 16 bits, alpha, mono from the grey ramp: each the PNG's samples.
  "$bin" -q --backend cpu -r 72 -tiff -gray "$ramp" "$tmp/rt-gray"
  "$bin" -q --backend cpu -r 72 -tiff --gray --bits 16 "$ramp" "$tmp/rt-gray16"
  "$bin" -q --backend cpu -r 72 --tiff -gray --transparent "$ramp" "$tmp/rt-grayt"
  "$bin" -q --backend cpu -r 72 -tiff --bits 16 "$ramp" "$tmp/rt-rgb16"
  "$bin" -q --backend cpu -r 72 -tiff -mono "$ramp" "$tmp/rt-mono"
  "$bin" -q --backend cpu -r 72 --bits 16 "$ramp" "$tmp/ramp-rgb16"
  check "-tiff -gray: 8-bit grey, MinIsBlack" test "$(tiff_pixels "$tmp/rt-gray-1.tif")" = "256x40 8 1 1"
  check "-tiff -gray --bits 16: 16-bit grey" test "$(tiff_pixels "$tmp/rt-gray16-1.tif")" = "256x40 16 1 1"
  check "-tiff -gray --transparent: grey and alpha" test "$(tiff_pixels "$tmp/rt-grayt-1.tif")" = "256x40 8 2 1"
  check "-tiff -mono: 1 bit" test "$(tiff_pixels "$tmp/rt-mono-1.tif")" = "256x40 1 1 1"
  for k in gray:ramp-gray gray16:ramp-gray16 grayt:ramp-grayt rgb16:ramp-rgb16 mono:ramp-mono; do
    check "-tiff ${k%%:*}: the PNG's pixels exactly" same_samples "$tmp/${k#*:}-1.png" "$tmp/rt-${k%%:*}-1.tif"
  done
  "$bin" -q --backend cpu -r 72 -tiff --singlefile "$pdf" "$tmp/tone"
  check "-tiff --singlefile writes PREFIX.tif" test -f "$tmp/tone.tif" -a ! -e "$tmp/tone.png"
  "$bin" -q --backend cpu -tiff "$src/testdata/pdf/three-pages-count-2e9.pdf" "$tmp/tn"
  check "-tiff: pages numbered as PNGs are" test "$(cd "$tmp" && echo tn-*)" = "tn-1.tif tn-2.tif tn-3.tif"

  "$bin" -q --backend cpu -jpeg "$pdf" "$tmp/jp"; rc=$?
  check "-jpeg: PREFIX-1.jpg, exit 0" test "$rc" = 0 -a -f "$tmp/jp-1.jpg" -a ! -e "$tmp/jp-1.png"
  got=$(jpeg_header "$tmp/jp-1.jpg")
  check "-jpeg: JPEG magic, 209x209 RGB, 150 dpi, baseline ($got)" test "$got" = "209x209 3 1 150 baseline"
  "$bin" -q --backend cpu -r 72 -jpeg -gray -jpegopt quality=90,progressive=y,optimize=y "$ramp" "$tmp/jg"
  got=$(jpeg_header "$tmp/jg-1.jpg")
  check "-jpeg -gray -jpegopt progressive=y: grey, progressive ($got)" test "$got" = "256x40 1 1 72 progressive"
  "$bin" -q --backend cpu -r 72 -jpeg --transparent -jpegopt optimize=y "$ramp" "$tmp/jt"; rc=$?
  got=$(jpeg_header "$tmp/jt-1.jpg")
  check "-jpeg --transparent: RGB over white (no alpha), optimize=y ($got)" \
    test "$rc" = 0 -a "$got" = "256x40 3 1 72 baseline"
  "$bin" -q --backend cpu -r 72 -jpeg -jpegopt quality=10 "$ramp" "$tmp/jq10"
  "$bin" -q --backend cpu -r 72 -jpeg -jpegopt quality=100 "$ramp" "$tmp/jq100"
  check "-jpegopt quality: 10 smaller than 100" \
    test "$(wc -c < "$tmp/jq10-1.jpg")" -lt "$(wc -c < "$tmp/jq100-1.jpg")"

  # Print preview (testdata/pdf/print-preview.pdf, whose docstring in
  # scripts/make_pdf_features.py gives each case; 72 dpi, one pixel a
  # point, image y = 100 - page y): the inks at the middle of each case,
  # as PDF 32000-1 §11.7.4 gives them (Ghostscript 10's tiff32nc with
  # -sOverprint=simulate and tiffsep give the same values).
  pp=$src/testdata/pdf/print-preview.pdf
  at() {  # TIFF X,Y ... -> the samples there
    tiff_pixels "$1" all > "$tmp/at.txt"
    python3 - "$tmp/at.txt" "${@:2}" <<'PY'
import sys
v = open(sys.argv[1]).read().split()
w = int(v[0].split("x")[0])
print(" ".join(v[4 + int(y) * w + int(x)] for x, y in (a.split(",") for a in sys.argv[2:])))
PY
  }
  cases="20,30 60,30 100,30 140,30 180,30 20,80 60,80"
  "$bin" -q --backend cpu -r 72 --aa 1x32 --colorspace cmyk "$pp" "$tmp/cmyk"
  check "--colorspace cmyk: an 8-bit CMYK TIFF (photometric separated, 4 samples)" \
    test "$(tiff_pixels "$tmp/cmyk-1.tif")" = "200x100 8 4 5"
  got=$(at "$tmp/cmyk-1.tif" $cases)
  check "--colorspace cmyk: overprint OPM 1 keeps cyan under yellow, knockout and OPM 0 do not; a spot through its alternate paints only its non-zero inks; multiply 0.75 ($got)" \
    test "$got" = "255-0-255-0 0-0-255-0 255-0-0-64 0-0-255-0 191-0-0-0 0-0-0-255 102-255-0-51"
  "$bin" -q --backend cpu -r 72 --aa 1x32 --separations "$pp" "$tmp/sep"
  check "--separations: every ink in one TIFF (5 samples)" test "$(tiff_pixels "$tmp/sep-1.tif")" = "200x100 8 5 5"
  got=$(at "$tmp/sep-1.tif" $cases)
  check "--separations: the spot Varnish an ink of its own, overprinted and kept under black ($got)" \
    test "$got" = "255-0-255-0-0 0-0-255-0-0 255-0-0-0-255 0-0-255-0-0 191-0-0-0-0 0-0-0-255-153 102-255-0-0-204"
  got=$(for n in Cyan Magenta Yellow Black Varnish; do at "$tmp/sep-1($n).tif" 60,80; done | tr '\n' ' ')
  check "--separations: a grey plate per ink, 255 - ink, as tiffsep writes them ($got)" \
    test "$got" = "153 0 255 255 51 "
  got=$(pixels "$tmp/sep-1.png" 20,30 60,30 180,30)
  check "--separations: the press sheet in RGB, cyan and yellow overprinted green ($got)" \
    test "$got" = "200x100 8 2 0-255-0 255-255-0 64-255-255"
  # mpvg-compare reads these TIFFs: inks against inks, channel by channel.
  cmp=$(dirname "$bin")/mpvg-compare
  "$cmp" -q "$tmp/cmyk-1.tif" "$tmp/cmyk-1.tif"; rc=$?
  check "mpvg-compare: a CMYK TIFF equals itself" test "$rc" = 0
  "$bin" -q --backend cpu -r 72 --colorspace cmyk "$pp" "$tmp/cmyk0"
  "$bin" -q --backend cpu -r 72 --seed 5 --colorspace cmyk "$pp" "$tmp/cmyk5"
  "$cmp" -q "$tmp/cmyk0-1.tif" "$tmp/cmyk5-1.tif"; rc=$?
  "$cmp" -q --aa "$tmp/cmyk0-1.tif" "$tmp/cmyk5-1.tif"; rc_aa=$?
  check "mpvg-compare: another seed's CMYK differs, forgiven as antialiasing with --aa ($rc, $rc_aa)" \
    test "$rc" = 1 -a "$rc_aa" = 0
  out=$("$cmp" "$tmp/cmyk-1.tif" "$tmp/sep-1.tif"); rc=$?
  check "mpvg-compare: CMYK against five inks fails, says why" test "$rc" = 1 -a -n "$(grep -F 'differ in their channels' <<<"$out")"
  "$bin" -q --backend cpu -r 72 --aa 1x32 "$pp" "$tmp/pprgb"
  "$bin" -q --backend cpu -r 72 --aa 1x32 -tiff "$pp" "$tmp/pprgb"
  "$cmp" -q "$tmp/pprgb-1.png" "$tmp/pprgb-1.tif"; rc=$?
  check "mpvg-compare: an RGB TIFF equals the PNG of the same render" test "$rc" = 0
  "$bin" -q --backend cpu -r 36 --aa 1x32 -tiff "$pp" "$tmp/ppsmall"
  json=$("$cmp" --json "$tmp/pprgb-1.tif" "$tmp/ppsmall-1.tif"); rc=$?
  check "mpvg-compare --json, sizes differ: both sizes ($json)" \
    test "$rc" = 1 -a -n "$(grep -F '"a":{"width":200,"height":100,"channels":4},"b":{"width":100,"height":50,"channels":4}' <<<"$json")"
  # Colour management (parsers/pdf/output_intent.h; testdata/pdf/rgb-inks*.pdf):
  # RGB black, red, grey black, CMYK black, then an RGB image of black and
  # red. Without a press profile, PDF's device formulas (RGB black as K
  # alone, one warning); with the output intent (testdata/icc/cmy-press.icc,
  # a press of C, M, Y alone) or --cmyk-profile naming it, RGB colours and
  # images go through the profile (black as C, M, Y), grey and CMYK stay K.
  ri=$src/testdata/pdf/rgb-inks.pdf
  err=$("$bin" --backend cpu -r 72 --aa 1x32 --colorspace cmyk "$ri" "$tmp/ri" 2>&1)
  got=$(at "$tmp/ri-1.tif" 5,10 15,10 25,10 35,10 45,10 55,10)
  check "no press profile: PDF's formulas, RGB black as K ($got)" \
    test "$got" = "0-0-0-255 0-255-255-0 0-0-0-255 0-0-0-255 0-0-0-255 0-255-255-0"
  check "no press profile: one warning ($err)" test "$(echo "$err" | grep -c 'no CMYK output profile')" = 1
  profiled() {  # TIFF: ok if RGB colours went through cmy-press.icc (C, M, Y up, no K) and grey, CMYK did not
    python3 - "$(at "$1" 5,10 15,10 25,10 35,10 45,10 55,10)" <<'PY'
import sys
p = [list(map(int, v.split("-"))) for v in sys.argv[1].split()]
rich = all(c >= 240 for c in p[0][:3]) and p[0][3] == 0 and p[4] == p[0]
red = p[1][0] < 30 and p[1][1] > 200 and p[1][2] > 200 and p[1][3] == 0 and p[5] == p[1]
print("ok" if rich and red and p[2] == p[3] == [0, 0, 0, 255] else " ".join(sys.argv[1:]))
PY
  }
  err=$("$bin" --backend cpu -r 72 --aa 1x32 --colorspace cmyk "$src/testdata/pdf/rgb-inks-intent.pdf" "$tmp/rii" 2>&1)
  got=$(profiled "$tmp/rii-1.tif")
  check "the output intent's profile converts RGB colours and images ($got)" test "$got" = ok
  check "the output intent: no warning about a missing profile ($err)" test -z "$(echo "$err" | grep 'no CMYK output')"
  "$bin" -q --backend cpu -r 72 --aa 1x32 --colorspace cmyk --cmyk-profile "$src/testdata/icc/cmy-press.icc" "$ri" "$tmp/rip"
  got=$(profiled "$tmp/rip-1.tif")
  check "--cmyk-profile converts RGB colours and images through it ($got)" test "$got" = ok
  for bad in "--cmyk-profile $src/testdata/pdf/rgb-inks.pdf --colorspace cmyk" "--cmyk-profile $ri"; do
    err=$("$bin" -q --backend cpu $bad "$ri" "$tmp/cb" 2>&1); rc=$?
    check "$bad: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1
  done
  for bad in "--colorspace cmyk -jpeg" "--separations -gray" "--colorspace cmyk --bits 16" \
    "--colorspace cmyk --gamma linear" "--separations --transparent" "--colorspace lab"; do
    err=$("$bin" -q --backend cpu $bad "$pp" "$tmp/ib" 2>&1); rc=$?
    check "$bad: exit 99, one line ($err)" test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a -z "$(ls "$tmp" | grep '^ib')"
  done
fi
for bad in "-jpeg --bits 16" "-jpeg -mono" "-tiff -jpeg" "-tiffcompression zstd" "-jpegopt quality=0" \
  "-jpegopt progressive=maybe" "-jpegopt speed=1"; do
  err=$("$bin" -q --backend cpu $bad "$ramp" "$tmp/ub" 2>&1); rc=$?
  check "$bad: exit 99, one line, nothing written ($err)" \
    test "$rc" = 99 -a "$(echo "$err" | wc -l)" = 1 -a -z "$(ls "$tmp" | grep '^ub')"
done
out=$("$bin" --help)
check "--help lists -jpeg, -jpegopt, -tiff and -tiffcompression" \
  test -n "$(echo "$out" | grep -e ' -jpeg ')" -a -n "$(echo "$out" | grep -e '-jpegopt')" \
  -a -n "$(echo "$out" | grep -e ' -tiff ')" -a -n "$(echo "$out" | grep -e '-tiffcompression')"

echo "$fails failure(s)"
test "$fails" = 0
