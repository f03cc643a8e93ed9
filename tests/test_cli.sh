#!/usr/bin/env bash
# Command-line behaviour of svg2png: outputs, sizes, stdin/stdout, and one
# clear error line with a non-zero exit for bad input.
# usage: test_cli.sh SVG2PNG SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
differ() { ! cmp -s "$1" "$2"; }
svg=$src/testdata/golden/arcs.svg   # 128 x 96

"$bin" -q "$svg" "$tmp/a.png"; rc=$?
check "renders at the intrinsic size" test "$rc" = 0 -a "$(png_size "$tmp/a.png")" = 128x96
"$bin" -q -w 64 "$svg" "$tmp/b.png"
check "-w keeps the aspect ratio" test "$(png_size "$tmp/b.png")" = 64x48
"$bin" -q -h 192 "$svg" "$tmp/c.png"
check "-h keeps the aspect ratio" test "$(png_size "$tmp/c.png")" = 256x192
"$bin" -q -w 100 -h 100 "$svg" "$tmp/d.png"
check "-w and -h stretch" test "$(png_size "$tmp/d.png")" = 100x100
"$bin" -q -w 100 -h 100 -a "$svg" "$tmp/e.png"
check "-a fits inside" test "$(png_size "$tmp/e.png")" = 100x75
"$bin" -q -z 0.5 "$svg" "$tmp/f.png"
check "-z scales" test "$(png_size "$tmp/f.png")" = 64x48
"$bin" -q - - < "$svg" > "$tmp/g.png"
check "stdin to stdout gives the same bytes as files" cmp -s "$tmp/a.png" "$tmp/g.png"
if command -v script > /dev/null; then
  # stdout a terminal (util-linux script runs the command on a pseudo-terminal).
  tty_out=$(script -qec "'$bin' -q '$svg' -" /dev/null < /dev/null); rc=$?
  check "a PNG is not written to a terminal: exit 2, one line" \
    test "$rc" = 2 -a -n "$(echo "$tty_out" | grep -e 'standard output is a terminal')" -a "$(echo "$tty_out" | wc -l)" = 1
fi
"$bin" -q -o "$tmp/h.png" "$svg"
check "-o names the output" cmp -s "$tmp/a.png" "$tmp/h.png"
"$bin" -q -o "$tmp/newdir" "$svg"; rc=$?
check "-o FOLDER with one input, the folder missing: made, FOLDER/arcs.png" test "$rc" = 0 -a -d "$tmp/newdir" && cmp -s "$tmp/a.png" "$tmp/newdir/arcs.png"
mkdir -p "$tmp/there"
"$bin" -q -o "$tmp/there" "$svg"; rc=$?
check "-o FOLDER with one input, the folder there: FOLDER/arcs.png" test "$rc" = 0 && cmp -s "$tmp/a.png" "$tmp/there/arcs.png"
"$bin" -q --seed 7 "$svg" "$tmp/i.png"
check "--seed changes the sample pattern" differ "$tmp/a.png" "$tmp/i.png"
# The box filter's images are the same bit for bit on every backend (wide
# filters agree within 1/255: test_gpu).
# --compression 1 is the same deflate on either executor: the same bytes.
"$bin" -q --aa 1x32 --compression 1 "$svg" "$tmp/j1.png"
"$bin" -q --aa 1x32 --compression 1 --backend cpu "$svg" "$tmp/j2.png"
check "--backend cpu renders the same 1x32 image" cmp -s "$tmp/j1.png" "$tmp/j2.png"
# Every level holds the same filtered rows (inflated by Python's zlib).
rows() { pixels "$1" raw; }
for l in 0 1 2 9; do "$bin" -q --compression $l "$svg" "$tmp/z$l.png"; done
check "--compression 0, 1, 2 and 9 hold the same rows" test "$(rows "$tmp/z0.png")" = "$(rows "$tmp/z1.png")" \
  -a "$(rows "$tmp/z1.png")" = "$(rows "$tmp/z2.png")" -a "$(rows "$tmp/z2.png")" = "$(rows "$tmp/z9.png")"
check "--compression 0 stores, 1 and 9 deflate" test "$(stat -c %s "$tmp/z0.png")" -gt "$(stat -c %s "$tmp/z1.png")" \
  -a "$(stat -c %s "$tmp/z1.png")" -gt "$(stat -c %s "$tmp/z9.png")"
