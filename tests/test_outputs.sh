#!/usr/bin/env bash
# Outputs appear whole or not at all (lib/output/output_file.h), in single runs
# and batches: a full disk leaves no file under the final name and says
# why, a kill never leaves a truncated PNG, new files follow the caller's
# umask and replaced ones keep their mode; batches end with a summary line
# and --timeout fails only the file that ran too long.
# usage: test_outputs.sh SVG2PNG SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
svg=$src/testdata/golden/stroke_dashes.svg
# A document heavy enough to take a second or more on the CPU at -w 4000.
heavy=$tmp/heavy.svg
{
  echo '<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">'
  for i in $(seq 0 399); do
    echo "<path d=\"M $((i % 97)) 0 C 30 $((i % 53)) 70 $((100 - i % 41)) 100 $((i % 89))\" fill=\"none\" stroke=\"#$(printf '%06x' $((i * 40503 % 16777216)))\" stroke-width=\"$((1 + i % 5))\" stroke-dasharray=\"3 1\"/>"
  done
  echo '</svg>'
} > "$heavy"
complete_png() {  # the file ends with an IEND chunk
  test "$(tail -c 12 "$1" | od -An -tx1 | tr -d ' \n')" = 0000000049454e44ae426082
}
status_and_png() {  # exit status, expected status, a PNG that must be whole
  test "$1" = "$2" && complete_png "$3"
}

# Failures say why, and leave nothing behind.
err=$("$bin" -q --backend cpu "$svg" "$tmp" 2>&1); rc=$?
check "a folder as the output: exit 1, 'Is a directory'" test "$rc" = 1 -a "$err" = "svg2png: cannot write '$tmp': Is a directory"
err=$("$bin" -q --backend cpu "$svg" "$tmp/no/such/dir.png" 2>&1); rc=$?
check "a missing folder: exit 1, 'No such file or directory'" \
  test "$rc" = 1 -a "$err" = "svg2png: cannot write '$tmp/no/such/dir.png': No such file or directory"
if [ -e /dev/full ]; then
  err=$("$bin" -q --backend cpu "$svg" /dev/full 2>&1); rc=$?
  check "/dev/full: exit 1, 'No space left on device'" test "$rc" = 1 -a -n "$(grep -F 'No space left on device' <<<"$err")"
