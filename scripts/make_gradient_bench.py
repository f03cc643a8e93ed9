#!/usr/bin/env python3
"""Writes a gradient-heavy benchmark input: an SVG whose every solid fill
becomes a gradient of the same colour, alternately linear and radial.

    scripts/make_gradient_bench.py IN.svg > OUT.svg

Each filled path (fill="rgb(...)" or fill="#rrggbb") gets its own gradient in
objectBoundingBox units, from the fill colour through a lighter one (a third
of the way to white) back to a darker one (a fifth of the way to black):
every sample of every fill evaluates a gradient, and the image keeps the
original's look. Strokes keep their solid colours. Used by mpvg_bench to
compare the cost of per-sample paints with solid colours (the paper's tiger
as `tiger_gradients.svg`).
"""
import re
import sys

FILL = re.compile(r'fill="(rgb\((\d+),\s*(\d+),\s*(\d+)\)|#([0-9a-fA-F]{6}))"')


def parse_colour(m):
    if m.group(5):
        h = m.group(5)
        return tuple(int(h[i:i + 2], 16) for i in (0, 2, 4))
    return tuple(int(m.group(i)) for i in (2, 3, 4))


def hexc(c):
    return "#%02x%02x%02x" % tuple(max(0, min(255, round(v))) for v in c)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    text = open(sys.argv[1], encoding="utf-8").read()
    gradients = []

    def replace(m):
        c = parse_colour(m)
        i = len(gradients)
        light = tuple(v + (255 - v) / 3 for v in c)
        dark = tuple(v * 0.8 for v in c)
        stops = ('<stop offset="0" stop-color="%s"/><stop offset="0.5" stop-color="%s"/>'
                 '<stop offset="1" stop-color="%s"/>' % (hexc(c), hexc(light), hexc(dark)))
        if i % 2 == 0:
            gradients.append('<linearGradient id="g%d" x1="0" y1="0" x2="1" y2="1">%s</linearGradient>' % (i, stops))
        else:
            gradients.append('<radialGradient id="g%d" cx="0.5" cy="0.5" r="0.6" fx="0.35" fy="0.35">%s'
                             '</radialGradient>' % (i, stops))
        return 'fill="url(#g%d)"' % i

    text = FILL.sub(replace, text)
    sys.stdout.write(insert_defs(text, gradients))


def insert_defs(text, items):
    """The document with a <defs> of `items`: into its empty <defs>, or right
    after the root element's start tag."""
    defs = "<defs>\n" + "\n".join(items) + "\n</defs>"
    if re.search(r"<defs>\s*</defs>", text):
        return re.sub(r"<defs>\s*</defs>", lambda _: defs, text, count=1)
    return re.sub(r"(<svg[^>]*>)", lambda m: m.group(1) + "\n" + defs, text, count=1)


if __name__ == "__main__":
    main()