"$bin" -q --compression 10 "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "--compression 10: exit 2" test "$rc" = 2
"$bin" -q --bits 16 "$svg" "$tmp/k.png"
check "--bits 16 writes a 16-bit PNG" test "$(od -An -tu1 -j24 -N1 "$tmp/k.png" | tr -d ' ')" = 16

err=$("$bin" "$tmp/missing.svg" "$tmp/x.png" 2>&1); rc=$?
check "missing input: exit 1, one line" test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 1
check "missing input: says what" grep -q "cannot read" <<<"$err"
printf '<svg xmlns="http://www.w3.org/2000/svg"><rect width="10" height="10"</svg>' > "$tmp/bad.svg"
err=$("$bin" "$tmp/bad.svg" "$tmp/x.png" 2>&1); rc=$?
check "malformed XML: exit 1, one line" test "$rc" = 1 -a "$(echo "$err" | wc -l)" = 1
check "malformed XML: says where" grep -q "XML parse error at line" <<<"$err"
check "malformed XML: no output file" test ! -e "$tmp/x.png"
printf '<html/>' > "$tmp/html.svg"
"$bin" "$tmp/html.svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "not SVG: exit 1" test "$rc" = 1
err=$("$bin" --frobnicate "$svg" "$tmp/x.png" 2>&1); rc=$?
check "unknown option: exit 2 with a message" test "$rc" = 2 -a -n "$err"
"$bin" -w -3 "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "negative width: exit 2" test "$rc" = 2
"$bin" --aa 9x9 "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "unknown --aa mode: exit 2" test "$rc" = 2
"$bin" "$svg" 2>/dev/null; rc=$?
check "missing output argument: exit 2" test "$rc" = 2
"$bin" -q "$svg" "$tmp/no/such/dir/x.png" 2>/dev/null; rc=$?
check "unwritable output: exit 1" test "$rc" = 1
"$bin" --help > "$tmp/help.txt"; rc=$?
check "--help: exit 0 with usage" test "$rc" = 0 -a -s "$tmp/help.txt"

# shape-rendering: crispEdges: aliased under the box filter and under the
# default (cardinal) one, which then integrates over 5 x 5 unit areas.
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><rect x="1.5" y="1.5" width="4" height="4" shape-rendering="crispEdges"/></svg>' > "$tmp/crisp.svg"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><rect x="1.5" y="1.5" width="4" height="4"/></svg>' > "$tmp/smooth.svg"
for aa in 1x32 4x4x32; do
  err=$("$bin" --aa $aa "$tmp/crisp.svg" "$tmp/crisp-$aa.png" 2>&1); rc=$?
  check "crispEdges under $aa: exit 0, no warning" test "$rc" = 0 -a -z "$err"
  "$bin" -q --aa $aa "$tmp/smooth.svg" "$tmp/smooth-$aa.png"
  check "crispEdges under $aa: differs from the antialiased square" differ "$tmp/crisp-$aa.png" "$tmp/smooth-$aa.png"
done

# Images: the document's folder tree is readable, other folders only with
# --allow-read; standard input reads relative to the current directory.
mkdir -p "$tmp/doc" "$tmp/pics"
cp "$src/testdata/images/rgba8.png" "$tmp/pics/"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image width="8" height="8" href="../pics/rgba8.png"/></svg>' > "$tmp/doc/img.svg"
err=$("$bin" "$tmp/doc/img.svg" "$tmp/img1.png" 2>&1); rc=$?
check "image outside the document's folder: a warning, still exit 0" test "$rc" = 0
check "image outside the document's folder: says why" grep -q "outside the folders the document may read" <<<"$err"
err=$("$bin" --allow-read "$tmp/pics" "$tmp/doc/img.svg" "$tmp/img2.png" 2>&1); rc=$?
check "--allow-read opens the folder" test "$rc" = 0 -a -z "$(grep -v note: <<<"$err")"
check "--allow-read: the image is drawn" differ "$tmp/img1.png" "$tmp/img2.png"
(cd "$tmp/doc" && "$bin" -q - "$tmp/img3.png" < "$tmp/doc/img.svg")
check "stdin: only the current directory's tree is read" cmp -s "$tmp/img1.png" "$tmp/img3.png"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image width="8" height="8" href="rgba8.png"/></svg>' > "$tmp/here.svg"
(cd "$tmp/pics" && "$bin" -q - "$tmp/img4.png" < "$tmp/here.svg")
check "stdin: images in the current directory are read" cmp -s "$tmp/img2.png" "$tmp/img4.png"
"$bin" --help | grep -q -- "--allow-read DIR"
check "--help documents --allow-read" test $? = 0

