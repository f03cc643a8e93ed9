#!/usr/bin/env bash
# Issue 45's hostile inputs, one case per finding: no signal, the exit
# status and message a user should get, peak RSS under a bound measured
# here (GNU time), files only inside the output's folder. Small inputs
# are in testdata/hostile/, large ones written by make_hostile_inputs.py.
# usage: test_hostile.sh SVG2PNG PDF2PNG SOURCE_DIR   (PDF2PNG "" without MuPDF)
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
h=$src/testdata/hostile
python3 "$src/tests/make_hostile_inputs.py" "$tmp" markers.svg lines-1e5.svg filter-chain.svg dash-200k.svg \
  mesh-200k-large.pdf
# "KB RC SECONDS" of a command (stderr in $tmp/err); a signal shows as RC > 128.
measure() {
  /usr/bin/time -f "%M %e" -o "$tmp/rss" timeout 300 "$@" 2> "$tmp/err"
  local rc=$?
  read -r kb s < <(tail -n 1 "$tmp/rss")
  echo "$kb $rc $s"
}
under_mb() { test "$1" -lt $(($2 * 1024)); }
one_line() { test "$(wc -l < "$tmp/err")" = 1; }
err() { tr '\n' ' ' < "$tmp/err" | cut -c1-240; }

# 5. The budget bounds geometry and filters.
read -r kb rc s <<<"$(measure "$svg2png" --backend cpu --max-memory 1G "$tmp/markers.svg" "$tmp/markers.png")"
check "10^6 markers under --max-memory 1G: refused, one line naming the budget ($(err))" \
  test "$rc" = 1 -a ! -e "$tmp/markers.png" -a -n "$(grep -E '^svg2png: the render needs .*, the budget is 1 GiB \(--max-memory\)$' "$tmp/err")"
check "... peak $((kb / 1024)) MB, under 1100 MB (was killed at 24 GB), ${s} s" under_mb "$kb" 1100
read -r kb rc s <<<"$(measure "$svg2png" --backend cpu "$tmp/lines-1e5.svg" "$tmp/lines.png")"
check "10^5 <line> elements: rendered in $((kb / 1024)) MB, under 1 GB (was 1.1 GB), ${s} s" \
  test "$rc" = 0 -a -s "$tmp/lines.png" -a "$kb" -lt 1048576
read -r kb rc s <<<"$(measure "$svg2png" --backend cpu --max-memory 256M "$tmp/filter-chain.svg" "$tmp/chain.png")"
check "10^4 chained blurs under --max-memory 256M: rendered whole in $((kb / 1024)) MB, under 300 MB (was 735 MB), ${s} s ($(err))" \
  test "$rc" = 0 -a -s "$tmp/chain.png" -a "$kb" -lt 307200 -a ! -s "$tmp/err"

# 6. No silent wrong output: a filter region 2e9 wide draws.
"$svg2png" --backend cpu -q "$h/flood-2e9.svg" "$tmp/flood.png"
got=$(pixels "$tmp/flood.png" 50,50 150,150)
check "a userSpaceOnUse feFlood region 2e9 wide: red over the canvas ($got)" test "$got" = "200x200 8 6 255-0-0-255 255-0-0-255"

# 7. Regressions: a JPEG header's claim, a 200k-entry dash array.
read -r kb rc s <<<"$(measure "$svg2png" --backend cpu "$h/jpeg-65500.svg" "$tmp/jpeg.png")"
check "a JPEG claiming 65500 x 65500 pixels: refused with a warning, the rest drawn, ${s} s ($(err))" \
  test "$rc" = 0 -a -s "$tmp/jpeg.png" -a -n "$(grep -E 'over the limit|need OpenImageIO' "$tmp/err")"
check "... in under 5 s (was 28 s)" python3 -c "import sys; sys.exit(0 if float('$s') < 5 else 1)"
read -r kb rc s <<<"$(measure "$svg2png" --backend cpu "$tmp/dash-200k.svg" "$tmp/dash.png")"
check "a 200,000-entry stroke-dasharray: rendered in ${s} s, under 5 s (was 19 s)" \
  python3 -c "import sys; sys.exit(0 if $rc == 0 and float('$s') < 5 else 1)"

