#!/usr/bin/env bash
# The persistent renderer (svg2png --server, MPVG_SERVER=1; lib/server/server.h):
# its outputs are the in-process ones byte for byte (files, standard
# streams, relative paths and read policy), written by the client (its
# umask), errors keep their exit status, batches render in-process, a
# folder others can enter is never used, a client whose credentials differ
# from the server's (limits, capabilities, groups, no_new_privs,
# environment) renders in-process, jobs run concurrently, a job whose
# client has gone is dropped, a client whose server hangs or dies renders
# in-process, and an idle server exits. With auto the server, its CUDA
# ready, may take the GPU where the process would not wait for it: the
# comparisons use 1x32, whose bytes are the same on both backends (wide
# filters agree within 1/255), or --backend cpu.
# usage: test_server.sh SVG2PNG SOURCE_DIR
set -u
bin=$(realpath "$1")
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
export MPVG_SERVER_DIR=$tmp/sock MPVG_SERVER_IDLE=20 MPVG_SERVER_LOG=$tmp/server.log
mkdir -m 700 "$MPVG_SERVER_DIR"
svg=$src/testdata/golden/stroke_dashes.svg
# This test's servers: those whose environment names its socket folder.
our_servers() {
  local p
  for p in $(pgrep -f -- "--serve-internal"); do
    tr '\0' '\n' < "/proc/$p/environ" 2>/dev/null | grep -qx "MPVG_SERVER_DIR=$MPVG_SERVER_DIR" && echo "$p"
  done
}
cleanup() {
  local p
  for p in $(our_servers); do kill -9 "$p" 2>/dev/null; done
  rm -rf "$tmp"
}
trap cleanup EXIT
# wait_for CONDITION...: polls it for up to 20 s.
wait_for() {
  local i
  for i in $(seq 1000); do "$@" && return 0; sleep 0.02; done
  return 1
}
# dead PID: gone, or a zombie where nothing reaps it, with no thread left
# (a killed process's other threads, which share its sockets, outlive the
# first one for a while).
dead() {
  ! kill -0 "$1" 2>/dev/null ||
    { grep -q "^State:.*Z" "/proc/$1/status" 2>/dev/null && test "$(ls "/proc/$1/task" 2>/dev/null | wc -l)" -le 1; }
}
log_count() { grep -c -- "$1" "$MPVG_SERVER_LOG" 2>/dev/null || true; }
served_pid() { sed -n 's/^persistent renderer: pid //p' <<<"$1"; }

"$bin" -q --aa 1x32 "$svg" "$tmp/ref.png"
err=$("$bin" --server --stats --aa 1x32 "$svg" "$tmp/s1.png" 2>&1); rc=$?
check "--server: exit 0" test "$rc" = 0
check "--server: the job ran in the persistent renderer" grep -q "^persistent renderer: pid" <<<"$err"
pid=$(served_pid "$err")
check "--server: the same bytes as in-process" cmp -s "$tmp/ref.png" "$tmp/s1.png"
check "the socket is the user's alone" test "$(stat -c %a "$MPVG_SERVER_DIR"/svg2png-*.sock)" = 600
err=$(MPVG_SERVER=1 "$bin" --stats --aa 1x32 "$svg" "$tmp/s2.png" 2>&1)
check "MPVG_SERVER=1: the same server serves again" test "$(served_pid "$err")" = "$pid"
check "MPVG_SERVER=1: the same bytes" cmp -s "$tmp/ref.png" "$tmp/s2.png"
"$bin" --server -q --aa 1x32 - - < "$svg" > "$tmp/s3.png"
check "--server: standard input to standard output" cmp -s "$tmp/ref.png" "$tmp/s3.png"
(cd "$src/testdata/golden" && "$bin" --server -q --aa 1x32 stroke_dashes.svg "$tmp/s4.png")
check "--server: paths relative to the caller's folder" cmp -s "$tmp/ref.png" "$tmp/s4.png"
err=$("$bin" --server "$tmp/missing.svg" "$tmp/x.png" 2>&1); rc=$?
check "--server: a missing input is exit 1 with the message" test "$rc" = 1 -a -n "$(grep "cannot read" <<<"$err")"
"$bin" --server --frobnicate "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "--server: a usage error is exit 2" test "$rc" = 2
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><rect width="4" height="4"/></svg' > "$tmp/bad.svg"
err=$("$bin" --server "$tmp/bad.svg" "$tmp/bad.png" 2>&1); rc=$?
check "--server: a malformed document is exit 1 with the message, no output" \
  test "$rc" = 1 -a -n "$(grep "XML" <<<"$err")" -a ! -e "$tmp/bad.png"
