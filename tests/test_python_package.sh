#!/usr/bin/env bash
# The Python package as its users install it (pyproject.toml,
# scikit-build-core): `python3 -m venv v && v/bin/pip install SOURCE` in a
# scratch folder, then `import mpvg` from the venv, a render equal to
# svg2png's pixels, and `python -m mpvg`. Skipped (77), saying why, where
# the venv module or the package index (for scikit-build-core and pybind11)
# is not available.
#
#   tests/test_python_package.sh SVG2PNG SOURCE_DIR [PYTHON]
set -uo pipefail
svg2png=$1 src=$2 python=${3:-/usr/bin/python3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if ! "$python" -m venv --system-site-packages "$tmp/v" > "$tmp/venv.log" 2>&1; then
  echo "test_python_package: skipped, $python -m venv fails: $(tail -1 "$tmp/venv.log")"
  exit 77
fi
pip=$tmp/v/bin/pip
if ! timeout 60 "$pip" download -q --no-deps -d "$tmp/probe" scikit-build-core > "$tmp/probe.log" 2>&1; then
  echo "test_python_package: skipped, no package index to get scikit-build-core from ($(grep -m1 -o 'No matching.*\|Failed to establish[^)]*' "$tmp/probe.log"))"
  exit 77
fi
fails=0
check() {
  local what=$1; shift
  if "$@"; then echo "ok   $what"; else echo "FAIL $what"; fails=$((fails + 1)); fi
}
t0=$(date +%s)
( cd "$tmp" && "$pip" install -q "$src" > "$tmp/install.log" 2>&1 )
rc=$?
echo "pip install: exit $rc in $(( $(date +%s) - t0 )) s"
check "pip install SOURCE into a fresh venv" test "$rc" = 0 || tail -20 "$tmp/install.log"
py=$tmp/v/bin/python
svg=$src/testdata/css/linked-expected.svg
check "import mpvg from the venv (not the build tree)" \
  test "$(cd "$tmp" && "$py" -c 'import mpvg, os; print(os.path.dirname(mpvg.__file__).startswith(os.path.realpath("'"$tmp"'/v")))')" = True
"$svg2png" -q --backend cpu -w 64 "$svg" "$tmp/cli.png"
(cd "$tmp" && "$py" -m mpvg --backend cpu -w 64 "$svg" "$tmp/mod.png")
same=$(cd "$tmp" && "$py" - "$tmp/cli.png" "$tmp/mod.png" <<'PY'
import struct, sys, zlib
import numpy as np
def read(path):
    d = open(path, "rb").read()
    w, h, bd, ct = struct.unpack(">IIBB", d[16:26])
    i, z = 8, b""
    while i < len(d):
        n = struct.unpack(">I", d[i:i + 4])[0]
        if d[i + 4:i + 8] == b"IDAT":
            z += d[i + 8:i + 8 + n]
        i += 12 + n
    ch = {2: 3, 6: 4}[ct]
    raw, stride, rows, prev = zlib.decompress(z), w * ch, [], bytearray(w * ch)
    for y in range(h):
        t, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b, c = prev[x], (prev[x - ch] if x >= ch else 0)
            p = a + b - c
            pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c)
                    else b if abs(p - b) <= abs(p - c) else c][t]
            line[x] = (line[x] + pred) & 255
        rows.append(bytes(line)); prev = line
    img = np.frombuffer(b"".join(rows), np.uint8).reshape(h, w, ch)
    return img if ch == 4 else np.concatenate([img, np.full((h, w, 1), 255, np.uint8)], axis=2)
cli, mod = read(sys.argv[1]), read(sys.argv[2])
print("same" if cli.shape == mod.shape and (cli == mod).all() else "differ")
PY
)
check "python -m mpvg writes svg2png's pixels ($same)" test "$same" = same
echo "$fails failure(s)"
test "$fails" = 0
