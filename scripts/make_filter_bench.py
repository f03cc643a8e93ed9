#!/usr/bin/env python3
"""Writes filter-heavy benchmark inputs (issue 28).

    scripts/make_filter_bench.py shadows IN.svg > OUT.svg
    scripts/make_filter_bench.py grid N [--plain] > OUT.svg

shadows: every run of 64 consecutive sibling <path> elements of IN (the
paper's tiger has no groups of its own) becomes a group with a drop shadow
(feDropShadow, 3 user units, offset 4 4), and the whole drawing one group
under a full-frame Gaussian blur (stdDeviation 1.5): the input made filter
heavy, to set against its own frame time.

grid: N x N small circles, each a group with a filter of its own (a blur
and an offset merged under the circle): independent filtered groups, the
case the paper's future work asks to filter in parallel. --plain writes the
same groups unfiltered.
"""
import re
import sys

from make_gradient_bench import insert_defs

PATH = re.compile(r"<path\b[^>]*/>")
SHADOW = ('<filter id="mpvg_shadow" x="-20%" y="-20%" width="140%" height="140%">'
          '<feDropShadow dx="4" dy="4" stdDeviation="3" flood-opacity="0.5"/></filter>'
          '<filter id="mpvg_blur" x="0" y="0" width="1" height="1"><feGaussianBlur stdDeviation="1.5"/></filter>')


def shadows(text):
    out, last, run = [], 0, []

    def flush():
        for i in range(0, len(run), 64):
            out.append('<g filter="url(#mpvg_shadow)">\n%s\n</g>' % "\n".join(run[i:i + 64]))
        run.clear()

    for m in PATH.finditer(text):
        between = text[last:m.start()]
        if between.strip():
            flush()
            out.append(between)
        run.append(m.group(0))
        last = m.end()
    flush()
    out.append(text[last:])
    body = "".join(out)
    # The whole drawing under one blur: the root's content in a group.
    start = body.index(">", body.index("<svg")) + 1
    end = body.rindex("</svg>")
    body = body[:start] + '<g filter="url(#mpvg_blur)">' + body[start:end] + "</g>" + body[end:]
    return insert_defs(body, [SHADOW])


def grid(n, plain):
    size = 1000
    step = size / n
    cells = []
    for i in range(n * n):
        x, y = (i % n + 0.5) * step, (i // n + 0.5) * step
        hue = (i * 37) % 360
        f = "" if plain else ' filter="url(#mpvg_glow)"'
        cells.append('<g%s><circle cx="%.2f" cy="%.2f" r="%.2f" fill="hsl(%d, 70%%, 50%%)"/></g>'
                     % (f, x, y, step * 0.3, hue))
    defs = ("" if plain else
            '<defs><filter id="mpvg_glow" x="-50%" y="-50%" width="200%" height="200%">'
            '<feGaussianBlur stdDeviation="4"/><feOffset dx="3" dy="3" result="o"/>'
            '<feMerge><feMergeNode in="o"/><feMergeNode in="SourceGraphic"/></feMerge></filter></defs>')
    return ('<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d">%s\n%s\n</svg>\n'
            % (size, size, size, size, defs, "\n".join(cells)))


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "shadows":
        with open(sys.argv[2], encoding="utf-8") as f:
            sys.stdout.write(shadows(f.read()))
    elif len(sys.argv) >= 3 and sys.argv[1] == "grid":
        sys.stdout.write(grid(int(sys.argv[2]), "--plain" in sys.argv[3:]))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
