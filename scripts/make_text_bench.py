#!/usr/bin/env python3
"""Writes the text benchmark inputs (BENCHMARKS.md, "Text"):

    scripts/make_text_bench.py OUTDIR [SEGMENTS]

OUTDIR/text_page.svg: a US-letter page (612 x 792) of 5,000 characters in
two columns of 50 lines of 50 (a pangram cycled, DejaVu Sans 9 px,
alternate lines in a tspan of another colour), i.e. the layout and outline work of a page of
body text. OUTDIR/shapes_page.svg (written when SEGMENTS is given): a
text-free page of SEGMENTS path segments, small closed cubic blobs of 8
segments each on a grid, for comparing render times at equal segment
counts (svg2png --stats prints the text page's).
"""
import math
import random
import sys

out = sys.argv[1]
TEXT = "Sphinx of black quartz, judge my vow; the quick brown fox jumps over the lazy dog. "
lines = []
k = 0
for i in range(100):
    s = "".join(TEXT[(k + j) % len(TEXT)] for j in range(50))
    k += 50
    s = s.replace("&", "&amp;").replace("<", "&lt;")
    x = 36 if i < 50 else 316
    y = 40 + (i % 50) * 14.5
    if i % 2:
        lines.append(f'<text x="{x}" y="{y:.1f}"><tspan fill="#224">{s}</tspan></text>')
    else:
        lines.append(f'<text x="{x}" y="{y:.1f}">{s}</text>')
with open(f"{out}/text_page.svg", "w") as f:
    f.write('<svg xmlns="http://www.w3.org/2000/svg" width="612" height="792" '
            'font-family="DejaVu Sans" font-size="9" xml:space="preserve">\n'
            '<rect width="612" height="792" fill="white"/>\n' + "\n".join(lines) + "\n</svg>\n")

if len(sys.argv) > 2:
    segments = int(sys.argv[2])
    blobs = max(1, segments // 8)
    cols = int(math.ceil(math.sqrt(blobs * 612 / 792)))
    rows = int(math.ceil(blobs / cols))
    cw, ch = 540 / cols, 760 / rows
    rnd = random.Random(1)
    paths = []
    for b in range(blobs):
        cx = 36 + (b % cols + 0.5) * cw
        cy = 16 + (b // cols + 0.5) * ch
        r = 0.4 * min(cw, ch)
        pts = []
        for j in range(8):
            a = 2 * math.pi * j / 8
            rr = r * (0.6 + 0.4 * rnd.random())
            pts.append((cx + rr * math.cos(a), cy + rr * math.sin(a)))
        d = f"M{pts[0][0]:.2f},{pts[0][1]:.2f}"
        for j in range(8):
            p0, p1 = pts[j], pts[(j + 1) % 8]
            c1 = (p0[0] + (p1[0] - cx) * 0.2, p0[1] + (p1[1] - cy) * 0.2)
            c2 = (p1[0] + (p0[0] - cx) * 0.2, p1[1] + (p0[1] - cy) * 0.2)
            d += f"C{c1[0]:.2f},{c1[1]:.2f} {c2[0]:.2f},{c2[1]:.2f} {p1[0]:.2f},{p1[1]:.2f}"
        paths.append(f'<path d="{d}Z" fill="#{rnd.randrange(0x1000000):06x}"/>')
    with open(f"{out}/shapes_page.svg", "w") as f:
        f.write('<svg xmlns="http://www.w3.org/2000/svg" width="612" height="792">\n'
                '<rect width="612" height="792" fill="white"/>\n' + "\n".join(paths) + "\n</svg>\n")
