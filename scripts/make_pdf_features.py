#!/usr/bin/env python3
"""Writes the PDF test inputs, hand-written object by object:

    python3 scripts/make_pdf_features.py        (from anywhere; Python 3 stdlib)

- testdata/pdf/features/NAME.pdf: one feature per file, for
  tests/test_pdf_golden.cpp (each beside its reviewed NAME.png golden, or
  listed there as pending).
- testdata/pdf/three-pages*.pdf, testdata/pdf/truncated.pdf: the error
  cases of tests/test_cli_pdf.sh (see testdata/pdf/README.md).

Content streams are uncompressed and binary data (images, mesh shadings,
sampled functions) is ASCIIHex-encoded, so every file reads as text.
The output is committed; the tests do not need Python. The writer is
deterministic: running it again gives the same bytes.
"""
import math
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
FEATURES = os.path.join(ROOT, "testdata", "pdf", "features")
PDFDIR = os.path.join(ROOT, "testdata", "pdf")

HELVETICA = "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>"


class Pdf:
    """Objects numbered from 1 in the order they are reserved or added;
    write() lays them out with a cross-reference table of exact offsets."""

    def __init__(self):
        self.objects = []

    def reserve(self):
        self.objects.append(None)
        return len(self.objects)

    def set(self, num, body):
        self.objects[num - 1] = body.encode("latin-1") if isinstance(body, str) else body

    def add(self, body):
        num = self.reserve()
        self.set(num, body)
        return num

    def add_stream(self, entries, data):
        data = data.encode("latin-1") if isinstance(data, str) else data
        head = "<< %s /Length %d >>\nstream\n" % (entries, len(data))
        return self.add(head.encode("latin-1") + data + b"\nendstream")

    def add_hex_stream(self, entries, data):
        """Binary data as an ASCIIHexDecode stream, 32 bytes a line."""
        text = "\n".join(data[i:i + 32].hex() for i in range(0, len(data), 32)) + ">"
        return self.add_stream(entries + " /Filter /ASCIIHexDecode", text)

    def bytes(self, root):
        out = b"%PDF-1.7\n%\xe2\xe3\xcf\xd3\n"
        offsets = []
        for i, body in enumerate(self.objects):
            assert body is not None, "object %d reserved but never set" % (i + 1)
            offsets.append(len(out))
            out += b"%d 0 obj\n" % (i + 1) + body + b"\nendobj\n"
        xref = len(out)
        out += b"xref\n0 %d\n0000000000 65535 f \n" % (len(self.objects) + 1)
        for o in offsets:
            out += b"%010d 00000 n \n" % o
        out += b"trailer\n<< /Size %d /Root %d 0 R >>\nstartxref\n%d\n%%%%EOF\n" % (len(self.objects) + 1, root, xref)
        return out


def ref(num):
    return "%d 0 R" % num


def fmt(v):
    if isinstance(v, float):
        s = ("%.4f" % v).rstrip("0").rstrip(".")
        return s if s not in ("-0", "") else "0"
    return str(v)


def one_page(name, size, content, resources="", extra="", objects=None, catalog_extra=None):
    """Writes features/NAME.pdf: one page. `objects(pdf)` adds objects the
    page refers to and returns a dict of their numbers, which `resources`,
    `extra` and `catalog_extra` use as %(key)s."""
    numbers = {}

    def make(pdf):
        if objects:
            numbers.update(objects(pdf))
        return size, content, resources % numbers, extra % numbers

    pdf = Pdf()
    catalog = pdf.reserve()
    tree = pdf.reserve()
    page = pdf.reserve()
    box, content_, resources_, extra_ = make(pdf)
    if len(box) == 2:
        box = (0, 0) + tuple(box)
    contents = pdf.add_stream("", content_)
    pdf.set(page, "<< /Type /Page /Parent %s /MediaBox [%s] /Contents %s /Resources << %s >> %s>>" %
            (ref(tree), " ".join(fmt(v) for v in box), ref(contents), resources_, extra_ + " " if extra_ else ""))
    pdf.set(tree, "<< /Type /Pages /Kids [%s] /Count 1 >>" % ref(page))
    cat_extra = (catalog_extra % numbers) if catalog_extra else ""
    pdf.set(catalog, "<< /Type /Catalog /Pages %s %s>>" % (ref(tree), cat_extra + " " if cat_extra else ""))
    write(os.path.join(FEATURES, name + ".pdf"), pdf.bytes(catalog))


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


def lines(*parts):
    return "\n".join(parts) + "\n"


# Geometry helpers, returning content-stream operators.

def circle(cx, cy, r):
    """A circle of four cubics, counter-clockwise."""
    k = 0.5523 * r
    return ("%s %s m %s %s %s %s %s %s c %s %s %s %s %s %s c %s %s %s %s %s %s c %s %s %s %s %s %s c h" %
            tuple(fmt(float(v)) for v in (
                cx + r, cy,
                cx + r, cy + k, cx + k, cy + r, cx, cy + r,
                cx - k, cy + r, cx - r, cy + k, cx - r, cy,
                cx - r, cy - k, cx - k, cy - r, cx, cy - r,
                cx + k, cy - r, cx + r, cy - k, cx + r, cy)))


def star(cx, cy, r):
    """A pentagram: one self-intersecting contour whose centre winds twice."""
    pts = [(cx + r * math.sin(math.radians(144 * i)), cy + r * math.cos(math.radians(144 * i))) for i in range(5)]
    ops = ["%s %s m" % (fmt(pts[0][0]), fmt(pts[0][1]))]
    ops += ["%s %s l" % (fmt(x), fmt(y)) for x, y in pts[1:]]
    return " ".join(ops) + " h"


def stripes(x, y, w, h, step, colors, vertical=True):
    """Stripes `step` wide over the rectangle, cycling through `colors`."""
    ops = []
    n = int(math.ceil((w if vertical else h) / step))
    for i in range(n):
        ops.append("%s rg" % colors[i % len(colors)])
        if vertical:
            ops.append("%s %s %s %s re f" % (fmt(x + i * step), fmt(y), fmt(min(step, w - i * step)), fmt(h)))
        else:
            ops.append("%s %s %s %s re f" % (fmt(x), fmt(y + i * step), fmt(w), fmt(min(step, h - i * step))))
    return "\n".join(ops)


RAINBOW = ["1 0 0", "1 0.6 0", "1 1 0", "0 0.8 0", "0 0.8 1", "0 0 1", "0.6 0 1", "1 0 0.6"]


# The features.

def fill_rules():
    # The same pentagram with f, f*, B and B* (fill then stroke), one per
    # quadrant: nonzero fills the centre (winding 2), even-odd leaves it.
    content = lines(
        "0 0 0 RG 3 w 1 j",
        "0.85 0 0 rg", star(50, 150, 42), "f",
        "0 0 0.85 rg", star(150, 150, 42), "f*",
        "0 0.6 0 rg", star(50, 50, 42), "B",
        "0.9 0.6 0 rg", star(150, 50, 42), "B*",
    )
    one_page("fill-rules", (200, 200), content)


