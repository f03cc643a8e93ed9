# Helpers of the command-line tests (test_cli.sh, test_cli_pdf.sh): a
# scratch folder removed on exit, `check DESCRIPTION CONDITION...` counting
# failures in $fails, png_size and pixels.
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
# Reads PNGs of any colour type and depth: `pixels PNG X,Y ...` prints
# "WxH depth type" and each pixel's samples as R-G-B (or G, or G-A); `all`
# every pixel, `raw` the inflated rows (filter bytes included) in hex.
phys() {  # a PNG's pHYs: "X Y UNIT" (pixels per metre, 1: metre), or "none"
  python3 -c "
import struct, sys
d = open(sys.argv[1], 'rb').read()
i = d.find(b'pHYs')
print(*(struct.unpack('>IIB', d[i + 4:i + 13]) if i > 0 else ['none']))" "$1"
}
pixels() {
  python3 - "$@" <<'PY'
import struct, sys, zlib
d = open(sys.argv[1], "rb").read()
w, h, bd, ct = struct.unpack(">IIBB", d[16:26])
i, z = 8, b""
while i < len(d):
    n = struct.unpack(">I", d[i:i + 4])[0]
    if d[i + 4:i + 8] == b"IDAT":
        z += d[i + 8:i + 8 + n]
    i += 12 + n
ch = {0: 1, 2: 3, 4: 2, 6: 4}[ct]
raw = zlib.decompress(z)
stride, bpp = (w * ch * bd + 7) // 8, max(1, ch * bd // 8)
rows, prev, at = [], bytearray(stride), 0
for y in range(h):
    t, line = raw[at], bytearray(raw[at + 1:at + 1 + stride])
    at += 1 + stride
    for x in range(stride):
        a = line[x - bpp] if x >= bpp else 0
        b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
        p = a + b - c
        pred = [0, a, b, (a + b) // 2,
                a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c][t]
        line[x] = (line[x] + pred) & 255
    rows.append(line)
    prev = line
def px(x, y):
    r = rows[y]
    if bd == 1:
        return [(r[x >> 3] >> (7 - (x & 7))) & 1]
    if bd == 8:
        return list(r[x * ch:(x + 1) * ch])
    return [(r[2 * (x * ch + k)] << 8) | r[2 * (x * ch + k) + 1] for k in range(ch)]
out = ["%dx%d %d %d" % (w, h, bd, ct)]
for a in sys.argv[2:]:
    if a == "raw":
        out.append(raw.hex())
    elif a == "all":
        out += ["-".join(map(str, px(x, y))) for y in range(h) for x in range(w)]
    else:
        x, y = map(int, a.split(","))
        out.append("-".join(map(str, px(x, y))))
print(" ".join(out))
PY
}