# Start-up: PNGs are written without OpenImageIO, which is opened (as a
# module) only for the JPEG, GIF and WebP images a document holds.
! ldd "$bin" | grep -qi openimageio
check "svg2png does not link OpenImageIO" test $? = 0
cp "$src/testdata/images/rgb.jpg" "$tmp/doc/"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image width="8" height="8" href="rgb.jpg"/></svg>' > "$tmp/doc/jpg.svg"
err=$("$bin" --aa 1x32 "$tmp/doc/jpg.svg" "$tmp/jpg.png" 2>&1); rc=$?
if grep -q "OpenImageIO" <<<"$err"; then
  echo "skip JPEG through the OpenImageIO module: $err"
else
  check "a JPEG image is decoded (module loaded on demand)" test "$rc" = 0 -a -z "$err"
  printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"/>' > "$tmp/empty.svg"
  "$bin" -q --aa 1x32 "$tmp/empty.svg" "$tmp/empty.png"
  check "a JPEG image is drawn" differ "$tmp/jpg.png" "$tmp/empty.png"
fi

# --backend auto says in --stats which backend it chose and why; an
# explicit CUDA request without a device is an error.
err=$("$bin" --stats "$svg" "$tmp/s.png" 2>&1); rc=$?
check "--stats: auto names its choice" grep -Eq "^auto chose (the CPU|CUDA): " <<<"$err"
check "--stats: a wall time" grep -q "^wall " <<<"$err"
if ! command -v nvidia-smi > /dev/null; then
  err=$("$bin" --backend cuda "$svg" "$tmp/cuda.png" 2>&1); rc=$?
  check "--backend cuda without a device: exit 1, says why" test "$rc" = 1 -a -n "$(grep "CUDA backend unavailable" <<<"$err")"
  check "--backend cuda without a device: no output" test ! -e "$tmp/cuda.png"
fi

