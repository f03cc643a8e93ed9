#!/usr/bin/env bash
# The persistent renderer (svg2png --server, MPVG_SERVER=1; apps/server.h):
# its outputs are the in-process ones byte for byte (files, standard
# streams, relative paths, batches), errors keep their exit status, a
# folder others can enter is never used, and an idle server exits. With
# auto the server, its CUDA ready, may take the GPU where the process
# would not wait for it: the comparisons use 1x32, whose bytes are the same
# on both backends (wide filters agree within 1/255).
# usage: test_server.sh SVG2PNG SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"
export MPVG_SERVER_DIR=$tmp/sock MPVG_SERVER_IDLE=20
mkdir -m 700 "$MPVG_SERVER_DIR"
svg=$src/testdata/golden/stroke_dashes.svg
server_pids() { pgrep -f -- "--serve-internal" || true; }
before=$(server_pids)

"$bin" -q --aa 1x32 "$svg" "$tmp/ref.png"
err=$("$bin" --server --stats --aa 1x32 "$svg" "$tmp/s1.png" 2>&1); rc=$?
check "--server: exit 0" test "$rc" = 0
check "--server: the job ran in the persistent renderer" grep -q "^persistent renderer: pid" <<<"$err"
pid=$(sed -n 's/^persistent renderer: pid //p' <<<"$err")
check "--server: the same bytes as in-process" cmp -s "$tmp/ref.png" "$tmp/s1.png"
check "the socket is the user's alone" test "$(stat -c %a "$MPVG_SERVER_DIR"/svg2png-*.sock)" = 600
err=$(MPVG_SERVER=1 "$bin" --stats --aa 1x32 "$svg" "$tmp/s2.png" 2>&1)
check "MPVG_SERVER=1: the same server serves again" test "$(sed -n 's/^persistent renderer: pid //p' <<<"$err")" = "$pid"
check "MPVG_SERVER=1: the same bytes" cmp -s "$tmp/ref.png" "$tmp/s2.png"
"$bin" --server -q --aa 1x32 - - < "$svg" > "$tmp/s3.png"
check "--server: standard input to standard output" cmp -s "$tmp/ref.png" "$tmp/s3.png"
(cd "$src/testdata/golden" && "$bin" --server -q --aa 1x32 stroke_dashes.svg "$tmp/s4.png")
check "--server: paths relative to the caller's folder" cmp -s "$tmp/ref.png" "$tmp/s4.png"
err=$("$bin" --server "$tmp/missing.svg" "$tmp/x.png" 2>&1); rc=$?
check "--server: a missing input is exit 1 with the message" test "$rc" = 1 -a -n "$(grep "cannot read" <<<"$err")"
"$bin" --server --frobnicate "$svg" "$tmp/x.png" 2>/dev/null; rc=$?
check "--server: a usage error is exit 2" test "$rc" = 2
mkdir -p "$tmp/batch"
cp "$src/testdata/golden/arcs.svg" "$src/testdata/golden/opacity.svg" "$tmp/batch/"
"$bin" -q --aa 1x32 -o "$tmp/b1" "$tmp"/batch/*.svg
"$bin" --server -q --aa 1x32 -o "$tmp/b2" "$tmp"/batch/*.svg
check "--server: a batch writes the in-process batch's bytes" cmp -s "$tmp/b1/arcs.png" "$tmp/b2/arcs.png"
check "--server: a batch's second file too" cmp -s "$tmp/b1/opacity.png" "$tmp/b2/opacity.png"

# A socket folder others may enter is refused: the job renders in-process.
mkdir -m 777 "$tmp/open"
err=$(MPVG_SERVER_DIR=$tmp/open "$bin" --server --stats --aa 1x32 "$svg" "$tmp/o.png" 2>&1); rc=$?
check "open socket folder: rendered in-process, same bytes" test "$rc" = 0 -a -z "$(grep "persistent renderer" <<<"$err")"
check "open socket folder: no socket made" test -z "$(ls "$tmp/open")"
cmp -s "$tmp/ref.png" "$tmp/o.png"
check "open socket folder: same bytes" test $? = 0

# An idle server exits and removes its socket.
kill "$pid" 2>/dev/null
export MPVG_SERVER_IDLE=0.5
rm -f "$MPVG_SERVER_DIR"/*.sock
err=$("$bin" --server --stats "$svg" "$tmp/i.png" 2>&1)
pid2=$(sed -n 's/^persistent renderer: pid //p' <<<"$err")
check "a new server after the old one is gone" test -n "$pid2" -a "$pid2" != "$pid"
for i in $(seq 40); do kill -0 "$pid2" 2>/dev/null || break; sleep 0.1; done
check "an idle server exits" test -n "$pid2" && ! kill -0 "$pid2" 2>/dev/null
check "an idle server removes its socket" test -z "$(ls "$MPVG_SERVER_DIR")"
# No server of this test is left behind.
for p in $(server_pids); do grep -qw "$p" <<<"$before" || kill "$p" 2>/dev/null; done

echo "$fails failed"
test "$fails" = 0
