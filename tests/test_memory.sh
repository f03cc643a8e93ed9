#!/usr/bin/env bash
# Memory without surprises (core/memory_budget.h): oversized inputs render
# in bounded memory, measured as the process's peak RSS by GNU time; what
# cannot fit ends with one line, never std::bad_alloc. The inputs are
# written by make_hostile_inputs.py (small files that decode huge).
# usage: test_memory.sh SVG2PNG PDF2PNG SOURCE_DIR   (PDF2PNG "" without MuPDF)
set -u
svg2png=$1
pdf2png=$2
src=$3
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
if [ ! -x /usr/bin/time ] || ! command -v python3 >/dev/null; then
  echo "skip: GNU time (/usr/bin/time) and python3 are needed (scripts/setup-debian.sh installs them)"
  echo "0 failed"
  exit 0
fi
python3 "$src/tests/make_hostile_inputs.py" "$tmp" gif-claim.svg png-16000.svg strokes-1e5.svg page-14400.pdf \
  image-20000.pdf mesh-200k.pdf
# peak KB, exit status and stderr of a command: "KB RC", stderr in $tmp/err
measure() {
  /usr/bin/time -f "%M" -o "$tmp/rss" "$@" 2> "$tmp/err"
  local rc=$?
  echo "$(tail -n 1 "$tmp/rss") $rc"
}
under_mb() {  # peak KB, limit MB
  test "$1" -lt $(($2 * 1024))
}

read -r kb rc <<<"$(measure "$svg2png" --backend cpu -w 100 "$tmp/png-16000.svg" "$tmp/png.png")"
echo "png-16000.svg at -w 100: peak $((kb / 1024)) MB"
check "a 16000 x 16000 PNG drawn 100 pixels wide: rendered" test "$rc" = 0 -a -s "$tmp/png.png"
check "... in under 200 MB ($((kb / 1024)) MB; it was 8.2 GB)" under_mb "$kb" 200

read -r kb rc <<<"$(measure "$svg2png" --backend cpu -w 100 "$tmp/gif-claim.svg" "$tmp/gif.png")"
echo "gif-claim.svg: peak $((kb / 1024)) MB"
# (Builds without OpenImageIO decode no GIF at all: refused as well.)
check "a 100-byte GIF claiming 16000 x 16000: refused with a warning, the rest rendered" \
  test "$rc" = 0 -a -s "$tmp/gif.png" -a -n "$(grep -E "over the limit|need OpenImageIO" "$tmp/err")"
check "... in under 300 MB ($((kb / 1024)) MB; it was 1.1 GB)" under_mb "$kb" 300

read -r kb rc <<<"$(measure "$svg2png" --backend cpu -w 1000 "$tmp/strokes-1e5.svg" "$tmp/strokes.png")"
echo "strokes-1e5.svg at 1000 px: peak $((kb / 1024)) MB"
check "100,000 stroked segments at 1000 px: rendered in under 1 GB ($((kb / 1024)) MB)" \
  test "$rc" = 0 -a -s "$tmp/strokes.png" -a "$kb" -lt 1048576

# The budget: an image that would need more texels than its share is not
# drawn (the 16000 x 16000 PNG magnified 100 times: every texel shows).
sed 's/<image width="1000" height="1000"/<image width="100000" height="100000"/' "$tmp/png-16000.svg" > "$tmp/zoomed.svg"
read -r kb rc <<<"$(measure "$svg2png" --backend cpu --max-memory 1G -w 1000 "$tmp/zoomed.svg" "$tmp/zoomed.png")"
check "--max-memory 1G: a magnified 16000 x 16000 image is refused with a warning, exit 0 ($((kb / 1024)) MB)" \
  test "$rc" = 0 -a -n "$(grep -F "<image> not rendered" "$tmp/err")" -a "$kb" -lt 262144

# What cannot fit: one line, exit 1.
read -r kb rc <<<"$(measure "$svg2png" --backend cpu --max-memory 4G -w 32768 "$src/testdata/example.svg" "$tmp/huge.png")"
check "a 32768-pixel output over the budget: one line naming both ($(cat "$tmp/err"))" \
  test "$rc" = 1 -a "$(wc -l < "$tmp/err")" = 1 -a -n "$(grep -E "needs .* GiB, the budget is 2 GiB" "$tmp/err")" \
  -a ! -e "$tmp/huge.png"
read -r kb rc <<<"$(measure "$svg2png" --backend cpu /dev/zero "$tmp/zero.png")"
check "/dev/zero as input: refused at the input limit, one line ($(cat "$tmp/err"))" \
  test "$rc" = 1 -a "$(cat "$tmp/err")" = "svg2png: '/dev/zero' is larger than the input limit of 1 GiB (--max-input)"
read -r kb rc <<<"$(measure "$svg2png" --backend cpu --max-input 1M /dev/zero "$tmp/zero.png")"
refused_under() { test "$1" = 1 && under_mb "$2" "$3"; }
check "--max-input 1M: /dev/zero refused in under 100 MB ($((kb / 1024)) MB)" refused_under "$rc" "$kb" 100
err=$("$svg2png" --max-memory 12x "$src/testdata/example.svg" "$tmp/x.png" 2>&1); rc=$?
check "a bad --max-memory is a usage error" test "$rc" = 2 -a -n "$(grep -F "expects a size" <<<"$err")"

if [ -n "$pdf2png" ]; then
  read -r kb rc <<<"$(measure "$pdf2png" --backend cpu "$tmp/image-20000.pdf" "$tmp/img")"
  echo "image-20000.pdf at 150 dpi: peak $((kb / 1024)) MB"
  check "a 20000 x 20000 PDF image: rendered in under 600 MB ($((kb / 1024)) MB; it was 12.7 GB)" \
    test "$rc" = 0 -a -s "$tmp/img-1.png" -a "$kb" -lt 614400
  read -r kb rc <<<"$(measure "$pdf2png" --backend cpu "$tmp/mesh-200k.pdf" "$tmp/mesh")"
  echo "mesh-200k.pdf at 150 dpi: peak $((kb / 1024)) MB"
  check "a 200,000-triangle mesh shading: rendered in under 1 GB ($((kb / 1024)) MB; it was 1.8 GB)" \
    test "$rc" = 0 -a -s "$tmp/mesh-1.png" -a "$kb" -lt 1048576
  read -r kb rc <<<"$(measure "$pdf2png" --backend cpu --max-memory 8G "$tmp/page-14400.pdf" "$tmp/big")"
  check "a 14400 pt page at 150 dpi over the budget: one line naming the page ($(cat "$tmp/err"))" \
    test "$rc" = 99 -a -n "$(grep -E "^pdf2png: page 1: the output of 30000x30000 pixels needs" "$tmp/err")" \
    -a -z "$(grep -F bad_alloc "$tmp/err")"
fi

echo "$fails failed"
test "$fails" = 0