# 8. XML as deep as the converter's limit.
"$svg2png" --backend cpu -q "$h/nest-99.svg" "$tmp/n99.png" 2> "$tmp/err"; rc=$?
got=$(pixels "$tmp/n99.png" 50,50)
check "a rect in 99 nested groups: drawn ($got, exit $rc, $(err))" test "$rc" = 0 -a "$got" = "200x200 8 6 0-128-0-255"
"$svg2png" --backend cpu "$h/nest-300.svg" "$tmp/n300.png" 2> "$tmp/err"; rc=$?
check "300 nested groups: exit 0, one warning ($(err))" \
  test "$rc" = 0 -a -s "$tmp/n300.png" -a -n "$(grep -F 'nested deeper than 257 levels' "$tmp/err")"

if [ -n "$pdf2png" ]; then
  # 1. The mesh whose item count wrapped past 2^32 (a heap overflow).
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu "$h/mesh-overflow.pdf" "$tmp/mo")"
  check "65,537 whole-grid mesh triangles: rendered, no signal (exit $rc, $((kb / 1024)) MB, ${s} s; was SIGSEGV)" \
    test "$rc" = 0 -a -s "$tmp/mo-1.png"
  check "... under 400 MB" under_mb "$kb" 400
  got=$(pixels "$tmp/mo-1.png" 100,1100 1100,100)
  check "... each half the top-most triangle's colour, as mutool draws it ($got)" test "$got" = "1250x1250 8 2 0-100-50 200-100-50"
  # 3. 200,000 large triangles within 2x mutool's memory (116 MB here).
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu --max-memory 1G "$tmp/mesh-200k-large.pdf" "$tmp/ml")"
  check "200,000 large mesh triangles under --max-memory 1G: rendered in $((kb / 1024)) MB, under 232 MB (was 6.1 GB), ${s} s" \
    test "$rc" = 0 -a -s "$tmp/ml-1.png" -a "$kb" -lt 237568
  # 2. Spot names are not paths.
  mkdir -p "$tmp/out/plates" "$tmp/escaped"
  pdf2png=$(realpath "$pdf2png")
  ( cd "$tmp/out/plates" && "$pdf2png" --backend cpu -q -r 72 --aa 1x32 --separations "$h/spot-names.pdf" sp ) 2> "$tmp/err"
  rc=$?
  check "--separations with spot names ../../../escaped, a/b: exit 0 ($(err))" test "$rc" = 0
  check "... nothing outside the output's folder" test -z "$(find "$tmp" -newer "$h/spot-names.pdf" -name '*escaped*' ! -path "$tmp/out/plates/*" -type f)"
  got=$(cd "$tmp/out/plates" && ls | tr '\n' ' ')
  check "... every plate beside the output, names escaped, apart in case ($got)" \
    test "$got" = "sp-1(..%2F..%2F..%2Fescaped).tif sp-1(Black).tif sp-1(Cyan).tif sp-1(GOLD~2).tif sp-1(Gold).tif sp-1(Grün).tif sp-1(Magenta).tif sp-1(Yellow).tif sp-1(a%2Fb).tif sp-1.png sp-1.tif "
  "$pdf2png" --backend cpu -q -r 72 --separations "$h/spots-65.pdf" "$tmp/s65" 2> "$tmp/err"; rc=$?
  check "65 spot colours: refused with one line, nothing written ($(err))" \
    test "$rc" = 99 -a -n "$(grep -F 'more than 64 spot colours' "$tmp/err")" -a -z "$(ls "$tmp" | grep '^s65')"
  # 4. --max-input for devices, FIFOs and stdin.
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu /dev/zero "$tmp/z")"
  check "pdf2png /dev/zero: refused at the input limit, one line ($(err))" \
    test "$rc" = 1 -a "$(cat "$tmp/err")" = "pdf2png: '/dev/zero' is larger than the input limit of 1 GiB (--max-input)"
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu --max-input 1M /dev/zero "$tmp/z")"
  check "--max-input 1M /dev/zero: refused in $((kb / 1024)) MB, under 100 MB" test "$rc" = 1 -a "$kb" -lt 102400
  mkfifo "$tmp/fifo"
  head -c 3000000 /dev/zero > "$tmp/fifo" &
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu --max-input 1M "$tmp/fifo" "$tmp/f")"
  wait
  check "a FIFO past --max-input: refused, one line ($(err))" test "$rc" = 1 && one_line
  read -r kb rc s <<<"$(measure "$pdf2png" --backend cpu --max-input 1M - "$tmp/i" < /dev/zero)"
  check "stdin past --max-input: refused, one line ($(err))" test "$rc" = 1 && one_line
fi

echo "$fails failed"
test "$fails" = 0