def clips():
    # Top left: a circle (W n) over vertical stripes. Top right: an
    # even-odd ring (W* n: two nested squares of the same direction).
    # Bottom left: nested clips, a diagonal square inside a square, then
    # after Q only the outer one. Bottom right: glyph outlines as the clip
    # (text render mode 7, filled, stroked and added to the clip).
    content = lines(
        "q", circle(50, 150, 38), "W n", stripes(0, 100, 100, 100, 10, ["1 0 0", "0 0 1"]), "Q",
        "q 110 110 80 80 re 130 130 40 40 re W* n", stripes(100, 100, 100, 100, 10, ["0 0.7 0", "1 0.8 0"], False), "Q",
        "q 10 10 80 80 re W n",
        "q 50 15 m 85 50 l 50 85 l 15 50 l h W n 0.9 0.5 0 rg 0 0 100 100 re f Q",
        "0 0.5 1 rg 0 45 100 10 re f",
        "Q",
        "q BT /F1 64 Tf 7 Tr 2 w 0 0 0 RG 0.5 0.5 0.5 rg 108 30 Td (Ok) Tj ET",
        stripes(100, 0, 100, 100, 6, ["1 0 0", "0 0.6 0", "0 0 1"]), "Q",
    )
    one_page("clips", (200, 200), content, "/Font << /F1 %s >>" % HELVETICA)


def dashes():
    rows = []
    # Dash patterns and phases (butt caps), on lines 180 pt long.
    for y, width, cap, pattern in [(210, 4, 0, "[12 6] 0"), (198, 4, 0, "[12 6] 9"), (184, 6, 1, "[0 12] 0"),
                                   (170, 4, 2, "[10 6 2 6] 0"), (158, 3, 0, "[] 0")]:
        rows.append("%d w %d J %s d 10 %d m 190 %d l S" % (width, cap, pattern, y, y))
    # Caps on thick solid lines: butt, round, square (thin guides show the
    # line's ends).
    for i, cap in enumerate((0, 1, 2)):
        x = 20 + 60 * i
        rows.append("0 0 0.8 RG 12 w %d J [] 0 d %d 140 m %d 140 l S" % (cap, x, x + 30))
    rows.append("1 0 0 RG 0.5 w 0 J 20 130 m 20 150 l 50 130 m 50 150 l 80 130 m 80 150 l 110 130 m 110 150 l "
                "140 130 m 140 150 l 170 130 m 170 150 l S")
    # Joins: miter, round, bevel on a zigzag.
    for i, join in enumerate((0, 1, 2)):
        x = 15 + 62 * i
        rows.append("0 0.5 0 RG 10 w 0 J %d j %d 90 m %d 120 l %d 90 l %d 120 l S" % (join, x, x + 15, x + 30, x + 45))
    # Miter limit: a sharp (about 23 degree) corner with limits 10 (mitred)
    # and 2 (bevelled).
    for i, limit in enumerate((10, 2)):
        x = 20 + 50 * i
        rows.append("0.6 0 0.6 RG 6 w 0 j %d M %d 50 m %d 75 l %d 50 l S" % (limit, x, x + 20, x + 10))
    # Width 0: the thinnest line the device can draw, also under a scale.
    rows.append("0 0 0 RG 0 w 0 J 10 M 120 50 m 190 75 l S")
    rows.append("q 3 0 0 3 0 0 cm 40 18 m 63 18 l S Q")
    # A non-uniform CTM: the pen is an ellipse (4 x 1), stroked and dashed.
    rows.append("q 4 0 0 1 0 0 cm 0.8 0.3 0 RG 2 w [] 0 d %s S Q" % circle(12, 20, 14))
    rows.append("q 4 0 0 1 0 0 cm 0 0.4 0.8 RG 1.5 w [4 3] 0 d %s S Q" % circle(37, 20, 14))
    content = "0 0 0 RG\n" + "\n".join(rows) + "\n"
    one_page("dashes", (200, 220), content)


def text_render_modes():
    # "Ag" in modes 0 to 7: blue fill, red stroke (1.5 pt). Modes 4 to 7
    # add the glyphs to the clip; green and orange stripes are then painted
    # over the text's box, inside q/Q. A grey baseline marks each row.
    ops = ["/F1 40 Tf 1.5 w 0 0 1 rg 1 0 0 RG"]
    for mode in range(8):
        x = 10 if mode < 4 else 130
        y = 160 - 45 * (mode % 4)
        ops.append("q 0.7 g 0 0 0 RG 0.5 w %d %d m %d %d l S Q" % (x, y - 1, x + 100, y - 1))
        if mode < 4:
            ops.append("BT %d Tr %d %d Td (Ag) Tj ET" % (mode, x, y))
        else:
            ops.append("q BT %d Tr %d %d Td (Ag) Tj ET" % (mode, x, y))
            ops.append(stripes(x, y - 10, 100, 45, 5, ["0 0.7 0", "1 0.6 0"]))
            ops.append("Q")
    one_page("text-render-modes", (240, 200), "\n".join(ops) + "\n", "/Font << /F1 %s >>" % HELVETICA)


def shading_axial():
    # Red to blue along x from 60 to 140 in a wider box, without Extend
    # (top: white beyond the axis) and with it (middle); bottom: a stitched
    # red-yellow-blue ramp along a diagonal, extended, as a shading pattern
    # filling a circle.
    def objects(pdf):
        lin = "/FunctionType 2 /Domain [0 1] /C0 [1 0 0] /C1 [0 0 1] /N 1"
        stitch = ("/FunctionType 3 /Domain [0 1] /Bounds [0.5] /Encode [0 1 0 1] /Functions ["
                  "<< /FunctionType 2 /Domain [0 1] /C0 [1 0 0] /C1 [1 1 0] /N 1 >> "
                  "<< /FunctionType 2 /Domain [0 1] /C0 [1 1 0] /C1 [0 0 1] /N 1 >>]")
        a = pdf.add("<< /ShadingType 2 /ColorSpace /DeviceRGB /Coords [60 0 140 0] /Function << %s >> >>" % lin)
        b = pdf.add("<< /ShadingType 2 /ColorSpace /DeviceRGB /Coords [60 0 140 0] /Function << %s >> "
                    "/Extend [true true] >>" % lin)
        c = pdf.add("<< /ShadingType 2 /ColorSpace /DeviceRGB /Coords [70 10 130 60] /Function << %s >> "
                    "/Extend [true true] >>" % stitch)
        p = pdf.add("<< /Type /Pattern /PatternType 2 /Shading %s >>" % ref(c))
        return {"a": ref(a), "b": ref(b), "p": ref(p)}

    content = lines(
        "q 10 140 180 50 re W n /A sh Q",
        "q 10 80 180 50 re W n /B sh Q",
        "/Pattern cs /P scn", circle(100, 38, 32), "f",
    )
    one_page("shading-axial", (200, 200), content, "/Shading << /A %(a)s /B %(b)s >> /Pattern << /P %(p)s >>",
             objects=objects)


def shading_radial():
    # Quadrants: concentric (r 0 to 35) without Extend, the same extended,
    # a focal case (a point circle off the centre, inside the outer one),
    # and two disjoint circles (a cone), extended.
    def objects(pdf):
        fn = "<< /FunctionType 2 /Domain [0 1] /C0 [1 1 0] /C1 [0 0 0.8] /N 1 >>"
        out = {}
        for key, coords, extend in [("a", "50 150 0 50 150 35", ""), ("b", "150 150 0 150 150 35", "[true true]"),
                                    ("c", "35 40 0 50 50 40", "[true true]"),
                                    ("d", "125 50 8 170 50 20", "[true true]")]:
            out[key] = ref(pdf.add("<< /ShadingType 3 /ColorSpace /DeviceRGB /Coords [%s] /Function %s %s>>" %
                                   (coords, fn, "/Extend " + extend + " " if extend else "")))
        return out

    content = lines(
        "q 5 105 90 90 re W n /A sh Q",
        "q 105 105 90 90 re W n /B sh Q",
        "q 5 5 90 90 re W n /C sh Q",
        "q 105 5 90 90 re W n /D sh Q",
    )
    one_page("shading-radial", (200, 200), content, "/Shading << /A %(a)s /B %(b)s /C %(c)s /D %(d)s >>",
             objects=objects)


