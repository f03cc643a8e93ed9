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


MAKERS = {
    "gif-claim.svg": gif_claim,
    "png-16000.svg": png_16000,
    "image-20000.pdf": image_20000,
    "mesh-200k.pdf": mesh_200k,
    "strokes-1e5.svg": strokes_1e5,
    "page-14400.pdf": page_14400,
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
