#!/usr/bin/env python3
"""Builds testdata/fonts/MpvgTestVF.ttf: a tiny variable TrueType font made
for mpvg's tests (Debian 12 packages no variable font). One axis, wght
100..900 (default 400); glyphs for 'I', 'L', 'T', 'space': rectangles
whose stems are 40 units thin at wght 100 and 240 thick at 900, so a test
can tell the weights apart by their ink. Needs python3-fonttools; the font
is committed, so the tests do not run this.

    python3 scripts/make-test-font.py testdata/fonts/MpvgTestVF.ttf testdata/fonts/MpvgTestColor.ttf \
        testdata/fonts/MpvgTestSvg.ttf testdata/fonts/MpvgTestColrV1.ttf

The second font (colour glyphs: COLR version 0 and sbix) is described at
color_font() below, the third (OpenType SVG glyphs) at svg_font(), the
fourth (COLR version 1 paint graphs) at colr_v1_font().
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


# colr_v1_font()'s CPAL palette: 8-bit sRGB and alpha.
COLR_PALETTE = [
    (204, 26, 26, 255),   # 0 red
    (255, 200, 0, 255),   # 1 yellow
    (0, 90, 220, 255),    # 2 blue
    (20, 180, 60, 255),   # 3 green
    (200, 60, 160, 204),  # 4 magenta, alpha 0.8
    (30, 200, 220, 255),  # 5 cyan
    (120, 60, 20, 128),   # 6 brown, alpha 128/255
]
FOREGROUND = 0xFFFF  # the text's colour


def colr_v1_font(path):
    """testdata/fonts/MpvgTestColrV1.ttf, "Mpvg Test COLRv1": COLR version 1
    colour glyphs on private-use characters (U+E100 up), every paint format
    FreeType reads, for tests/test_color_glyph.cpp, which draws the same
    graphs with the numbers below. Units per em 1000; outlines (no
    characters) are rectangles, `tri` a triangle. Angles, scales, alphas and
    stop offsets are binary fractions that F2Dot14 stores exactly.

    U+E100 c_solid        layers: box in palette 0; bar in the foreground at alpha 0.5
    U+E101 c_linear       strip0..2 with linear gradients, pad / repeat / reflect
    U+E102 c_radial       the same with radial gradients (concentric, focal inside, cone)
    U+E103 c_sweep        the same with sweep gradients
    U+E104 c_glyph_paint  tri filled by a translated gradient; bar clipping layers
    U+E105 c_colr_glyph   c_solid scaled about a centre, then c_clip (its clip box applies)
    U+E106 c_transform    sq under each transform format
    U+E107 c_clip         box, tri and a bare solid over all, in a clip box
    U+E108 c_cycle        box, then itself again (a PaintColrGlyph cycle)
    U+E109 c_deep         five MULTIPLY composites, each the source of the next (more groups than fit)
    U+E10A c_var          box, then bar in a PaintVarSolid (FreeType 2.12 skips it)
    U+E10B c_v0           COLR version 0 layers only
    U+E110 + m            c_comp_<mode m>: rectB in palette 5 at alpha 0.75 (source)
                          composited with mode m onto rectA in palette 4 (backdrop)
    """
    from fontTools.colorLib.builder import buildCOLR, buildCPAL
    from fontTools.ttLib.tables import otTables as ot

    F = ot.PaintFormat

    def solid(index, alpha=1.0):
        return {"Format": F.PaintSolid, "PaletteIndex": index, "Alpha": alpha}

    def glyph(name, paint):
        return {"Format": F.PaintGlyph, "Glyph": name, "Paint": paint}

    def line(extend, stops):
        return {"Extend": extend,
                "ColorStop": [{"StopOffset": o, "PaletteIndex": i, "Alpha": a} for o, i, a in stops]}

    def linear(extend, stops, p0, p1, p2):
        return {"Format": F.PaintLinearGradient, "ColorLine": line(extend, stops),
                "x0": p0[0], "y0": p0[1], "x1": p1[0], "y1": p1[1], "x2": p2[0], "y2": p2[1]}

    def radial(extend, stops, c0, r0, c1, r1):
        return {"Format": F.PaintRadialGradient, "ColorLine": line(extend, stops),
                "x0": c0[0], "y0": c0[1], "r0": r0, "x1": c1[0], "y1": c1[1], "r1": r1}

    def sweep(extend, stops, c, start, end):
        return {"Format": F.PaintSweepGradient, "ColorLine": line(extend, stops),
                "centerX": c[0], "centerY": c[1], "startAngle": start, "endAngle": end}

    def translate(dx, dy, paint):
        return {"Format": F.PaintTranslate, "dx": dx, "dy": dy, "Paint": paint}

    def layers(*paints):
        return {"Format": F.PaintColrLayers, "Layers": list(paints)}

    def composite(mode, source, backdrop):
        return {"Format": F.PaintComposite, "SourcePaint": source, "CompositeMode": mode,
                "BackdropPaint": backdrop}

    def polygon(pts):
        pen = TTGlyphPen(None)
        pen.moveTo(pts[0])
        for p in pts[1:]:
            pen.lineTo(p)
        pen.closePath()
        return pen.glyph()

    outlines = {
        "strip0": rects([(50, 0, 330, 800)]),
        "strip1": rects([(360, 0, 640, 800)]),
        "strip2": rects([(670, 0, 950, 800)]),
        "box": rects([(100, 0, 900, 800)]),
        "bar": rects([(100, 300, 900, 500)]),
        "tri": polygon([(100, 0), (500, 800), (900, 0)]),
        "sq": rects([(0, 0, 200, 200)]),
        "rectA": rects([(100, 100, 600, 600)]),
        "rectB": rects([(400, 200, 900, 700)]),
    }
    colr = {
        "c_solid": layers(glyph("box", solid(0)), glyph("bar", solid(FOREGROUND, 0.5))),
        "c_linear": layers(
            glyph("strip0", linear("pad", [(0, 1, 1.0), (1, 2, 1.0)], (100, 200), (280, 600), (300, 100))),
            glyph("strip1", linear("repeat", [(0.125, 1, 1.0), (0.5, 3, 0.5), (0.875, 2, 1.0)],
                                   (400, 300), (600, 300), (450, 500))),
            glyph("strip2", linear("reflect", [(0.25, 2, 1.0), (0.5, 0, 0.25)], (700, 100), (920, 700), (700, 700))),
        ),
        "c_radial": layers(
            glyph("strip0", radial("pad", [(0, 1, 1.0), (1, 2, 1.0)], (190, 400), 20, (190, 400), 130)),
            glyph("strip1", radial("repeat", [(0, 1, 1.0), (0.5, 3, 1.0), (1, 2, 0.5)], (450, 300), 0, (500, 450), 100)),
            glyph("strip2", radial("reflect", [(0, 5, 1.0), (1, 6, 1.0)], (700, 200), 30, (900, 600), 80)),
        ),
        "c_sweep": layers(
            glyph("strip0", sweep("pad", [(0, 1, 1.0), (1, 2, 1.0)], (190, 400), 45, 135)),
            glyph("strip1", sweep("repeat", [(0, 1, 1.0), (0.5, 3, 0.5), (1, 2, 1.0)], (500, 400), 0, 90)),
            glyph("strip2", sweep("reflect", [(0.25, 5, 1.0), (0.75, 0, 1.0)], (810, 400), 270, 180)),
        ),
        "c_glyph_paint": layers(
            glyph("tri", translate(100, 0, linear("pad", [(0, 1, 1.0), (1, 2, 1.0)], (0, 0), (800, 0), (0, 800)))),
            glyph("bar", layers(solid(3, 0.75), glyph("rectA", solid(4)))),
        ),
        "c_colr_glyph": layers(
            {"Format": F.PaintScaleAroundCenter, "scaleX": 0.5, "scaleY": 0.75, "centerX": 500, "centerY": 400,
             "Paint": {"Format": F.PaintColrGlyph, "Glyph": "c_solid"}},
            {"Format": F.PaintColrGlyph, "Glyph": "c_clip"},
        ),
        "c_transform": layers(
            {"Format": F.PaintTransform, "Paint": glyph("sq", solid(0, 0.75)),
             "Transform": {"xx": 1.0, "yx": 0.25, "xy": 0.5, "yy": 1.0, "dx": 50, "dy": 550}},
            translate(300, 550, glyph("sq", solid(1, 0.75))),
            {"Format": F.PaintScale, "scaleX": 1.5, "scaleY": 0.5, "Paint": glyph("sq", solid(2, 0.75))},
            {"Format": F.PaintScaleAroundCenter, "scaleX": 0.5, "scaleY": 1.25, "centerX": 600, "centerY": 100,
             "Paint": glyph("sq", solid(3, 0.75))},
            {"Format": F.PaintScaleUniform, "scale": 0.75, "Paint": glyph("sq", solid(4))},
            {"Format": F.PaintScaleUniformAroundCenter, "scale": 1.25, "centerX": 1000, "centerY": 0,
             "Paint": glyph("sq", solid(5, 0.75))},
            {"Format": F.PaintRotate, "angle": 45, "Paint": glyph("sq", solid(6))},
            translate(600, 500, {"Format": F.PaintRotateAroundCenter, "angle": -22.5, "centerX": 100, "centerY": 100,
                                 "Paint": glyph("sq", solid(0, 0.5))}),
            translate(700, 0, {"Format": F.PaintSkew, "xSkewAngle": 22.5, "ySkewAngle": 0,
                               "Paint": glyph("sq", solid(1))}),
            translate(400, 300, {"Format": F.PaintSkewAroundCenter, "xSkewAngle": 11.25, "ySkewAngle": -33.75,
                                 "centerX": 100, "centerY": 100, "Paint": glyph("sq", solid(2, 0.75))}),
        ),
        "c_clip": layers(glyph("box", solid(1)), glyph("tri", solid(2)), solid(6)),
        "c_cycle": layers(glyph("box", solid(1)), {"Format": F.PaintColrGlyph, "Glyph": "c_cycle"}),
        "c_var": layers(glyph("box", solid(1)),
                        glyph("bar", {"Format": F.PaintVarSolid, "PaletteIndex": 2, "Alpha": 1.0,
                                      "VarIndexBase": 0xFFFFFFFF})),
        "c_v0": [("box", 0), ("bar", FOREGROUND)],
    }
    deep = glyph("rectA", solid(1))
    for i in range(5):  # each source is the previous composite: two groups deeper each time
        deep = composite("multiply", deep, glyph("rectB", solid(i, 0.75)))
    colr["c_deep"] = deep
    modes = list(ot.CompositeMode.__members__)
    for m in modes:
        colr["c_comp_" + m.lower()] = composite(m.lower(), glyph("rectB", solid(5, 0.75)), glyph("rectA", solid(4)))

    named = ["c_solid", "c_linear", "c_radial", "c_sweep", "c_glyph_paint", "c_colr_glyph", "c_transform",
             "c_clip", "c_cycle", "c_deep", "c_var", "c_v0"]
    cmap = {0xE100 + i: n for i, n in enumerate(named)}
    cmap.update({0xE110 + i: "c_comp_" + m.lower() for i, m in enumerate(modes)})
    order = [".notdef", "space"] + list(outlines) + named + ["c_comp_" + m.lower() for m in modes]
    g = {".notdef": rects([(50, 0, 450, 700)]), "space": rects([])}
    g.update(outlines)
    for n in order:
        if n not in g:
            g[n] = rects([(100, 0, 900, 800)])  # the colour glyphs' own outline: a fallback box
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x20: "space", **cmap})
    fb.setupGlyf(g)
    fb.setupHorizontalMetrics({n: (1000 if n not in (".notdef", "space") else 500, lsb(g[n])) for n in order})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "Mpvg Test COLRv1", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, sTypoDescender=-200, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    fb.font["COLR"] = buildCOLR(colr, glyphMap=fb.font.getReverseGlyphMap(),
                                clipBoxes={"c_clip": (200, 100, 800, 600)})
    fb.font["CPAL"] = buildCPAL([[tuple(v / 255 for v in c) for c in COLR_PALETTE]])
    # The same bytes on every run: fixed timestamps (2024-01-01).
    fb.font["head"].created = fb.font["head"].modified = 3786912000
    fb.font.recalcTimestamp = False
    fb.font.save(path)


if len(sys.argv) > 4:
    colr_v1_font(sys.argv[4])
