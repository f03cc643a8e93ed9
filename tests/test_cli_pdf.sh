#!/usr/bin/env bash
# Command-line behaviour of pdf2png: output names as pdftoppm gives them,
# resolution, --scale-to, crops, --singlefile, and one clear error line with
# a non-zero exit for bad input.
# usage: test_cli_pdf.sh PDF2PNG SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
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
err=$("$bin" -q --dpi zero "$pdf" "$tmp/m" 2>&1); rc=$?
check "a bad option value: exit 2" test "$rc" = 2
"$bin" -q --backend cpu -r 72 -f 1 -l 3 "$pdf" "$tmp/l"; rc=$?
check "-l past the last page renders what exists" test "$rc" = 0 -a -f "$tmp/l-1.png"

"$bin" -q --backend cpu -r 72 - "$tmp/in" < "$pdf"
check "- reads the document from stdin, the same image" cmp -s "$tmp/r-1.png" "$tmp/in-1.png"

echo "$fails failure(s)"
test "$fails" = 0
