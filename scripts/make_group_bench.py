#!/usr/bin/env python3
"""Writes a group-heavy benchmark input: an SVG whose paths are wrapped in
nested groups, every group masked.

    scripts/make_group_bench.py IN.svg > OUT.svg

Every run of consecutive sibling <path> elements is cut into groups of 64
paths, each of those into groups of 16, each of those into groups of 4
(three levels of nesting), and every group gets mask="url(#...)" with a
luminance mask made of one white rectangle over the whole canvas. Every
sample of every path then goes through three groups and three masks (four
stack levels with the mask's own), yet the image is the input's: the
input itself is the same scene flattened by hand. Used by mpvg_bench to
compare the cost of groups and masks with a flat scene (the paper's tiger
as `tiger_groups.svg`).
"""
import re
import sys

from make_gradient_bench import insert_defs

PATH = re.compile(r"<path\b[^>]*/>")
SIZES = (64, 16, 4)
MASK = ('<mask id="mpvg_all" maskUnits="userSpaceOnUse" x="-100000" y="-100000" width="200000" '
        'height="200000"><rect x="-100000" y="-100000" width="200000" height="200000" fill="white"/></mask>')


def wrap(paths, level):
    """The paths as nested groups from `level` down."""
    if level == len(SIZES):
        return "\n".join(paths)
    size = SIZES[level]
    out = []
    for i in range(0, len(paths), size):
        out.append('<g mask="url(#mpvg_all)">\n%s\n</g>' % wrap(paths[i:i + size], level + 1))
    return "\n".join(out)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    text = open(sys.argv[1], encoding="utf-8").read()
    # Runs of sibling paths: consecutive matches with only whitespace between.
    out, run, last = [], [], 0
    for m in PATH.finditer(text):
        between = text[last:m.start()]
        if run and between.strip():
            out.append(wrap(run, 0))
            run = []
        if not run:
            out.append(between)
        run.append(m.group(0))
        last = m.end()
    if run:
        out.append(wrap(run, 0))
    out.append(text[last:])
    sys.stdout.write(insert_defs("".join(out), [MASK]))


if __name__ == "__main__":
    main()
