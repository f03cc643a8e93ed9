#!/usr/bin/env python3
"""Builds testdata/fonts/MpvgTestVF.ttf: a tiny variable TrueType font made
for mpvg's tests (Debian 12 packages no variable font). One axis, wght
100..900 (default 400); glyphs for 'I', 'L', 'T', 'space': rectangles
whose stems are 40 units thin at wght 100 and 240 thick at 900, so a test
can tell the weights apart by their ink. Needs python3-fonttools; the font
is committed, so the tests do not run this.

    python3 scripts/make-test-font.py testdata/fonts/MpvgTestVF.ttf testdata/fonts/MpvgTestColor.ttf \
        testdata/fonts/MpvgTestSvg.ttf

The second font (colour glyphs: COLR version 0 and sbix) is described at
color_font() below, the third (OpenType SVG glyphs) at svg_font().
"""
import sys

from fontTools.fontBuilder import FontBuilder
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib.tables.TupleVariation import TupleVariation


def lsb(glyph):
    """The left side bearing that keeps the outline where it is drawn."""
    return min((x for x, _ in glyph.coordinates), default=0) if glyph.numberOfContours > 0 else 0


def rects(rs):
    pen = TTGlyphPen(None)
    for x0, y0, x1, y1 in rs:
        pen.moveTo((x0, y0))
        pen.lineTo((x0, y1))
        pen.lineTo((x1, y1))
        pen.lineTo((x1, y0))
        pen.closePath()
    return pen.glyph()


# Glyphs at the default (wght 400): stem 100 units.
STEM = 100
glyphs = {
    ".notdef": rects([(50, 0, 450, 700)]),
    "space": rects([]),
    "I": rects([(100, 0, 100 + STEM, 700)]),
    "L": rects([(100, 0, 100 + STEM, 700), (100, 0, 500, STEM)]),
    "T": rects([(250, 0, 250 + STEM, 700), (50, 700 - STEM, 550, 700)]),
}
advances = {".notdef": 500, "space": 300, "I": 300, "L": 550, "T": 600}
order = [".notdef", "space", "I", "L", "T"]

fb = FontBuilder(1000, isTTF=True)
fb.setupGlyphOrder(order)
fb.setupCharacterMap({0x20: "space", ord("I"): "I", ord("L"): "L", ord("T"): "T"})
fb.setupGlyf(glyphs)
fb.setupHorizontalMetrics({g: (advances[g], lsb(glyphs[g])) for g in order})
fb.setupHorizontalHeader(ascent=800, descent=-200)
fb.setupNameTable({"familyName": "Mpvg Test VF", "styleName": "Regular"})
fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200, sxHeight=500,
            sCapHeight=700, usWeightClass=400)
fb.setupPost()
fb.setupFvar(axes=[("wght", 100, 400, 900, "Weight")], instances=[])


def deltas(name, amount):
    """Per-point deltas that thicken every stem by `amount` (right/top edges move)."""
    g = glyphs[name]
    if g.numberOfContours <= 0:
        return [(0, 0)] * 4  # phantom points only
    coords = g.coordinates
    out = []
    # Each rectangle: points (x0,y0) (x0,y1) (x1,y1) (x1,y0); thicken along
    # its thin side (vertical stems: x1 moves; horizontal bars: y moves).
    for c in range(g.numberOfContours):
        pts = [coords[4 * c + k] for k in range(4)]
        (x0, y0), _, (x1, y1), _ = pts
        if x1 - x0 <= y1 - y0:  # a vertical stem: its right edge moves
            out += [(0, 0), (0, 0), (amount, 0), (amount, 0)]
        elif y0 == 0:  # a bar on the baseline: its top moves up
            out += [(0, 0), (0, amount), (0, amount), (0, 0)]
        else:  # a bar at the top: its bottom moves down
            out += [(0, -amount), (0, 0), (0, 0), (0, -amount)]
    return out + [(0, 0)] * 4  # phantom points


variations = {}
for name in order:
    variations[name] = [
        # At wght 900 stems are 240 thick, at 100 they are 40.
        TupleVariation({"wght": (0, 1, 1)}, deltas(name, 140)),
        TupleVariation({"wght": (-1, -1, 0)}, deltas(name, 60)),
    ]
# The negative region's deltas thin the stems: flip their sign.
for name in order:
    tv = variations[name][1]
    tv.coordinates = [(-x, -y) for x, y in tv.coordinates]
fb.setupGvar(variations)
fb.save(sys.argv[1] if len(sys.argv) > 1 else "MpvgTestVF.ttf")


