#!/usr/bin/env python3
"""Writes the oversized inputs of tests/test_memory.sh into OUTDIR (Python 3
standard library; each file is small on disk and huge once decoded):

    make_hostile_inputs.py OUTDIR [NAME ...]

- gif-claim.svg: a 100-byte GIF claiming 16000 x 16000 pixels, as a data URI.
- png-16000.svg: a 16000 x 16000 PNG (all one colour, ~0.8 MB), as a data URI.
- image-20000.pdf: a page with a 20000 x 20000 Flate RGB image (~1.2 MB).
- mesh-200k.pdf: a page with a type 4 shading of 200,000 triangles.
- strokes-1e5.svg: 100,000 stroked line segments (one zigzag path per row).
- page-14400.pdf: a 14400 x 14400 pt page (the largest PDF allows).
- issue 45's: mesh-overflow.pdf (65,537 whole-grid triangles), mesh-200k-large.pdf,
  spot-names.pdf (spot names that are paths), spots-65.pdf, markers.svg (10^6
  markers), lines-1e5.svg, filter-chain.svg (10^4 blurs), dash-200k.svg.
"""
import base64
import os
import random
import struct
import sys
import zlib


def png_16000():
    w = h = 16000
    row = b"\x00" + b"\x40\x80\xc0" * w
    c = zlib.compressobj(9)
    data = b"".join(c.compress(row) for _ in range(h)) + c.flush()

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", data) + chunk(b"IEND", b"")
    return svg_with_image("image/png", png)


def gif_claim():
    # Logical screen and image descriptor of 16000 x 16000, a 2-colour
    # table, and a few bytes of LZW data: the rest of the image is missing.
    w = h = 16000
    gif = b"GIF89a" + struct.pack("<HHBBB", w, h, 0x80, 0, 0) + b"\x00\x00\x00\xff\x00\x00"
    gif += b"," + struct.pack("<HHHHB", 0, 0, w, h, 0) + b"\x02\x02\x4c\x01\x00;"
    return svg_with_image("image/gif", gif)


def svg_with_image(mime, data):
    uri = "data:%s;base64,%s" % (mime, base64.b64encode(data).decode("ascii"))
    return ('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
            'width="1000" height="1000"><image width="1000" height="1000" xlink:href="%s"/></svg>\n' % uri).encode()


def strokes_1e5():
    rnd = random.Random(25)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="1000">']
    per_row = 1000
    for r in range(100):
        y = 5 + r * 10
        pts = " ".join("%d,%.1f" % (i, y + rnd.uniform(-4, 4)) for i in range(0, per_row + 1))
        out.append('<polyline fill="none" stroke="#%06x" stroke-width="1.5" points="%s"/>' % (rnd.randrange(1 << 24), pts))
    out.append("</svg>")
    return ("\n".join(out) + "\n").encode()


def pdf(objects, root=1):
    out = b"%PDF-1.7\n"
    offsets = []
    for i, body in enumerate(objects):
        offsets.append(len(out))
        out += b"%d 0 obj\n" % (i + 1) + body + b"\nendobj\n"
    xref = len(out)
    out += b"xref\n0 %d\n0000000000 65535 f \n" % (len(objects) + 1)
    for o in offsets:
        out += b"%010d 00000 n \n" % o
    out += b"trailer\n<< /Size %d /Root %d 0 R >>\nstartxref\n%d\n%%%%EOF\n" % (len(objects) + 1, root, xref)
    return out


def stream(entries, data):
    return b"<< %s /Length %d >>\nstream\n" % (entries, len(data)) + data + b"\nendstream"


def page_pdf(size, content, resources):
    return pdf([
        b"<< /Type /Catalog /Pages 2 0 R >>",
        b"<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
        b"<< /Type /Page /Parent 2 0 R /MediaBox [0 0 %d %d] /Contents 4 0 R /Resources << %s >> >>"
        % (size, size, resources),
        stream(b"", content),
    ] + EXTRA)


EXTRA = []


def image_20000():
    w = h = 20000
    row = b"\x20\x60\xa0" * w
    c = zlib.compressobj(9)
    data = b"".join(c.compress(row) for _ in range(h)) + c.flush()
    EXTRA[:] = [stream(b"/Type /XObject /Subtype /Image /Width %d /Height %d /ColorSpace /DeviceRGB "
                       b"/BitsPerComponent 8 /Filter /FlateDecode" % (w, h), data)]
    return page_pdf(600, b"q 600 0 0 600 0 0 cm /Im Do Q\n", b"/XObject << /Im 5 0 R >>")


def mesh_200k():
    rnd = random.Random(7)
    n = 200000
    data = bytearray()
    for _ in range(n):
        x, y = rnd.uniform(0, 590), rnd.uniform(0, 590)
        for dx, dy in ((0, 0), (10, 0), (0, 10)):
            data += struct.pack(">BHH3B", 0, int((x + dx) * 65535 / 600), int((y + dy) * 65535 / 600),
                                rnd.randrange(256), rnd.randrange(256), rnd.randrange(256))
    EXTRA[:] = [stream(b"/ShadingType 4 /ColorSpace /DeviceRGB /BitsPerCoordinate 16 /BitsPerComponent 8 "
                       b"/BitsPerFlag 8 /Decode [0 600 0 600 0 1 0 1 0 1] /Filter /FlateDecode",
                       zlib.compress(bytes(data), 9))]
    return page_pdf(600, b"/Sh sh\n", b"/Shading << /Sh 5 0 R >>")