def shading_function():
    # Type 1 shadings. Top left: a PostScript (type 4) function
    # f(x, y) = (x, y, 1 - x) on [0 1]^2. Top right: a sampled (type 0)
    # function, 2 x 2 samples red, green, blue, yellow, interpolated.
    # Bottom: distance from the origin, f(x, y) = (r, r, 1) with
    # r = sqrt(x^2 + y^2) clipped to 1, on [-1 1]^2 stretched to 180 x 80.
    def objects(pdf):
        f1 = pdf.add_stream("/FunctionType 4 /Domain [0 1 0 1] /Range [0 1 0 1 0 1]", "{ 1 index 1 exch sub }")
        f2 = pdf.add_hex_stream("/FunctionType 0 /Domain [0 1 0 1] /Range [0 1 0 1 0 1] /Size [2 2] "
                                "/BitsPerSample 8", bytes([255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 0]))
        f3 = pdf.add_stream("/FunctionType 4 /Domain [-1 1 -1 1] /Range [0 1 0 1 0 1]",
                            "{ dup mul exch dup mul add sqrt dup 1 gt { pop 1 } if dup 1 }")
        a = pdf.add("<< /ShadingType 1 /ColorSpace /DeviceRGB /Domain [0 1 0 1] /Matrix [80 0 0 80 10 110] "
                    "/Function %s >>" % ref(f1))
        b = pdf.add("<< /ShadingType 1 /ColorSpace /DeviceRGB /Domain [0 1 0 1] /Matrix [80 0 0 80 110 110] "
                    "/Function %s >>" % ref(f2))
        c = pdf.add("<< /ShadingType 1 /ColorSpace /DeviceRGB /Domain [-1 1 -1 1] /Matrix [90 0 0 40 100 50] "
                    "/Function %s >>" % ref(f3))
        return {"a": ref(a), "b": ref(b), "c": ref(c)}

    one_page("shading-function", (200, 200), "/A sh\n/B sh\n/C sh\n", "/Shading << /A %(a)s /B %(b)s /C %(c)s >>",
             objects=objects)