# Batches: every good file written though one is broken, the exit status
# says one failed; outputs byte for byte those of single runs (with auto,
# a small single file may render on the CPU while a batch takes the GPU:
# the box filter's bytes are the same on both, wide filters' within
# 1/255, so the comparison uses 1x32); --shard
# parts are disjoint and cover the batch; --batch reads "IN OUT" lines.
mkdir -p "$tmp/batch"
for f in arcs gradient_repeat; do cp "$src/testdata/golden/$f.svg" "$tmp/batch/"; done
printf '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect' > "$tmp/batch/broken.svg"
cp "$src/testdata/golden/arcs.svg" "$tmp/batch/zz.svg"
err=$("$bin" -q -o "$tmp/bout" "$tmp"/batch/*.svg 2>&1); rc=$?
check "batch with a broken file: exit 1" test "$rc" = 1
check "batch with a broken file: names it" grep -q "broken.svg: XML parse error" <<<"$err"
check "batch with a broken file: the others written" test -s "$tmp/bout/arcs.png" -a -s "$tmp/bout/gradient_repeat.png" -a -s "$tmp/bout/zz.png" -a ! -e "$tmp/bout/broken.png"
"$bin" -q --aa 1x32 "$tmp/batch/gradient_repeat.svg" "$tmp/single.png"
"$bin" -q --aa 1x32 -o "$tmp/bout32" "$tmp/batch/gradient_repeat.svg" "$tmp/batch/arcs.svg"
check "batch output is the single run's, byte for byte" cmp -s "$tmp/single.png" "$tmp/bout32/gradient_repeat.png"
# Forest frames (frame/forest.h): one render thread, files rendered together
# as they queue up; the same bytes as one frame each.
mkdir -p "$tmp/forest"
for f in arcs gradient_repeat nested_clips opacity pattern_nested stroke_dashes image_svg; do
  [ -f "$src/testdata/golden/$f.svg" ] && cp "$src/testdata/golden/$f.svg" "$tmp/forest/"
done
"$bin" -q --aa 1x32 --render-threads 1 --threads 4 --frame-scenes 8 -o "$tmp/fout8" "$tmp"/forest/*.svg; rc8=$?
"$bin" -q --aa 1x32 --render-threads 1 --frame-scenes 1 -o "$tmp/fout1" "$tmp"/forest/*.svg; rc1=$?
same_forest() { for f in "$tmp"/fout1/*.png; do cmp -s "$f" "$tmp/fout8/$(basename "$f")" || return 1; done; }
check "--frame-scenes 8: the same bytes as a frame per file" test "$rc8" = 0 -a "$rc1" = 0 -a -n "$(ls "$tmp/fout1")" -a \
  "$(ls "$tmp/fout1" | wc -l)" = "$(ls "$tmp/forest" | wc -l)"
check "--frame-scenes 8: each file as alone" same_forest
for i in 0 1 2; do "$bin" -q -o "$tmp/shard$i" --shard $i/3 "$tmp"/batch/*.svg 2>/dev/null; done
all=$(ls "$tmp/shard0" "$tmp/shard1" "$tmp/shard2" 2>/dev/null | grep png | sort | tr '\n' ' ')
check "--shard: the parts cover the batch, each file once" test "$all" = "arcs.png gradient_repeat.png zz.png "
check "--shard 0/3 takes inputs 0 and 3" test "$(ls "$tmp/shard0" | tr '\n' ' ')" = "arcs.png zz.png "
printf '%s\t%s\n# a comment\n\n%s %s\n' "$tmp/batch/arcs.svg" "$tmp/l1.png" "$tmp/batch/zz.svg" "$tmp/l2.png" > "$tmp/list.txt"
"$bin" -q --batch "$tmp/list.txt"; rc=$?
check "--batch LIST: exit 0, both written as single runs write them" test "$rc" = 0 -a -s "$tmp/l1.png"
check "--batch LIST: same bytes" cmp -s "$tmp/l1.png" "$tmp/bout/arcs.png"
"$bin" -q --batch - < "$tmp/list.txt"; rc=$?
check "--batch -: the list from standard input" test "$rc" = 0
mkdir -p "$tmp/other"; cp "$tmp/batch/arcs.svg" "$tmp/other/"
err=$("$bin" -q -o "$tmp/dup" "$tmp/batch/arcs.svg" "$tmp/other/arcs.svg" 2>&1); rc=$?
check "batch: two inputs to one output is an error, nothing written" test "$rc" = 1 -a ! -e "$tmp/dup/arcs.png"
"$bin" -q --shard 3/3 -o "$tmp/x" "$tmp/batch/arcs.svg" 2>/dev/null; rc=$?
check "--shard out of range: exit 2" test "$rc" = 2

printf '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><switch><rect width="10" height="10" fill="red" systemLanguage="de"/><rect width="10" height="10" fill="lime"/></switch></svg>' > "$tmp/lang.svg"
"$bin" -q --aa 1x8 "$tmp/lang.svg" "$tmp/lang-en.png"
"$bin" -q --aa 1x8 --languages de-CH,en "$tmp/lang.svg" "$tmp/lang-de.png"
check "--languages changes what switch picks" differ "$tmp/lang-en.png" "$tmp/lang-de.png"
"$bin" -q --languages "" "$tmp/lang.svg" "$tmp/lang-x.png" 2>/dev/null; rc=$?
check "--languages without tags: exit 2" test "$rc" = 2
printf '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect width="5" height="5"/></svg>' | gzip -c > "$tmp/z.svgz"
"$bin" -q "$tmp/z.svgz" "$tmp/z.png"; rc=$?
check ".svgz input renders" test "$rc" = 0 -a -s "$tmp/z.png"

# Filter effects: one file and a batch give the same bytes; a filter too
# costly to run warns and the rest of the file still renders.
f="$src/testdata/golden/filters.svg"
"$bin" -q --backend cpu --aa 1x32 "$f" "$tmp/filters-one.png"; rc=$?
mkdir -p "$tmp/fb"; "$bin" -q --backend cpu --aa 1x32 -o "$tmp/fb" "$f" "$src/testdata/golden/arcs.svg"; rc2=$?
check "filters: one file and a batch give the same bytes" test "$rc" = 0 -a "$rc2" = 0 && cmp -s "$tmp/filters-one.png" "$tmp/fb/filters.png"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="2000" height="2000"><filter id="f" filterUnits="userSpaceOnUse" x="0" y="0" width="2000" height="2000"><feMorphology radius="3000"/><feMorphology radius="3000"/><feMorphology radius="3000"/></filter><rect width="2000" height="2000" fill="red" filter="url(#f)"/><rect width="10" height="10" fill="lime"/></svg>' > "$tmp/costly.svg"
err=$("$bin" --backend cpu --aa 1x8 "$tmp/costly.svg" "$tmp/costly.png" 2>&1); rc=$?
check "a filter too costly to run: a warning, exit 0" test "$rc" = 0 -a -s "$tmp/costly.png" && grep -q "too costly" <<<"$err"

# --dpi (rsvg-convert -d, resvg --dpi): a document sized in physical units
# comes out at that resolution, which the PNG records; px stay px.
printf '<svg xmlns="http://www.w3.org/2000/svg" width="2in" height="25.4mm"><rect width="100%%" height="100%%" fill="red"/></svg>' > "$tmp/inch.svg"
"$bin" -q --backend cpu --dpi 300 "$tmp/inch.svg" "$tmp/dpi.png"; rc=$?
check "--dpi 300: 2in x 25.4mm is 600x300" test "$rc" = 0 -a "$(png_size "$tmp/dpi.png")" = 600x300
check "--dpi 300: pHYs 11811 per metre ($(phys "$tmp/dpi.png"))" test "$(phys "$tmp/dpi.png")" = "11811 11811 1"
"$bin" -q --backend cpu "$tmp/inch.svg" "$tmp/dpi96.png"
check "without --dpi: 96 per inch, no pHYs" test "$(png_size "$tmp/dpi96.png")" = 192x96 -a "$(phys "$tmp/dpi96.png")" = none
"$bin" -q --backend cpu -d 48 "$svg" "$tmp/dpi48.png"
check "-d leaves px documents' size" test "$(png_size "$tmp/dpi48.png")" = 128x96
err=$("$bin" --dpi 5 "$svg" "$tmp/x.png" 2>&1); rc=$?
check "--dpi out of range: exit 2" test "$rc" = 2 -a -n "$(grep -F 'takes 10 to 4000' <<<"$err")"

# --query: the drawn elements' ids and boxes as JSON; --export-id: one of
# them alone, the output its box.
cat > "$tmp/ids.svg" <<'EOF'
<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect id="back" width="100" height="80" fill="#ddd"/>
  <g id="pair" opacity="0.5">
    <rect id="a" x="20" y="30" width="40" height="20" fill="blue"/>
    <circle id="b" cx="70" cy="20" r="10" fill="red" stroke="black" stroke-width="2"/>
  </g>
  <defs><rect id="unused" width="5" height="5"/></defs>
</svg>
EOF
out=$("$bin" --query "$tmp/ids.svg"); rc=$?
check "--query: exit 0" test "$rc" = 0
listed=$(python3 -c "
import json, sys
d = json.loads(sys.argv[1])
print('%g %g' % (d['width'], d['height']), ';'.join('%s %g %g %g %g' % (e['id'], e['x'], e['y'], e['width'], e['height']) for e in d['elements']))
" "$out")
check "--query: ids, boxes, document order; nothing undrawn ($listed)" \
  test "$listed" = "100 80 back 0 0 100 80;pair 20 9 61 41;a 20 30 40 20;b 59 9 22 22"
"$bin" --query "$tmp/ids.svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "--query with an output: exit 2" test "$rc" = 2
"$bin" -q --backend cpu --aa 1x32 -i a "$tmp/ids.svg" "$tmp/a.png"; rc=$?
check "--export-id: exit 0, the element's box" test "$rc" = 0 -a "$(png_size "$tmp/a.png")" = 40x20
"$bin" -q --backend cpu --aa 1x32 -w 80 --export-id a "$tmp/ids.svg" "$tmp/a80.png"
check "--export-id with -w: the element's box scaled" test "$(png_size "$tmp/a80.png")" = 80x40
check "--export-id: the element alone, without its group's opacity" \
  test "$(pixels "$tmp/a.png" 0,0 39,19)" = "40x20 8 2 0-0-255 0-0-255"
err=$("$bin" -q -i unused "$tmp/ids.svg" "$tmp/x.png" 2>&1); rc=$?
check "--export-id of an element not drawn: exit 1, says so" test "$rc" = 1 -a -n "$(grep -F "draws nothing" <<<"$err")" -a ! -e "$tmp/x.png"
err=$("$bin" -q -i nope "$tmp/ids.svg" "$tmp/x.png" 2>&1); rc=$?
check "--export-id of a missing id: exit 1, names the file" test "$rc" = 1 -a "$err" = "svg2png: $tmp/ids.svg: no element has the id 'nope' (--export-id)"

# --timeout for one file: exit 1, one line, nothing written.
{
  echo '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
  for i in $(seq 0 299); do
    echo "<path d=\"M $((i % 97)) 0 C 30 $((i % 53)) 70 $((100 - i % 41)) 100 $((i % 89))\" fill=\"none\" stroke=\"#123456\" stroke-width=\"$((1 + i % 5))\" stroke-dasharray=\"3 1\"/>"
  done
  echo '</svg>'
} > "$tmp/slow.svg"
err=$("$bin" --backend cpu --timeout 0.05 -w 6000 "$tmp/slow.svg" "$tmp/slow.png" 2>&1); rc=$?
check "--timeout, one file: exit 1, one line, no output" \
  test "$rc" = 1 -a "$err" = "svg2png: $tmp/slow.svg: timed out after 0.05 s (--timeout)" -a ! -e "$tmp/slow.png"
"$bin" -q --backend cpu --timeout 60 "$svg" "$tmp/fast.png"; rc=$?
check "--timeout, one file in time: written" test "$rc" = 0 -a -s "$tmp/fast.png"

# --report: a batch's JSON lines.
mkdir -p "$tmp/rep"
printf '<svg xmlns="http://www.w3.org/2000/svg"><rect</svg>' > "$tmp/rep/broken.svg"
cp "$svg" "$tmp/rep/good.svg"
"$bin" -q --backend cpu --report "$tmp/report.jsonl" -o "$tmp/repout" "$tmp/rep/good.svg" "$tmp/rep/broken.svg"; rc=$?
rows=$(python3 -c "
import json, sys
rows = sorted((json.loads(l) for l in open(sys.argv[1])), key=lambda r: r['input'])
print(';'.join('%s %s %s %s' % (r['input'].rsplit('/', 1)[1], r['status'], r['output'].rsplit('/', 1)[1], bool(r.get('error'))) for r in rows))
" "$tmp/report.jsonl")
check "--report: one line a file, status and output ($rows)" test "$rc" = 1 -a "$rows" = "broken.svg failed broken.png True;good.svg ok good.png False"
"$bin" --report "$tmp/r.jsonl" "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "--report for one file: exit 2" test "$rc" = 2

# Error messages: the file, line and column of an XML error in words; a
# PDF given by mistake.
printf '<svg xmlns="http://www.w3.org/2000/svg">\n  <rect x=1 width="3"/>\n</svg>\n' > "$tmp/unquoted.svg"
err=$("$bin" "$tmp/unquoted.svg" "$tmp/x.png" 2>&1); rc=$?
check "XML error: file, line, column, a sentence" \
  test "$rc" = 1 -a "$err" = "svg2png: $tmp/unquoted.svg: XML parse error at line 2, column 11: the value of the attribute 'x' of <rect> must be in quotes"
printf '%%PDF-1.4\n%%\xe2\xe3\xcf\xd3\n1 0 obj\n' > "$tmp/doc.svg"
err=$("$bin" "$tmp/doc.svg" "$tmp/x.png" 2>&1); rc=$?
check "a PDF given to svg2png: use pdf2png" test "$rc" = 1 -a "$err" = "svg2png: $tmp/doc.svg: the input is a PDF document, not SVG: render it with pdf2png"

out=$("$(dirname "$bin")/mpvg-compare" --version); rc=$?
check "mpvg-compare --version ($out)" test "$rc" = 0 -a -n "$(grep -E '^mpvg-compare \(mpvg\) [0-9.]+$' <<<"$out")"

echo "$fails failed"
test "$fails" = 0