def page_14400():
    EXTRA[:] = []
    return page_pdf(14400, b"0 0 1 rg 100 100 14200 14200 re f\n", b"")


def mesh_pdf(n, corners, colors=None):
    """A page with a type 4 shading of n triangles; corners(k) gives
    triangle k's three points (page units), colors(k) its RGB bytes."""
    data = bytearray()
    for k in range(n):
        c = colors(k) if colors else (k % 251, 128, 255 - k % 251)
        for x, y in corners(k):
            data += struct.pack(">BHH3B", 0, int(x * 65535 / 600), int(y * 65535 / 600), *c)
    EXTRA[:] = [stream(b"/ShadingType 4 /ColorSpace /DeviceRGB /BitsPerCoordinate 16 /BitsPerComponent 8 "
                       b"/BitsPerFlag 8 /Decode [0 600 0 600 0 1 0 1 0 1] /Filter /FlateDecode",
                       zlib.compress(bytes(data), 9))]
    return page_pdf(600, b"/Sh sh\n", b"/Shading << /Sh 5 0 R >>")


def mesh_overflow():
    # 65,537 triangles that each cover the whole grid, two halves of the
    # page alternately, in few colours: a few KB of Flate. Their items per
    # cell summed past 2^32 in a uint32 (issue 45).
    halves = (((0, 0), (600, 0), (0, 600)), ((600, 600), (600, 0), (0, 600)))
    return mesh_pdf(65537, lambda k: halves[k % 2], lambda k: (200 * (k % 2), 100, 50))


def mesh_200k_large():
    # 200,000 triangles of 200 units a side over a 600-unit page: each
    # covers a ninth of the grid (by their boxes 1.5e9 items; 6.1 GB once).
    rnd = random.Random(3)

    def corners(k):
        x, y = rnd.uniform(0, 400), rnd.uniform(0, 400)
        return ((x, y), (x + 200, y), (x, y + 200))
    return mesh_pdf(200000, corners)


def separations_pdf(names):
    """A page painting a 10 x 10 square in each Separation named in names
    (PDF name syntax, # escapes allowed), 10 units apart."""
    spaces, content = b"", b""
    for i, name in enumerate(names):
        spaces += b"/CS%d [/Separation /%s /DeviceCMYK << /FunctionType 2 /Domain [0 1] /C0 [0 0 0 0] " \
                  b"/C1 [0 0.5 1 0] /N 1 >>] " % (i, name)
        content += b"/CS%d cs 1 scn %d %d 10 10 re f\n" % (i, 10 * (i % 9), 10 * (i // 9))
    EXTRA[:] = []
    return page_pdf(100, content, b"/ColorSpace << " + spaces + b">>")


def spot_names():
    # ../../../escaped, a/b and names equal but for case (issue 45).
    return separations_pdf([b"..#2F..#2F..#2Fescaped", b"a#2Fb", b"Gold", b"GOLD", b"Gr#C3#BCn"])


def spots_65():
    return separations_pdf([b"Spot%d" % i for i in range(65)])


SVG = '<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="200" height="200">'


def markers():
    # 1,000,000 markers (20,000 vertices in 50 polylines) of 100 stroked
    # subpaths each: 400 M stroke segments to make.
    rnd = random.Random(1)
    pts = " ".join("%d,%d" % (rnd.randrange(200), rnd.randrange(200)) for _ in range(20000))
    mark = " ".join("M%d,%d l1,1" % (i % 10, i // 10) for i in range(100))
    line = '<polyline fill="none" stroke="black" marker-mid="url(#m)" points="%s"/>' % pts
    return (SVG + '<marker id="m" markerWidth="10" markerHeight="10"><path d="%s" stroke="blue"/></marker>' % mark
            + line * 50 + "</svg>\n").encode()


def lines_1e5():
    rnd = random.Random(5)
    return ('<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="1000">' + "".join(
        '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % tuple(rnd.randrange(1000) for _ in range(4))
        for _ in range(100000)) + "</svg>\n").encode()


def filter_chain():
    # 10,000 blurs, each reading the one before (a chain holds two results).
    prims = "".join('<feGaussianBlur stdDeviation="1"/>' for _ in range(10000))
    return (SVG + '<filter id="f">%s</filter><rect width="100" height="100" fill="red" filter="url(#f)"/></svg>\n'
            % prims).encode()


def dash_200k():
    return (SVG + '<path d="M0,100 L200,100" stroke="black" stroke-dasharray="%s"/></svg>\n'
            % " ".join(["0.001"] * 200000)).encode()


MAKERS = {
    "gif-claim.svg": gif_claim,
    "png-16000.svg": png_16000,
    "image-20000.pdf": image_20000,
    "mesh-200k.pdf": mesh_200k,
    "strokes-1e5.svg": strokes_1e5,
    "page-14400.pdf": page_14400,
    "mesh-overflow.pdf": mesh_overflow,
    "mesh-200k-large.pdf": mesh_200k_large,
    "spot-names.pdf": spot_names,
    "spots-65.pdf": spots_65,
    "markers.svg": markers,
    "lines-1e5.svg": lines_1e5,
    "filter-chain.svg": filter_chain,
    "dash-200k.svg": dash_200k,
}


def main():
    out = sys.argv[1]
    names = sys.argv[2:] or list(MAKERS)
    os.makedirs(out, exist_ok=True)
    for name in names:
        with open(os.path.join(out, name), "wb") as f:
            f.write(MAKERS[name]())


if __name__ == "__main__":
    main()