def mesh_data(values, layout):
    """Packs mesh values: `layout` is a list of bit widths repeated over
    `values` (flags 8, coordinates 16, components 8: all byte aligned)."""
    out = bytearray()
    for i, v in enumerate(values):
        bits = layout[i % len(layout)]
        out += int(v).to_bytes(bits // 8, "big")
    return bytes(out)


def coord(v):
    """A coordinate of 0..200 pt as 16 bits with /Decode [0 200 ...]."""
    return round(v / 200 * 65535)


def mesh_shadings():
    mesh16 = "/BitsPerCoordinate 16 /BitsPerComponent 8 /Decode [0 200 0 200 0 1 0 1 0 1]"
    R, G, B, Y, C, M, W, K = ([255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0], [0, 255, 255], [255, 0, 255],
                              [255, 255, 255], [40, 40, 40])

    def vertex(flag, x, y, color, with_flag=True):
        return ((flag.to_bytes(1, "big") if with_flag else b"") + coord(x).to_bytes(2, "big") +
                coord(y).to_bytes(2, "big") + bytes(color))

    # Type 4: a strip of three triangles (flags 0 0 0, then 1, then 2) and
    # a separate one.
    data = b"".join([vertex(0, 20, 20, R), vertex(0, 100, 20, G), vertex(0, 60, 100, B), vertex(1, 140, 100, Y),
                     vertex(2, 180, 20, C),
                     vertex(0, 30, 120, M), vertex(0, 170, 120, W), vertex(0, 100, 190, K)])

    def mesh_page(name, entries, data):
        def objects(pdf):
            return {"s": ref(pdf.add_hex_stream("/ShadingType %s /ColorSpace /DeviceRGB %s" % (entries, mesh16),
                                                data))}
        one_page(name, (200, 200), "/S sh\n", "/Shading << /S %(s)s >>", objects=objects)

    mesh_page("mesh-type4", "4 /BitsPerFlag 8", data)

    # Type 5: a lattice of 4 x 3 vertices, rows bent.
    colors = [R, Y, G, C, M, W, K, B, B, C, Y, R]
    data = b""
    for j in range(3):
        for i in range(4):
            x = 20 + 53 * i + (10 if j == 1 else 0)
            y = 20 + 80 * j + 15 * math.sin(i)
            data += vertex(0, x, y, colors[4 * j + i], with_flag=False)
    mesh_page("mesh-type5", "5 /VerticesPerRow 4", data)

    def point(x, y):
        return coord(x).to_bytes(2, "big") + coord(y).to_bytes(2, "big")

    # Type 6: a Coons patch with curved sides (12 points counter-clockwise
    # from the bottom left: up the left side, along the top, down the
    # right, back along the bottom), then one sharing its top side (flag 1:
    # 8 points, 2 colours), then a separate one.
    p1 = [(20, 20), (10, 47), (30, 73), (20, 100), (47, 110), (73, 90), (100, 100), (110, 73), (90, 47), (100, 20),
          (73, 10), (47, 30)]
    p2 = [(110, 130), (90, 160), (100, 190), (73, 180), (47, 200), (20, 190), (30, 160), (10, 130)]
    p3 = [(120, 20), (140, 60), (100, 100), (130, 150), (150, 140), (170, 160), (190, 150), (170, 100), (190, 60),
          (180, 20), (160, 30), (140, 10)]
    data = (b"\0" + b"".join(point(*p) for p in p1) + bytes(R + G + B + Y) +
            b"\1" + b"".join(point(*p) for p in p2) + bytes(M + C) +
            b"\0" + b"".join(point(*p) for p in p3) + bytes(W + K + R + C))
    mesh_page("mesh-type6", "6 /BitsPerFlag 8", data)

    # Type 7: one tensor-product patch, the square 20..180 with straight
    # sides whose four inner control points are pulled apart (12 boundary
    # points as in type 6, then p11 p12 p22 p21).
    b = [(20, 20), (20, 73), (20, 127), (20, 180), (73, 180), (127, 180), (180, 180), (180, 127), (180, 73), (180, 20),
         (127, 20), (73, 20)]
    inner = [(110, 40), (40, 110), (90, 160), (160, 90)]
    data = b"\0" + b"".join(point(*p) for p in b + inner) + bytes(R + G + B + Y)
    mesh_page("mesh-type7", "7 /BitsPerFlag 8", data)


# An 8 x 8 arrow pointing up and to the right, one bit a pixel (1 set).
ARROW = [0b00011111, 0b00000111, 0b00001011, 0b00010011, 0b00100001, 0b01000000, 0b10000000, 0b00000000]
# A 4 x 4 RGB image: rows red green blue white / yellow cyan magenta black /
# a grey ramp / orange purple teal pink.
RGB4 = bytes([255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255,
              255, 255, 0, 0, 255, 255, 255, 0, 255, 0, 0, 0,
              0, 0, 0, 85, 85, 85, 170, 170, 170, 255, 255, 255,
              255, 128, 0, 128, 0, 128, 0, 128, 128, 255, 150, 200])


def image_masks():
    # Stencil masks: the same 8 x 8 bits, painted red where a bit is 0
    # (the default /Decode [0 1]) and blue where it is 1 (/Decode [1 0]);
    # a grey checkerboard shows what stays unpainted.
    def objects(pdf):
        entries = "/Type /XObject /Subtype /Image /Width 8 /Height 8 /ImageMask true /BitsPerComponent 1"
        a = pdf.add_hex_stream(entries, bytes(ARROW))
        b = pdf.add_hex_stream(entries + " /Decode [1 0]", bytes(ARROW))
        return {"a": ref(a), "b": ref(b)}

    content = lines(
        "0.8 g", *["%d %d 10 10 re" % (x, y) for x in range(0, 200, 20) for y in range(0, 100, 20)], "f",
        "0.8 g", *["%d %d 10 10 re" % (x, y) for x in range(10, 200, 20) for y in range(10, 100, 20)], "f",
        "q 1 0 0 rg 80 0 0 80 10 10 cm /A Do Q",
        "q 0 0 1 rg 80 0 0 80 110 10 cm /B Do Q",
    )
    one_page("image-mask", (200, 100), content, "/XObject << /A %(a)s /B %(b)s >>", objects=objects)


def checker(w, h, step=10):
    ops = ["0.75 g"]
    for y in range(0, h, step):
        for x in range(0, w, step):
            if (x // step + y // step) % 2 == 0:
                ops.append("%d %d %d %d re" % (x, y, step, step))
    ops.append("f")
    return "\n".join(ops)


def image_smask():
    # The 4 x 4 RGB image with a 4 x 4 soft mask whose alpha falls from 1
    # (left) to 0 (right), drawn large over a checkerboard.
    def objects(pdf):
        mask = pdf.add_hex_stream("/Type /XObject /Subtype /Image /Width 4 /Height 4 /ColorSpace /DeviceGray "
                                  "/BitsPerComponent 8", bytes([255, 170, 85, 0] * 4))
        im = pdf.add_hex_stream("/Type /XObject /Subtype /Image /Width 4 /Height 4 /ColorSpace /DeviceRGB "
                                "/BitsPerComponent 8 /SMask %s" % ref(mask), RGB4)
        return {"i": ref(im)}

    one_page("image-smask", (200, 200), checker(200, 200) + "\nq 160 0 0 160 20 20 cm /I Do Q\n",
             "/XObject << /I %(i)s >>", objects=objects)


def image_decode():
    # The 4 x 4 RGB image as it is (left) and with /Decode [1 0 1 0 1 0]
    # (right: the negative).
    def objects(pdf):
        e = "/Type /XObject /Subtype /Image /Width 4 /Height 4 /ColorSpace /DeviceRGB /BitsPerComponent 8"
        return {"a": ref(pdf.add_hex_stream(e, RGB4)),
                "b": ref(pdf.add_hex_stream(e + " /Decode [1 0 1 0 1 0]", RGB4))}

    one_page("image-decode", (200, 100), "q 80 0 0 80 10 10 cm /A Do Q\nq 80 0 0 80 110 10 cm /B Do Q\n",
             "/XObject << /A %(a)s /B %(b)s >>", objects=objects)


def image_interpolate():
    # The 4 x 4 RGB image magnified 20 times without /Interpolate (left:
    # MuPDF draws the pixels as squares) and with /Interpolate true (right:
    # smoothed).
    def objects(pdf):
        e = "/Type /XObject /Subtype /Image /Width 4 /Height 4 /ColorSpace /DeviceRGB /BitsPerComponent 8"
        return {"a": ref(pdf.add_hex_stream(e, RGB4)),
                "b": ref(pdf.add_hex_stream(e + " /Interpolate true", RGB4))}

    one_page("image-interpolate", (200, 100), "q 80 0 0 80 10 10 cm /A Do Q\nq 80 0 0 80 110 10 cm /B Do Q\n",
             "/XObject << /A %(a)s /B %(b)s >>", objects=objects)


def swatches(colorspace_op, values, y=110, size=40):
    """Four or five squares in a row, each `values[i]` set with `colorspace_op`."""
    ops = []
    for i, v in enumerate(values):
        ops.append("%s %s %d %d %d %d re f" % (v, colorspace_op, 10 + 47 * i, y, size, size))
    return "\n".join(ops)


def colorspace_indexed():
    # Fills with /Indexed colours 0 to 3 (top), and a 4 x 2 image of 2-bit
    # indices (bottom: 0 1 2 3 / 3 2 1 0).
    def objects(pdf):
        cs = pdf.add("[/Indexed /DeviceRGB 3 <ff0000 00c000 0000ff ffc000>]")
        im = pdf.add_hex_stream("/Type /XObject /Subtype /Image /Width 4 /Height 2 /ColorSpace %s "
                                "/BitsPerComponent 2" % ref(cs), bytes([0b00011011, 0b11100100]))
        return {"cs": ref(cs), "im": ref(im)}

    content = "/CS0 cs\n" + swatches("sc", ["0", "1", "2", "3"]) + "\nq 180 0 0 80 10 10 cm /I Do Q\n"
    one_page("colorspace-indexed", (200, 160), content, "/ColorSpace << /CS0 %(cs)s >> /XObject << /I %(im)s >>",
             objects=objects)


def colorspace_separation():
    # A spot colour whose tint maps to CMYK (0, 0.8t, t, 0): tints 0.25,
    # 0.5, 0.75, 1 (top), and a stroke in it (bottom).
    def objects(pdf):
        return {"cs": ref(pdf.add("[/Separation /Spot /DeviceCMYK << /FunctionType 2 /Domain [0 1] "
                                  "/C0 [0 0 0 0] /C1 [0 0.8 1 0] /N 1 >>]"))}

    content = ("/CS0 cs /CS0 CS\n" + swatches("sc", ["0.25", "0.5", "0.75", "1"]) +
               "\n0.6 SC 12 w 20 50 m 180 50 l S\n")
    one_page("colorspace-separation", (200, 160), content, "/ColorSpace << /CS0 %(cs)s >>", objects=objects)


def colorspace_devicen():
    # Two colorants, Cyan and a spot, mapped to CMYK (c, s, 0, 0) by a
    # PostScript function: (1 0), (0 1), (0.5 0.5), (1 1).
    def objects(pdf):
        fn = pdf.add_stream("/FunctionType 4 /Domain [0 1 0 1] /Range [0 1 0 1 0 1 0 1]", "{ 0 0 }")
        return {"cs": ref(pdf.add("[/DeviceN [/Cyan /Spot] /DeviceCMYK %s]" % ref(fn)))}

    content = "/CS0 cs\n" + swatches("sc", ["1 0", "0 1", "0.5 0.5", "1 1"]) + "\n"
    one_page("colorspace-devicen", (200, 160), content, "/ColorSpace << /CS0 %(cs)s >>", objects=objects)


def s15(v):
    """An ICC s15Fixed16Number."""
    return int(round(v * 65536)).to_bytes(4, "big", signed=True)


def icc_profile():
    """A minimal ICC v2 RGB display profile: sRGB's primaries (D50-adapted)
    and a pure gamma 2.2 curve, the matrix/TRC model."""
    def tag_xyz(x, y, z):
        return b"XYZ " + b"\0" * 4 + s15(x) + s15(y) + s15(z)

    def tag_curve(gamma):
        return b"curv" + b"\0" * 4 + (1).to_bytes(4, "big") + int(round(gamma * 256)).to_bytes(2, "big") + b"\0\0"

    def tag_desc(text):
        t = text.encode("ascii") + b"\0"
        return (b"desc" + b"\0" * 4 + len(t).to_bytes(4, "big") + t + b"\0" * 4 + b"\0" * 4 + b"\0" * 2 + b"\0" +
                b"\0" * 67)

    def tag_text(text):
        return b"text" + b"\0" * 4 + text.encode("ascii") + b"\0"

    tags = [(b"desc", tag_desc("mpvg test RGB")), (b"cprt", tag_text("No copyright, test data")),
            (b"wtpt", tag_xyz(0.9642, 1.0, 0.8249)),
            (b"rXYZ", tag_xyz(0.4361, 0.2225, 0.0139)), (b"gXYZ", tag_xyz(0.3851, 0.7169, 0.0971)),
            (b"bXYZ", tag_xyz(0.1431, 0.0606, 0.7141)),
            (b"rTRC", tag_curve(2.2)), (b"gTRC", tag_curve(2.2)), (b"bTRC", tag_curve(2.2))]
    offset = 128 + 4 + 12 * len(tags)
    table, body = b"", b""
    for sig, data in tags:
        while (offset + len(body)) % 4:
            body += b"\0"
        table += sig + (offset + len(body)).to_bytes(4, "big") + len(data).to_bytes(4, "big")
        body += data
    size = offset + len(body)
    header = (size.to_bytes(4, "big") + b"\0\0\0\0" + bytes([2, 0x10, 0, 0]) + b"mntr" + b"RGB " + b"XYZ " +
              bytes([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]) + b"acsp" + b"\0" * 4 + b"\0" * 4 + b"\0" * 4 + b"\0" * 4 +
              b"\0" * 8 + b"\0" * 4 + s15(0.9642) + s15(1.0) + s15(0.8249) + b"\0" * 4 + b"\0" * 16 + b"\0" * 28)
    assert len(header) == 128, len(header)
    return header + len(tags).to_bytes(4, "big") + table + body


def colorspace_iccbased():
    # ICCBased (N 3) with a small matrix/TRC profile written here (sRGB
    # primaries, gamma 2.2): primaries, a mid grey and a light orange.
    def objects(pdf):
        profile = pdf.add_hex_stream("/N 3 /Alternate /DeviceRGB", icc_profile())
        return {"cs": ref(pdf.add("[/ICCBased %s]" % ref(profile)))}

    content = ("/CS0 cs\n" + swatches("sc", ["1 0 0", "0 1 0", "0 0 1", "0.5 0.5 0.5"]) + "\n" +
               swatches("sc", ["1 0.7 0.3", "0.2 0.2 0.2", "0 0 0", "1 1 1"], y=50) + "\n0 G 0.5 w 10 50 181 40 re S\n")
    one_page("colorspace-iccbased", (200, 160), content, "/ColorSpace << /CS0 %(cs)s >>", objects=objects)


def colorspace_cmyk():
    # DeviceCMYK fills (k) and a stroke (K): cyan, magenta, yellow, black,
    # and mixtures.
    content = (swatches("k", ["1 0 0 0", "0 1 0 0", "0 0 1 0", "0 0 0 1"]) + "\n" +
               swatches("k", ["0.2 0.6 0 0.1", "0 0.5 1 0", "0.7 0 0.3 0.2", "0.3 0.3 0.3 0"], y=50) +
               "\n1 0 1 0 K 4 w 10 30 m 190 30 l S\n")
    one_page("colorspace-cmyk", (200, 160), content)


def form(pdf, bbox, content, group=None, extra=""):
    """A form XObject; `group` is the transparency group dictionary's
    entries (without /S /Transparency)."""
    g = " /Group << /S /Transparency %s >>" % group if group is not None else ""
    return pdf.add_stream("/Type /XObject /Subtype /Form /BBox [%s]%s %s" % (bbox, g, extra), content)


def softmask_luminosity():
    # Vertical stripes under a blue square masked by the luminosity of a
    # group: a white circle and an 80 % grey bar. Left: /BC [0.3 0.3 0.3]
    # (outside the group's shapes the mask is 0.3); right: no /BC (black,
    # nothing shows outside).
    def objects(pdf):
        g = "/CS /DeviceRGB"
        m1 = form(pdf, "0 0 200 200", "1 g %s f\n0.8 g 15 20 70 15 re f\n" % circle(50, 110, 30), g)
        m2 = form(pdf, "0 0 200 200", "1 g %s f\n0.8 g 115 20 70 15 re f\n" % circle(150, 110, 30), g)
        return {"a": ref(pdf.add("<< /Type /ExtGState /SMask << /Type /Mask /S /Luminosity /G %s /BC [0.3 0.3 0.3] >> >>"
                                 % ref(m1))),
                "b": ref(pdf.add("<< /Type /ExtGState /SMask << /Type /Mask /S /Luminosity /G %s >> >>" % ref(m2)))}

    content = lines(stripes(0, 0, 200, 200, 10, RAINBOW),
                    "q /A gs 0 0 0.6 rg 10 10 80 180 re f Q",
                    "q /B gs 0 0 0.6 rg 110 10 80 180 re f Q")
    one_page("softmask-luminosity", (200, 200), content, "/ExtGState << /A %(a)s /B %(b)s >>", objects=objects)


def softmask_alpha():
    # A red square masked by the alpha of a group holding three squares at
    # opacities 0.25, 0.6 and 1 (colours do not matter to an alpha mask),
    # over a checkerboard.
    def objects(pdf):
        g = form(pdf, "0 0 200 200", "0 g /a1 gs 20 20 50 160 re f /a2 gs 75 20 50 160 re f /a3 gs 130 20 50 160 re f\n",
                 "", "/Resources << /ExtGState << /a1 << /ca 0.25 >> /a2 << /ca 0.6 >> /a3 << /ca 1 >> >> >>")
        return {"m": ref(pdf.add("<< /Type /ExtGState /SMask << /Type /Mask /S /Alpha /G %s >> >>" % ref(g)))}

    content = checker(200, 200) + "\nq /M gs 0.9 0 0 rg 10 10 180 180 re f Q\n"
    one_page("softmask-alpha", (200, 200), content, "/ExtGState << /M %(m)s >>", objects=objects)


BLEND_MODES = ["Normal", "Multiply", "Screen", "Overlay", "Darken", "Lighten", "ColorDodge", "ColorBurn",
               "HardLight", "SoftLight", "Difference", "Exclusion", "Hue", "Saturation", "Color", "Luminosity"]


def blend_modes():
    # The 16 blend modes in a 4 x 4 grid (Normal top left, in the order of
    # the PDF specification's table, row by row): a 40 pt square, orange
    # above and light blue-grey below, over rainbow stripes 10 pt wide.
    ops = [stripes(0, 0, 200, 200, 10, RAINBOW)]
    for i, mode in enumerate(BLEND_MODES):
        x = 5 + 50 * (i % 4)
        y = 155 - 50 * (i // 4)
        ops.append("q /%s gs 1 0.5 0.1 rg %d %d 40 20 re f 0.55 0.6 0.75 rg %d %d 40 20 re f Q" %
                   (mode, x, y + 20, x, y))
    resources = "/ExtGState << %s >>" % " ".join("/%s << /BM /%s >>" % (m, m) for m in BLEND_MODES)
    one_page("blend-modes", (200, 200), "\n".join(ops) + "\n", resources)


def three_circles(x, y):
    return ("/half gs 1 0 0 rg %s f 0 0.7 0 rg %s f 0 0 1 rg %s f" %
            (circle(x + 30, y + 55, 25), circle(x + 55, y + 55, 25), circle(x + 42, y + 33, 25)))


def knockout_group():
    # Three overlapping circles at opacity 0.6 in a group: knockout (/K
    # true, left: each circle replaces the ones below it, over the
    # backdrop) and not (right: they composite onto each other).
    def objects(pdf):
        res = "/Resources << /ExtGState << /half << /ca 0.6 >> >> >>"
        return {"k": ref(form(pdf, "0 0 200 200", three_circles(5, 60) + "\n", "/K true", res)),
                "n": ref(form(pdf, "0 0 200 200", three_circles(105, 60) + "\n", "/K false", res))}

    content = stripes(0, 0, 200, 200, 10, ["0.85 0.85 0.85", "0.5 0.5 0.5"], False) + "\n/K Do /N Do\n"
    one_page("knockout-group", (200, 200), content, "/XObject << /K %(k)s /N %(n)s >>", objects=objects)


def isolated_group():
    # Circles blended with Multiply in a group over rainbow stripes:
    # isolated (/I true, left: the first circle meets a transparent
    # backdrop, so it shows its own colour) and not (right: it multiplies
    # the stripes).
    def objects(pdf):
        res = "/Resources << /ExtGState << /half << /BM /Multiply >> >> >>"
        return {"i": ref(form(pdf, "0 0 200 200", three_circles(5, 60) + "\n", "/I true", res)),
                "n": ref(form(pdf, "0 0 200 200", three_circles(105, 60) + "\n", "/I false", res))}

    content = stripes(0, 0, 200, 200, 10, RAINBOW) + "\n/I Do /N Do\n"
    one_page("isolated-group", (200, 200), content, "/XObject << /I %(i)s /N %(n)s >>", objects=objects)


def constant_alpha():
    # /ca on fills and /CA on strokes: overlapping squares at 0.5, a thick
    # stroke at 0.5 over its own fill (the inner half of the stroke shows
    # both), and both at once.
    def objects(pdf):
        return {}

    content = lines(
        "q /A gs 1 0 0 rg 20 100 80 80 re f 0 0 1 rg 60 120 80 60 re f Q",
        "q /B gs 0 0.6 0 rg 0 0 0 RG 16 w 30 20 60 60 re B Q",
        "q /C gs 1 0.5 0 rg 0.5 0 0.5 RG 10 w 120 20 60 60 re B Q",
        "q /A gs 0 0 0 RG 6 w 150 110 m 190 190 l S Q",
    )
    one_page("constant-alpha", (200, 200), content,
             "/ExtGState << /A << /ca 0.5 >> /B << /CA 0.5 >> /C << /CA 0.4 /ca 0.7 >> >>")


def tiling_pattern():
    # Left: a coloured pattern (PaintType 1), a red dot and a blue square in
    # a 20 x 20 cell, filling a circle. Right: an uncoloured pattern
    # (PaintType 2), a diagonal band in a 12 x 12 cell (two polygons that
    # join the neighbouring cells' into 45 degree stripes, all inside the
    # cell), rotated by 30 degrees, in green and in purple; bottom right: a
    # cell smaller than its step (gaps between cells).
    def objects(pdf):
        p1 = pdf.add_stream("/Type /Pattern /PatternType 1 /PaintType 1 /TilingType 1 /BBox [0 0 20 20] "
                            "/XStep 20 /YStep 20 /Resources << >>",
                            "1 0 0 rg %s f 0 0 1 rg 12 12 6 6 re f" % circle(6, 6, 4))
        p2 = pdf.add_stream("/Type /Pattern /PatternType 1 /PaintType 2 /TilingType 1 /BBox [0 0 12 12] "
                            "/XStep 12 /YStep 12 /Matrix [0.866 0.5 -0.5 0.866 0 0] /Resources << >>",
                            "0 0 m 3 0 l 12 9 l 12 12 l 9 12 l 0 3 l h 9 0 m 12 0 l 12 3 l h 0 9 m 3 12 l 0 12 l h f")
        p3 = pdf.add_stream("/Type /Pattern /PatternType 1 /PaintType 1 /TilingType 1 /BBox [0 0 10 10] "
                            "/XStep 16 /YStep 16 /Resources << >>", "0.9 0.5 0 rg 0 0 10 10 re f")
        return {"p1": ref(p1), "p2": ref(p2), "p3": ref(p3)}

    content = lines(
        "/Pattern cs /P1 scn", circle(50, 130, 45), "f",
        "/CS1 cs 0 0.6 0 /P2 scn 110 110 80 80 re f",
        "0.5 0 0.6 /P2 scn 10 10 80 60 re f",
        "/Pattern cs /P3 scn 110 10 80 80 re f",
        "0 G 0.5 w 110 10 80 80 re S",
    )
    one_page("tiling-pattern", (200, 200), content,
             "/Pattern << /P1 %(p1)s /P2 %(p2)s /P3 %(p3)s >> /ColorSpace << /CS1 [/Pattern /DeviceRGB] >>",
             objects=objects)


ASYMMETRIC = lines(
    "0.9 0.9 0.9 rg 0 0 200 120 re f",
    "1 0 0 rg 10 10 20 60 re f 10 10 50 15 re f",   # an L at the bottom left
    "0 0 1 rg 170 90 20 20 re f",                    # a square at the top right
    "0 g BT /F1 30 Tf 80 50 Td (Up) Tj ET",
)


def rotate():
    for angle in (90, 180, 270):
        one_page("rotate-%d" % angle, (200, 120), ASYMMETRIC, "/Font << /F1 %s >>" % HELVETICA,
                 "/Rotate %d" % angle)


def cropbox():
    # A 200 x 200 grid of coloured 20 pt squares; the CropBox [40 30 160
    # 170] keeps 120 x 140 of it, away from the origin.
    ops = []
    for j in range(10):
        for i in range(10):
            ops.append("%s %s %s rg %d %d 20 20 re f" % (fmt(i / 9), fmt(j / 9), fmt(0.5), 20 * i, 20 * j))
    ops.append("0 G 2 w 41 31 118 138 re S")
    one_page("cropbox", (200, 200), "\n".join(ops) + "\n", "", "/CropBox [40 30 160 170]")


def annotations():
    # Three Square annotations with appearance streams: printable (/F 4,
    # bottom left), hidden (/F 2, bottom right: must not show), and
    # printable with a BBox half the size of its /Rect (top: the appearance
    # is scaled to the rectangle).
    def objects(pdf):
        ap1 = form(pdf, "0 0 70 70", "0 0.6 0 rg 5 5 60 60 re f 1 g %s f" % circle(35, 35, 15))
        ap2 = form(pdf, "0 0 70 70", "1 0 0 rg 0 0 70 70 re f")
        ap3 = form(pdf, "0 0 80 35", "0 0 0.8 rg 0 0 80 35 re f 1 1 0 rg 10 10 20 15 re f")
        a1 = pdf.add("<< /Type /Annot /Subtype /Square /Rect [20 20 90 90] /F 4 /C [0 0.6 0] /AP << /N %s >> >>"
                     % ref(ap1))
        a2 = pdf.add("<< /Type /Annot /Subtype /Square /Rect [110 20 180 90] /F 2 /C [1 0 0] /AP << /N %s >> >>"
                     % ref(ap2))
        a3 = pdf.add("<< /Type /Annot /Subtype /Square /Rect [20 110 180 180] /F 4 /C [0 0 0.8] /AP << /N %s >> >>"
                     % ref(ap3))
        return {"annots": " ".join(ref(a) for a in (a1, a2, a3))}

    one_page("annotations", (200, 200), "0.9 g 0 0 200 200 re f 0 g 0.5 w 110 20 70 70 re S\n", "",
             "/Annots [%(annots)s]", objects=objects)


def optional_content():
    # Two optional content groups: On (listed in /D /ON) and Off (in /D
    # /OFF). Marked content of each, and a form XObject belonging to Off:
    # only the green square and the grey frame show.
    def objects(pdf):
        on = pdf.add("<< /Type /OCG /Name (On) >>")
        off = pdf.add("<< /Type /OCG /Name (Off) >>")
        f = form(pdf, "0 0 200 200", "1 0 0 rg 110 110 80 80 re f", None, "/OC %s" % ref(off))
        return {"on": ref(on), "off": ref(off), "f": ref(f)}

    content = lines(
        "0.5 G 2 w 5 5 190 190 re S",
        "/OC /oc1 BDC 0 0.7 0 rg 10 10 80 80 re f EMC",
        "/OC /oc2 BDC 1 0 0 rg 110 10 80 80 re f EMC",
        "/F Do",
    )
    one_page("optional-content", (200, 200), content,
             "/Properties << /oc1 %(on)s /oc2 %(off)s >> /XObject << /F %(f)s >>", objects=objects,
             catalog_extra="/OCProperties << /OCGs [%(on)s %(off)s] /D << /ON [%(on)s] /OFF [%(off)s] >> >>")


# The error cases of tests/test_cli_pdf.sh: three 100 x 100 pt pages, a
# red, a green and a blue square, page 2 broken in some way.

def three_pages(page2=None, extra_objects=None, count=3):
    """The three-page document; `page2(pdf, tree, page, contents)` may
    replace page 2's dictionary (or add objects) by setting `page` itself;
    `count` is what the page tree's /Count claims."""
    pdf = Pdf()
    catalog = pdf.reserve()
    tree = pdf.reserve()
    pages = []
    for i, rgb in enumerate(("1 0 0", "0 0.6 0", "0 0 1")):
        page = pdf.reserve()
        contents = pdf.add_stream("", "%s rg 10 10 80 80 re f\n" % rgb)
        pdf.set(page, "<< /Type /Page /Parent %s /MediaBox [0 0 100 100] /Contents %s /Resources << >> >>" %
                (ref(tree), ref(contents)))
        if i == 1 and page2:
            page2(pdf, tree, page, contents)
        pages.append(page)
    pdf.set(tree, "<< /Type /Pages /Kids [%s] /Count %d >>" % (" ".join(ref(p) for p in pages), count))
    pdf.set(catalog, "<< /Type /Catalog /Pages %s >>" % ref(tree))
    return pdf.bytes(catalog)


def error_cases():
    # Loading page 2 throws: it is a /Pages node whose only kid is itself
    # (MuPDF 1.21: "cycle in page tree").
    def cycle(pdf, tree, page, contents):
        pdf.set(page, "<< /Type /Pages /Parent %s /Kids [%s] /Count 1 >>" % (ref(tree), ref(page)))
    write(os.path.join(PDFDIR, "three-pages-bad-page2.pdf"), three_pages(cycle))


    # The intact document cut in the middle of page 3's content stream: no
    # cross-reference table or trailer any more; MuPDF repairs it.
    data = three_pages()
    write(os.path.join(PDFDIR, "three-pages.pdf"), data)
    # A page tree that claims two billion pages and holds three.
    write(os.path.join(PDFDIR, "three-pages-count-2e9.pdf"), three_pages(count=2000000000))
    # A catalog without a page tree.
    pdf = Pdf()
    catalog = pdf.add("<< /Type /Catalog >>")
    write(os.path.join(PDFDIR, "no-page-tree.pdf"), pdf.bytes(catalog))
    write(os.path.join(PDFDIR, "truncated.pdf"), data[:data.index(b"0 0 1 rg") + 4])


# pdf2png's --box, -gray and -mono (tests/test_cli_pdf.sh).

def page_boxes():
    """page-boxes.pdf, two pages. MediaBox [0 0 300 200] and CropBox
    [20 10 280 190] sit on the page tree (inherited); page 1 has its own
    BleedBox [30 20 270 180], TrimBox [40 30 260 170] and ArtBox [50 40 400
    160] (past the MediaBox: 250 x 120 once intersected). The media is
    light grey with a 10 pt square at each box's lower-left corner: red
    at the MediaBox's (0 0), green at the CropBox's, blue at the
    BleedBox's, black at the TrimBox's, magenta at the ArtBox's. Page 2 is
    the same content turned by /Rotate 90, without boxes of its own."""
    content = lines("0.9 g 0 0 300 200 re f",
                    "1 0 0 rg 0 0 10 10 re f",
                    "0 1 0 rg 20 10 10 10 re f",
                    "0 0 1 rg 30 20 10 10 re f",
                    "0 g 40 30 10 10 re f",
                    "1 0 1 rg 50 40 10 10 re f")
    pdf = Pdf()
    catalog = pdf.reserve()
    tree = pdf.reserve()
    p1 = pdf.reserve()
    p2 = pdf.reserve()
    contents = pdf.add_stream("", content)
    pdf.set(p1, "<< /Type /Page /Parent %s /Contents %s /Resources << >> /BleedBox [30 20 270 180] "
            "/TrimBox [40 30 260 170] /ArtBox [50 40 400 160] >>" % (ref(tree), ref(contents)))
    pdf.set(p2, "<< /Type /Page /Parent %s /Contents %s /Resources << >> /Rotate 90 >>" % (ref(tree), ref(contents)))
    pdf.set(tree, "<< /Type /Pages /Kids [%s %s] /Count 2 /MediaBox [0 0 300 200] /CropBox [20 10 280 190] >>"
            % (ref(p1), ref(p2)))
    pdf.set(catalog, "<< /Type /Catalog /Pages %s >>" % ref(tree))
    write(os.path.join(PDFDIR, "page-boxes.pdf"), pdf.bytes(catalog))


def grey_ramp():
    """grey-ramp.pdf: a 256 x 40 pt page of 256 vertical bands, band i
    1 pt wide in the grey i/255 (DeviceGray), over the top half; the
    bottom half the colours red, green, blue, yellow, cyan, magenta in
    bands of 40 pt (RGB, for the grey weights), then white."""
    ops = ["%s g %d 20 1 20 re f" % (fmt(i / 255), i) for i in range(256)]
    for k, rgb in enumerate(("1 0 0", "0 1 0", "0 0 1", "1 1 0", "0 1 1", "1 0 1")):
        ops.append("%s rg %d 0 40 20 re f" % (rgb, 40 * k))
    one_page_to(os.path.join(PDFDIR, "grey-ramp.pdf"), (256, 40), lines(*ops))


def one_page_to(path, size, content, resources="", objects=None):
    """A one-page document of `content` over a MediaBox of `size`, at `path`;
    `objects` and `resources` as one_page's."""
    pdf = Pdf()
    catalog = pdf.reserve()
    tree = pdf.reserve()
    page = pdf.reserve()
    numbers = objects(pdf) if objects else {}
    contents = pdf.add_stream("", content)
    res = "<< %s >>" % (resources % numbers) if resources else "<< >>"
    pdf.set(page, "<< /Type /Page /Parent %s /MediaBox [0 0 %s] /Contents %s /Resources %s >>" %
            (ref(tree), " ".join(fmt(v) for v in size), ref(contents), res))
    pdf.set(tree, "<< /Type /Pages /Kids [%s] /Count 1 >>" % ref(page))
    pdf.set(catalog, "<< /Type /Catalog /Pages %s >>" % ref(tree))
    write(path, pdf.bytes(catalog))


def thin_rules():
    """thin-rules.pdf: a 300 x 170 pt page of thin black rules. Rows of
    four horizontal strokes 7 pt apart, each 0.13 pt lower than the last
    (so that they fall differently on the pixel grid), in the widths 0.1,
    0.25, 0.4 (TeX's \\hline), 0.6 and 1 pt, from x 20 to 180; beside them
    eight vertical blue strokes 0.4 pt wide, 7.13 pt apart, from x 200;
    above, at y 155 to 167, the same horizontal widths as filled
    rectangles 160 pt long (TeX draws its rules so), one each."""
    ops = []
    y = 20.0
    for w in (0.1, 0.25, 0.4, 0.6, 1.0):
        for k in range(4):
            yy = fmt(y + k * 0.13)
            ops.append("%s w 20 %s m 180 %s l S" % (fmt(w), yy, yy))
            y += 7
    ops.append("0 0 1 RG 0.4 w")
    for k in range(8):
        x = fmt(200 + k * 7.13)
        ops.append("%s 20 m %s 140 l S" % (x, x))
    ops.append("0 g")
    for k, w in enumerate((0.1, 0.25, 0.4, 0.6, 1.0)):
        ops.append("20 %s 160 %s re f" % (fmt(155 + 2.8 * k), fmt(w)))
    one_page_to(os.path.join(PDFDIR, "thin-rules.pdf"), (300, 170), lines(*ops))


def print_preview():
    """print-preview.pdf: overprint and spot colours on a 200 x 100 pt page
    (pdf2png --colorspace cmyk, --separations), one 40 pt square a case:
    top row (y 50..90), each over a cyan (1 0 0 0 k) square:
      x 0..40:    yellow (0 0 1 0 k) overprinting, OPM 1 (x 10..30): cyan
                  stays under it (C 1, Y 1);
      x 40..80:   the same yellow without overprint: it knocks out (C 0);
      x 80..120:  the spot Varnish (Separation, alternate 0 0 0 0.25 at full
                  tint) at tint 1, overprinting: C 1 and Varnish 1;
      x 120..160: yellow overprinting with OPM 0: every process ink is
                  painted (C 0, Y 1);
      x 160..200: over 0.5 cyan, 0.5 cyan with /BM /Multiply: C 0.75 (ink
                  multiplies as complements: 1 - 0.5 x 0.5).
    bottom row (y 0..40):
      x 0..40:    over Varnish at tint 0.6, black (0 g) overprinting: K 1,
                  Varnish 0.6 kept (a DeviceGray colour paints the process
                  inks only);
      x 40..80:   over magenta (0 1 0 0 k), DeviceN [Cyan Varnish] at 0.4,
                  0.8 overprinting: M 1, C 0.4, Varnish 0.8."""
    ops = ["1 0 0 0 k 0 50 40 40 re f 40 50 40 40 re f 80 50 40 40 re f 120 50 40 40 re f",
           "0.5 0 0 0 k 160 50 40 40 re f",
           "/OPon gs 0 0 1 0 k 10 60 20 20 re f",
           "/Off gs 0 0 1 0 k 50 60 20 20 re f",
           "/OPon gs /Var cs 1 scn 90 60 20 20 re f",
           "/OPm0 gs 0 0 1 0 k 130 60 20 20 re f",
           "/Off gs /Mul gs 0.5 0 0 0 k 170 60 20 20 re f /Nor gs",
           "/Off gs /Var cs 0.6 scn 0 0 40 40 re f",
           "/OPon gs 0 g 10 10 20 20 re f",
           "/Off gs 0 1 0 0 k 40 0 40 40 re f",
           "/OPon gs /CV cs 0.4 0.8 scn 50 10 20 20 re f"]
    varnish = "[/Separation /Varnish /DeviceCMYK << /FunctionType 2 /Domain [0 1] /C0 [0 0 0 0] /C1 [0 0 0 0.25] /N 1 >>]"
    def objects(pdf):
        fn = pdf.add_stream("/FunctionType 4 /Domain [0 1 0 1] /Range [0 1 0 1 0 1 0 1]", "{ 0.25 mul 0 0 3 -1 roll }")
        return {"cv": "[/DeviceN [/Cyan /Varnish] /DeviceCMYK %s]" % ref(fn)}
    one_page_to(os.path.join(PDFDIR, "print-preview.pdf"), (200, 100), lines(*ops),
                resources="/ColorSpace << /Var " + varnish + " /CV %(cv)s >> "
                "/ExtGState << /OPon << /OP true /op true /OPM 1 >> /OPm0 << /OP true /op true /OPM 0 >> "
                "/Off << /OP false /op false >> /Mul << /BM /Multiply >> /Nor << /BM /Normal >> >>",
                objects=objects)


def rgb_inks():
    """rgb-inks.pdf and rgb-inks-intent.pdf: a 60 x 20 pt page of 10 pt
    squares, RGB black (0 0 0 rg), RGB red, DeviceGray black (0 g) and
    DeviceCMYK black (0 0 0 1 k), then a 2 x 1 RGB image (black, red) over
    x 40..60. The second has an output intent whose DestOutputProfile is
    testdata/icc/cmy-press.icc (scripts/make_test_cmyk_profile.cpp: a press
    printing RGB black as C, M, Y without K), for print preview's colour
    management: RGB colours and images go through it, grey and CMYK stay
    black ink."""
    content = lines("0 0 0 rg 0 0 10 20 re f", "1 0 0 rg 10 0 10 20 re f", "0 g 20 0 10 20 re f",
                    "0 0 0 1 k 30 0 10 20 re f", "q 20 0 0 20 40 0 cm /Im Do Q")
    with open(os.path.join(ROOT, "testdata", "icc", "cmy-press.icc"), "rb") as f:
        icc = f.read()
    for name, intent in (("rgb-inks.pdf", False), ("rgb-inks-intent.pdf", True)):
        pdf = Pdf()
        catalog = pdf.reserve()
        tree = pdf.reserve()
        page = pdf.reserve()
        image = pdf.add_hex_stream("/Type /XObject /Subtype /Image /Width 2 /Height 1 /ColorSpace /DeviceRGB "
                                   "/BitsPerComponent 8", bytes([0, 0, 0, 255, 0, 0]))
        contents = pdf.add_stream("", content)
        pdf.set(page, "<< /Type /Page /Parent %s /MediaBox [0 0 60 20] /Contents %s "
                "/Resources << /XObject << /Im %s >> >> >>" % (ref(tree), ref(contents), ref(image)))
        pdf.set(tree, "<< /Type /Pages /Kids [%s] /Count 1 >>" % ref(page))
        extra = ""
        if intent:
            profile = pdf.add_hex_stream("/N 4", icc)
            extra = ("/OutputIntents [<< /Type /OutputIntent /S /GTS_PDFX /OutputConditionIdentifier "
                     "(mpvg test press) /DestOutputProfile %s >>] " % ref(profile))
        pdf.set(catalog, "<< /Type /Catalog /Pages %s %s>>" % (ref(tree), extra))
        write(os.path.join(PDFDIR, name), pdf.bytes(catalog))


def main():
    fill_rules()
    clips()
    dashes()
    text_render_modes()
    shading_axial()
    shading_radial()
    shading_function()
    mesh_shadings()
    image_masks()
    image_smask()
    image_decode()
    image_interpolate()
    colorspace_indexed()
    colorspace_separation()
    colorspace_devicen()
    colorspace_iccbased()
    colorspace_cmyk()
    softmask_luminosity()
    softmask_alpha()
    blend_modes()
    knockout_group()
    isolated_group()
    constant_alpha()
    tiling_pattern()
    rotate()
    cropbox()
    annotations()
    optional_content()
    error_cases()
    page_boxes()
    grey_ramp()
    thin_rules()
    print_preview()
    rgb_inks()


if __name__ == "__main__":
    main()