mkdir -p "$tmp/batch"
cp "$src/testdata/golden/arcs.svg" "$src/testdata/golden/opacity.svg" "$tmp/batch/"
"$bin" -q --aa 1x32 -o "$tmp/b1" "$tmp"/batch/*.svg
jobs_before=$(log_count "job ")
"$bin" --server -q --aa 1x32 -o "$tmp/b2" "$tmp"/batch/*.svg
check "--server: a batch writes the in-process batch's bytes" cmp -s "$tmp/b1/arcs.png" "$tmp/b2/arcs.png"
check "--server: a batch's second file too" cmp -s "$tmp/b1/opacity.png" "$tmp/b2/opacity.png"
check "--server: a batch renders in-process" test "$(log_count "job ")" = "$jobs_before"

# The document's references resolve as in-process: its own folder, the
# client's for standard input, --allow-read relative to the client's folder;
# warnings come back.
mkdir -p "$tmp/doc" "$tmp/pics"
cp "$src/testdata/images/rgba8.png" "$tmp/pics/"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image width="8" height="8" href="../pics/rgba8.png"/></svg>' > "$tmp/doc/img.svg"
"$bin" -q "$tmp/doc/img.svg" "$tmp/img1.png"
(cd "$tmp" && "$bin" -q --allow-read pics doc/img.svg "$tmp/img2.png")
err=$("$bin" --server --stats "$tmp/doc/img.svg" "$tmp/simg1.png" 2>&1); rc=$?
check "--server: an image outside the folder: the warning comes back, exit 0" \
  test "$rc" = 0 -a -n "$(grep "outside the folders the document may read" <<<"$err")" -a -n "$(served_pid "$err")"
check "--server: an image outside the folder: not drawn, as in-process" cmp -s "$tmp/img1.png" "$tmp/simg1.png"
(cd "$tmp" && "$bin" --server -q --allow-read pics doc/img.svg "$tmp/simg2.png")
check "--server: a relative --allow-read opens the client's folder" cmp -s "$tmp/img2.png" "$tmp/simg2.png"
check "--server: ... and the image is drawn" test -n "$(cmp "$tmp/img1.png" "$tmp/img2.png" 2>&1)"
(cd "$tmp/doc" && "$bin" --server -q - "$tmp/simg3.png" < "$tmp/doc/img.svg")
check "--server: standard input reads the client's folder's tree only" cmp -s "$tmp/img1.png" "$tmp/simg3.png"
printf '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><image width="8" height="8" href="rgba8.png"/></svg>' > "$tmp/here.svg"
(cd "$tmp/pics" && "$bin" --server -q - "$tmp/simg4.png" < "$tmp/here.svg")
check "--server: standard input: images in the client's folder are read" cmp -s "$tmp/img2.png" "$tmp/simg4.png"

# Outputs are written by the client: its umask applies.
for mask in 077 022; do
  rm -f "$tmp/mask.png"
  err=$(umask $mask && "$bin" --server --stats --aa 1x32 "$svg" "$tmp/mask.png" 2>&1)
  want=$(printf '%o' $((0666 & ~8#$mask)))
  check "--server, umask $mask: served, the output's mode is $want" \
    test -n "$(served_pid "$err")" -a "$(stat -c %a "$tmp/mask.png")" = "$want"
  check "--server, umask $mask: the same bytes" cmp -s "$tmp/ref.png" "$tmp/mask.png"
done

# Credentials: the comparison itself (svg2png --server-credentials-internal
# prints this process's record, or compares two).
creds() { "$@" "$bin" --server-credentials-internal; }
creds env > "$tmp/c0"
differs() {  # FIELD COMMAND...: the record under COMMAND differs in FIELD first
  local field=$1
  shift
  creds "$@" > "$tmp/c1"
  test "$("$bin" --server-credentials-internal "$tmp/c0" "$tmp/c1")" = "$field"
}
check "credentials: a second run's record is equal" differs equal env
check "credentials: MPVG_SERVER_*, MPVG_T0 and others do not count" \
  differs equal env MPVG_SERVER_TIMEOUT=3 MPVG_T0=1 PWD=/ OLDPWD=/x
check "credentials: resource limits" differs limits prlimit --nofile=256:256
check "credentials: no_new_privs" differs NoNewPrivs setpriv --no-new-privs
check "credentials: FONTCONFIG_FILE" differs "env FONTCONFIG_FILE" env FONTCONFIG_FILE=/nonexistent/fonts.conf
check "credentials: an MPVG_ setting" differs "env MPVG_CUDA_SYNC" env MPVG_CUDA_SYNC=1
grep -v "^lsm=" "$tmp/c0" > "$tmp/c2"
check "credentials: a field one side lacks" test "$("$bin" --server-credentials-internal "$tmp/c0" "$tmp/c2")" = lsm
if [ "$(id -u)" = 0 ]; then
  check "credentials: capabilities" differs CapBnd setpriv --inh-caps=-all --bounding-set=-all
  check "credentials: supplementary groups" differs Groups setpriv --groups=12345
  check "credentials: an IPC namespace" differs ns/ipc unshare --ipc
else
  echo "skip credentials: capabilities, groups, namespaces (not root)"
fi

# ... and the server's use of it: a client whose credentials differ renders
# in-process, with the same bytes and exit status.
refused() {  # NAME COMMAND...
  local name=$1
  shift
  rm -f "$tmp/r.png"
  err=$("$@" "$bin" --server --stats --aa 1x32 "$svg" "$tmp/r.png" 2>&1); rc=$?
  check "$name: rendered in-process, exit 0" \
    test "$rc" = 0 -a -z "$(served_pid "$err")" -a -n "$(grep "persistent renderer: not used (refused" <<<"$err")"
  check "$name: the same bytes" cmp -s "$tmp/ref.png" "$tmp/r.png"
}
refused "other resource limits" prlimit --nofile=256:256
refused "no_new_privs" setpriv --no-new-privs
refused "another FONTCONFIG_FILE" env FONTCONFIG_FILE=/nonexistent/fonts.conf
if [ "$(id -u)" = 0 ]; then
  refused "capabilities dropped" setpriv --inh-caps=-all --bounding-set=-all
  refused "other supplementary groups" setpriv --groups=12345
else
  echo "skip refusals for capabilities and groups (not root)"
fi
err=$(MPVG_SERVER_TIMEOUT=3 "$bin" --server --stats --aa 1x32 "$svg" "$tmp/t.png" 2>&1)
check "the client's MPVG_SERVER_TIMEOUT does not keep it from the server" test "$(served_pid "$err")" = "$pid"

# A slow job (a few seconds on the CPU; larger on more cores), its
# in-process bytes.
slow_w=$(awk -v n="$(nproc)" 'BEGIN { printf "%d", 1200 * sqrt(n / 2) }')
slow=(--backend cpu -w "$slow_w" "$src/testdata/golden/curves.svg")
"$bin" -q "${slow[@]}" "$tmp/slow_ref.png"
# started N: the log holds N "started" lines.
started() { test "$(log_count ": started")" -ge "$1"; }

# Jobs run concurrently: a small job issued while the slow one runs
# finishes first.
n=$(log_count ": started")
"$bin" --server -q "${slow[@]}" "$tmp/slow1.png" & slow_pid=$!
wait_for started $((n + 1))
err=$("$bin" --server --stats --aa 1x32 "$svg" "$tmp/small.png" 2>&1)
kill -0 "$slow_pid" 2>/dev/null
check "concurrent jobs: the small one finished while the slow one runs" test $? = 0 -a "$(served_pid "$err")" = "$pid"
check "concurrent jobs: the small one's bytes" cmp -s "$tmp/ref.png" "$tmp/small.png"
wait "$slow_pid"
check "concurrent jobs: the slow one's bytes" cmp -s "$tmp/slow_ref.png" "$tmp/slow1.png"

# A job whose client is killed is dropped at its next stage boundary.
n=$(log_count ": started")
"$bin" --server -q "${slow[@]}" "$tmp/slow2.png" & client=$!
wait_for started $((n + 1))
kill -9 "$client"
wait "$client" 2>/dev/null
check "a job whose client has gone is cancelled" wait_for grep -q "cancelled .*: the client has gone" "$MPVG_SERVER_LOG"
check "... nothing is written" test ! -e "$tmp/slow2.png"
err=$("$bin" --server --stats --aa 1x32 "$svg" "$tmp/after.png" 2>&1)
check "... and the server serves on" test "$(served_pid "$err")" = "$pid"

# A server that hangs mid-job (stopped): the client hears no heartbeat for
# MPVG_SERVER_TIMEOUT seconds and renders in-process.
n=$(log_count ": started")
MPVG_SERVER_TIMEOUT=2 "$bin" --server --stats "${slow[@]}" "$tmp/slow3.png" 2> "$tmp/slow3.err" & client=$!
wait_for started $((n + 1))
kill -STOP "$pid"
t0=$(date +%s)
wait "$client"; rc=$?
check "a stopped server: the client renders in-process, exit 0" \
  test "$rc" = 0 -a -n "$(grep "persistent renderer: not used (no word" "$tmp/slow3.err")"
check "a stopped server: the in-process bytes" cmp -s "$tmp/slow_ref.png" "$tmp/slow3.png"
check "a stopped server: given up on within bounds" test $(($(date +%s) - t0)) -lt 60
kill -9 "$pid"
# The next client starts a new server (not one that connects to this one's
# socket while it dies, and falls back in-process).
wait_for dead "$pid"
rm -f "$MPVG_SERVER_DIR"/*.sock

# A server killed mid-job: the client renders in-process.
n=$(log_count ": started")
"$bin" --server --stats "${slow[@]}" "$tmp/slow4.png" 2> "$tmp/slow4.err" & client=$!
wait_for started $((n + 1))
pid3=$(sed -n 's/^\[\([0-9]*\)\] job .*: started$/\1/p' "$MPVG_SERVER_LOG" | tail -1)
check "a new server after a stopped one was killed" test -n "$pid3" -a "$pid3" != "$pid"
kill -9 "$pid3"
wait "$client"; rc=$?
check "a killed server: the client renders in-process, exit 0" \
  test "$rc" = 0 -a -n "$(grep "persistent renderer: not used (the persistent renderer ended" "$tmp/slow4.err")"
check "a killed server: the in-process bytes" cmp -s "$tmp/slow_ref.png" "$tmp/slow4.png"

# A socket folder others may enter is refused: the job renders in-process.
mkdir -m 777 "$tmp/open"
err=$(MPVG_SERVER_DIR=$tmp/open "$bin" --server --stats --aa 1x32 "$svg" "$tmp/o.png" 2>&1); rc=$?
check "open socket folder: rendered in-process, same bytes" test "$rc" = 0 -a -z "$(served_pid "$err")"
check "open socket folder: no socket made" test -z "$(ls "$tmp/open")"
cmp -s "$tmp/ref.png" "$tmp/o.png"
check "open socket folder: same bytes" test $? = 0

# An idle server exits and removes its socket.
export MPVG_SERVER_IDLE=0.5
rm -f "$MPVG_SERVER_DIR"/*.sock
err=$("$bin" --server --stats "$svg" "$tmp/i.png" 2>&1)
pid2=$(served_pid "$err")
check "a new server after the old one is gone" test -n "$pid2" -a "$pid2" != "$pid3"
for i in $(seq 40); do dead "$pid2" && break; sleep 0.1; done
check "an idle server exits" test -n "$pid2" && dead "$pid2"
check "an idle server removes its socket" test -z "$(ls "$MPVG_SERVER_DIR")"
check "no server of this test is left" test -z "$(our_servers)"

echo "$fails failed"
test "$fails" = 0
