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

# -gray and -mono (apps/png_writer.h): colour type and depth from the
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
check "-gray with -mono: exit 2, one line ($err)" test "$rc" = 2 -a "$(echo "$err" | wc -l)" = 1
err=$("$bin" -q -mono --bits 16 "$ramp" "$tmp/u" 2>&1); rc=$?
check "-mono with --bits 16: exit 2, one line ($err)" test "$rc" = 2 -a "$(echo "$err" | wc -l)" = 1
err=$("$bin" -q --box paper "$ramp" "$tmp/u" 2>&1); rc=$?
check "--box paper: exit 2, one line ($err)" test "$rc" = 2 -a "$(echo "$err" | wc -l)" = 1 -a ! -e "$tmp/u-1.png"
err=$("$bin" -q "$ramp" "$tmp/u" --box 2>&1); rc=$?
check "--box without a value: exit 2" test "$rc" = 2
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
check "--thin-lines fuzzy: exit 2" test "$rc" = 2

out=$("$bin" --help)
check "--help lists --box, -cropbox, -hide-annotations, -gray, -mono and --thin-lines" \
  test -n "$(echo "$out" | grep -e '--box B')" -a -n "$(echo "$out" | grep -e '-cropbox')" \
  -a -n "$(echo "$out" | grep -e '-hide-annotations')" \
  -a -n "$(echo "$out" | grep -e '-gray, --gray')" -a -n "$(echo "$out" | grep -e '-mono, --mono')" -a -n "$(echo "$out" | grep -e '--thin-lines M')"

echo "$fails failure(s)"
test "$fails" = 0