fi
chmod 755 "$tmp"  # another user (below) may enter it, not write in it
mkdir -m 555 "$tmp/ro"
if [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null; then
  err=$(setpriv --reuid=65534 --regid=65534 --clear-groups "$bin" -q --backend cpu "$svg" "$tmp/ro/x.png" 2>&1); rc=$?
else
  err=$("$bin" -q --backend cpu "$svg" "$tmp/ro/x.png" 2>&1); rc=$?
fi
check "a folder without write permission: 'Permission denied', nothing written" \
  test "$rc" = 1 -a -n "$(grep -F 'Permission denied' <<<"$err")" -a -z "$(ls -A "$tmp/ro")"
if [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null; then
  # A writable file in a folder where no file can be made: written in
  # place (it cannot be replaced), as before.
  mkdir "$tmp/ro2"
  : > "$tmp/ro2/out.png"
  chmod 666 "$tmp/ro2/out.png"
  chmod 555 "$tmp/ro2"
  setpriv --reuid=65534 --regid=65534 --clear-groups "$bin" -q --backend cpu "$svg" "$tmp/ro2/out.png"; rc=$?
  check "a writable file in a read-only folder: written in place" status_and_png "$rc" 0 "$tmp/ro2/out.png"
fi

# A full file system (a 16 KiB tmpfs, where this test may mount one).
mkdir "$tmp/full"
if mount -t tmpfs -o size=16k tmpfs "$tmp/full" 2>/dev/null; then
  trap 'umount "$tmp/full" 2>/dev/null; rm -rf "$tmp"' EXIT
  err=$("$bin" -q --backend cpu -w 600 "$heavy" "$tmp/full/big.png" 2>&1); rc=$?
  check "full disk: exit 1 with the reason" test "$rc" = 1 -a "$err" = "svg2png: cannot write '$tmp/full/big.png': No space left on device"
  check "full disk: no file under the final name, no temporary file" test -z "$(ls -A "$tmp/full")"
  "$bin" -q --backend cpu -w 40 "$svg" "$tmp/full/small.png"; rc=$?
  check "full disk: a file that fits is written whole" status_and_png "$rc" 0 "$tmp/full/small.png"
  cp "$tmp/full/small.png" "$tmp/small-before.png"
  "$bin" -q --backend cpu -w 600 "$heavy" "$tmp/full/small.png" 2>/dev/null
  check "full disk: a failed rewrite keeps the old file intact" cmp -s "$tmp/small-before.png" "$tmp/full/small.png"
  mkdir -p "$tmp/fb"
  cp "$svg" "$tmp/fb/a.svg"; cp "$heavy" "$tmp/fb/b.svg"
  rm -f "$tmp/full/small.png"
  sed -i 's/width="100" height="100"/width="600" height="600"/' "$tmp/fb/b.svg"
  err=$("$bin" -q --backend cpu -o "$tmp/full/out" "$tmp/fb/a.svg" "$tmp/fb/b.svg" 2>&1); rc=$?
  check "full disk in a batch: exit 1, the file that fits written" status_and_png "$rc" 1 "$tmp/full/out/a.png"
  check "full disk in a batch: the other named with the reason, nothing left of it" \
    test -n "$(grep -F "b.svg: cannot write '$tmp/full/out/b.png': No space left on device" <<<"$err")" \
    -a "$(ls -A "$tmp/full/out")" = a.png
  umount "$tmp/full"
else
  echo "skip full-disk cases: cannot mount a tmpfs here (not root)"
fi

# Killed while writing: the final name holds a whole PNG or nothing, and
# SIGTERM leaves no temporary file.
killed_ok=0
for delay in 0.05 0.15 0.3 0.5 0.8; do
  rm -f "$tmp/k.png" "$tmp"/.k.png.*
  "$bin" -q --backend cpu -w 3000 "$heavy" "$tmp/k.png" &
  pid=$!
  sleep "$delay"
  kill -TERM "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  if { [ ! -e "$tmp/k.png" ] || complete_png "$tmp/k.png"; } && [ -z "$(ls -A "$tmp" | grep '^\.k\.png\.')" ]; then
    killed_ok=$((killed_ok + 1))
  fi
done
check "SIGTERM at 5 moments: never a truncated PNG, never a temporary file left" test "$killed_ok" = 5

# Modes: new files follow the umask, rewritten files keep their mode.
(umask 077 && "$bin" -q --backend cpu "$svg" "$tmp/m77.png")
check "umask 077: a new output is 600" test "$(stat -c %a "$tmp/m77.png")" = 600
(umask 022 && "$bin" -q --backend cpu "$svg" "$tmp/m22.png")
check "umask 022: a new output is 644" test "$(stat -c %a "$tmp/m22.png")" = 644
chmod 640 "$tmp/m22.png"
"$bin" -q --backend cpu "$svg" "$tmp/m22.png"
check "a replaced output keeps its mode (640)" test "$(stat -c %a "$tmp/m22.png")" = 640
"$bin" -q --backend cpu "$svg" /dev/null; rc=$?
check "a device (/dev/null) is written in place" test "$rc" = 0 -a -c /dev/null
"$bin" -q --backend cpu "$svg" - | cat > "$tmp/piped.png"
check "standard output through a pipe: a whole PNG" complete_png "$tmp/piped.png"

# Batches: a summary line whether or not standard error is a terminal.
mkdir -p "$tmp/b"
cp "$svg" "$tmp/b/a.svg"; cp "$svg" "$tmp/b/c.svg"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect' > "$tmp/b/broken.svg"
err=$("$bin" --backend cpu -o "$tmp/bo" "$tmp"/b/*.svg 2>&1); rc=$?
check "batch summary line without a terminal" test "$rc" = 1 -a "$(tail -n 1 <<<"$err")" = "svg2png: 3 files, 2 written, 1 failed"
err=$("$bin" -q --backend cpu -o "$tmp/bo2" "$tmp/b/a.svg" "$tmp/b/c.svg" 2>&1)
check "-q: no summary when nothing failed" test -z "$err"

# --timeout: the file that takes too long fails, the others are written,
# and the run does not wait for it.
cp "$heavy" "$tmp/b/heavy.svg"
sed -i 's/width="100" height="100"/width="6000" height="6000"/' "$tmp/b/heavy.svg"
rm "$tmp/b/broken.svg"
start=$(date +%s%N)
err=$("$bin" --backend cpu --threads 1 --render-threads 2 --timeout 0.5 -o "$tmp/to" "$tmp"/b/*.svg 2>&1); rc=$?
took=$(( ($(date +%s%N) - start) / 1000000 ))
check "--timeout: exit 1, the slow file named" test "$rc" = 1 -a -n "$(grep -F "heavy.svg: timed out after 0.5 s" <<<"$err")"
check "--timeout: the others written, the slow one not" test -s "$tmp/to/a.png" -a -s "$tmp/to/c.png" -a ! -e "$tmp/to/heavy.png"
check "--timeout: the summary counts it" test -n "$(grep -F "3 files, 2 written, 1 failed (1 timed out)" <<<"$err")"
check "--timeout: the run ends soon after the limit (${took} ms)" test "$took" -lt 20000
err=$("$bin" --timeout 0 "$svg" "$tmp/x.png" 2>&1); rc=$?
check "--timeout 0 is a usage error" test "$rc" = 2

echo "$fails failed"
test "$fails" = 0
