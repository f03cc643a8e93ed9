#!/usr/bin/env python3
"""The README's opening picture, docs/antialiasing.png: testdata/resolution_chart.svg
rendered by svg2png (its default antialiasing) above rsvg-convert's render, each
with two 3x and 7.5x crops (the Siemens star's centre, the converging fan).

    python3 scripts/make_readme_picture.py [build/apps/svg2png]

Needs rsvg-convert (librsvg2-bin) and PIL (python3-pil). Look at the result
before committing it."""
import os
import subprocess
import sys
import tempfile

from PIL import Image, ImageDraw

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
svg2png = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "apps", "svg2png")
chart = os.path.join(root, "testdata", "resolution_chart.svg")
version = subprocess.run(["rsvg-convert", "--version"], capture_output=True, text=True).stdout.split()[-1]


def panel(path):
    im = Image.open(path).convert("RGB")
    p = Image.new("RGB", (1020, 300), "white")
    p.paste(im.crop((0, 0, 400, 300)), (0, 0))
    p.paste(im.crop((60, 100, 160, 200)).resize((300, 300), Image.NEAREST), (410, 0))
    p.paste(im.crop((290, 100, 330, 140)).resize((300, 300), Image.NEAREST), (720, 0))
    return p


with tempfile.TemporaryDirectory() as tmp:
    ours, theirs = os.path.join(tmp, "mpvg.png"), os.path.join(tmp, "rsvg.png")
    subprocess.run([svg2png, "-q", "-b", "white", chart, ours], check=True)
    subprocess.run(["rsvg-convert", "-b", "white", chart, "-o", theirs], check=True)
    out = Image.new("RGB", (1020, 636), "white")
    d = ImageDraw.Draw(out)
    d.text((4, 2), "mpvg svg2png (default: cardinal cubic B-spline, 512 samples a pixel)", fill="black")
    out.paste(panel(ours), (0, 16))
    d.text((4, 322), "rsvg-convert " + version, fill="black")
    out.paste(panel(theirs), (0, 336))
    out.save(os.path.join(root, "docs", "antialiasing.png"), optimize=True)
