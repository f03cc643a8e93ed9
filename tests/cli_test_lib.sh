# Helpers of the command-line tests (test_cli.sh, test_cli_pdf.sh): a
# scratch folder removed on exit, `check DESCRIPTION CONDITION...` counting
# failures in $fails, and png_size.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
check() {  # description, condition...
  local what=$1
  shift
  if "$@"; then echo "ok   $what"; else echo "FAIL $what"; fails=$((fails + 1)); fi
}
png_size() {  # prints WIDTHxHEIGHT of a PNG (IHDR at byte 16)
  local w h
  w=$(od -An -tu1 -j16 -N4 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4}')
  h=$(od -An -tu1 -j20 -N4 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4}')
  echo "${w}x${h}"
}