def color_font(path):
    """testdata/fonts/MpvgTestColor.ttf, "Mpvg Test Color": 'O' is a COLR
    version 0 glyph of two layers (a red square from palette entry 0, under
    a foreground bar filled with the text's colour); 'E' has an sbix bitmap
    (8 x 8 pixels at 8 ppem: blue over green halves) and an outline box from
    y = -100 to 700, where the bitmap's lower left corner goes."""
    import io

    from fontTools.colorLib.builder import buildCOLR, buildCPAL
    from fontTools.ttLib.tables import sbixGlyph, sbixStrike
    from fontTools.ttLib import newTable
    from PIL import Image

    order = [".notdef", "space", "O", "E", "O.red", "O.bar"]
    g = {
        ".notdef": rects([(50, 0, 450, 700)]),
        "space": rects([]),
        "O": rects([(50, 0, 650, 600)]),
        "E": rects([(0, -100, 800, 700)]),
        "O.red": rects([(50, 0, 650, 600)]),
        "O.bar": rects([(250, 0, 450, 600)]),
    }
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", ord("O"): "O", ord("E"): "E"})
    fb.setupGlyf(g)
    fb.setupHorizontalMetrics({n: (700 if n != "E" else 800, lsb(g[n])) for n in order})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Mpvg Test Color", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    font = fb.font
    font["COLR"] = buildCOLR({"O": [("O.red", 0), ("O.bar", 0xFFFF)]})
    font["CPAL"] = buildCPAL([[(1.0, 0.0, 0.0, 1.0)]])
    im = Image.new("RGBA", (8, 8), (0, 0, 255, 255))
    for y in range(4, 8):
        for x in range(8):
            im.putpixel((x, y), (0, 160, 0, 255))
    png = io.BytesIO()
    im.save(png, format="PNG")
    sbix = newTable("sbix")
    strike = sbixStrike.Strike(ppem=8, resolution=72)
    for name in order:
        glyph = sbixGlyph.Glyph(glyphName=name)
        if name == "E":
            glyph = sbixGlyph.Glyph(glyphName=name, graphicType="png ", imageData=png.getvalue())
        strike.glyphs[name] = glyph
    sbix.strikes[8] = strike
    font["sbix"] = sbix
    font.save(path)


if len(sys.argv) > 2:
    color_font(sys.argv[2])


# svg_font()'s documents. Glyph 2 (U+E000) shares the first with glyph 3,
# which it does not draw: a gradient from defs filling a rectangle, a
# circle in currentColor, and a lime square outside any glyph element.
SVG_GLYPHS_2_3 = (
    '<svg xmlns="http://www.w3.org/2000/svg">'
    '<defs><linearGradient id="g" x1="0" x2="1">'
    '<stop offset="0" stop-color="#f00"/><stop offset="1" stop-color="#00f"/></linearGradient></defs>'
    '<g id="glyph2"><rect x="100" y="-700" width="500" height="700" fill="url(#g)"/>'
    '<circle cx="350" cy="-350" r="150" fill="currentColor"/></g>'
    '<rect id="glyph3" x="0" y="-500" width="300" height="300" fill="#808"/>'
    '<rect x="0" y="-1000" width="1000" height="1000" fill="lime"/>'
    '</svg>'
)
# Glyph 4 (U+E001), gzip-compressed: a viewBox of 500 units on the 1000
# units of the em square doubles it.
SVG_GLYPH_4 = (
    '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 500 500">'
    '<path id="glyph4" d="M50 -350 h250 v350 h-250 z" fill="#0a0" stroke="#000" stroke-width="10"/>'
    '</svg>'
)
# Glyph 5 (U+E002): an image file, which a glyph document may not read.
SVG_GLYPH_5 = (
    '<svg xmlns="http://www.w3.org/2000/svg">'
    '<image id="glyph5" href="x.png" y="-700" width="700" height="700"/>'
    '</svg>'
)


def svg_font(path):
    """testdata/fonts/MpvgTestSvg.ttf, "Mpvg Test SVG": U+E000 to U+E002
    (private use, so no other test falls back to them) have black box
    outlines and SVG glyphs (SVG_GLYPHS_2_3, SVG_GLYPH_4 and SVG_GLYPH_5
    above), all 700 units wide."""
    import gzip

    from fontTools.ttLib import newTable

    order = [".notdef", "space", "uniE000", "glyph3", "uniE001", "uniE002"]
    g = {
        ".notdef": rects([(50, 0, 450, 700)]),
        "space": rects([]),
        "uniE000": rects([(100, 0, 600, 700)]),
        "glyph3": rects([(0, 200, 300, 500)]),
        "uniE001": rects([(100, 0, 600, 700)]),
        "uniE002": rects([(100, 0, 600, 700)]),
    }
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", 0xE000: "uniE000", 0xE001: "uniE001", 0xE002: "uniE002"})
    fb.setupGlyf(g)
    fb.setupHorizontalMetrics({n: (700, lsb(g[n])) for n in order})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Mpvg Test SVG", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    svg = newTable("SVG ")
    # fontTools writes each document as given: the second one as gzip bytes.
    svg.docList = [
        (SVG_GLYPHS_2_3, 2, 3),
        (gzip.compress(SVG_GLYPH_4.encode(), mtime=0), 4, 4),
        (SVG_GLYPH_5, 5, 5),
    ]
    fb.font["SVG "] = svg
    fb.font.save(path)


if len(sys.argv) > 3:
    svg_font(sys.argv[3])
