#!/usr/bin/python3
"""Writes the tiny images of testdata/images/ that the <image> tests read
(tests/test_svg_resources.cpp, tests/test_svg_image.cpp). Run by hand from
the repository root; the output is committed:

    /usr/bin/python3 scripts/make_test_images.py

Needs PIL (Debian: python3-pil). 16-bit PNGs are written by hand, as PIL
cannot write 16-bit colour; the pixel values are listed here so that the
tests can state them.
"""
import gzip
import os
import struct
import zlib

from PIL import Image

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testdata", "images")


def path(name):
    return os.path.join(OUT, name)


def png_chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def write_png16(name, width, height, color_type, channels, samples):
    """A 16-bit PNG: color_type 0 (grey) or 6 (RGBA), samples row by row."""
    raw = b""
    for y in range(height):
        raw += b"\0" + b"".join(struct.pack(">H", v) for v in samples[y * width * channels:(y + 1) * width * channels])
    data = b"\x89PNG\r\n\x1a\n"
    data += png_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, color_type, 0, 0, 0))
    data += png_chunk(b"IDAT", zlib.compress(raw, 9))
    data += png_chunk(b"IEND", b"")
    with open(path(name), "wb") as f:
        f.write(data)


def main():
    os.makedirs(os.path.join(OUT, "nested"), exist_ok=True)

    # 2x2 straight-alpha RGBA: red opaque, green half, blue quarter, clear white.
    rgba = Image.new("RGBA", (2, 2))
    rgba.putdata([(255, 0, 0, 255), (0, 255, 0, 128), (0, 0, 255, 64), (255, 255, 255, 0)])
    rgba.save(path("rgba8.png"), optimize=True)

    # 3x2 palette with tRNS: red opaque, green half, blue transparent.
    pal = Image.new("P", (3, 2))
    pal.putpalette([255, 0, 0, 0, 255, 0, 0, 0, 255])
    pal.putdata([0, 1, 2, 2, 1, 0])
    pal.save(path("palette_trns.png"), transparency=bytes([255, 128, 0]))

    # 2x1 greyscale, and greyscale with alpha.
    grey = Image.new("L", (2, 1))
    grey.putdata([0, 200])
    grey.save(path("grey.png"))
    grey_alpha = Image.new("LA", (2, 1))
    grey_alpha.putdata([(50, 255), (200, 100)])
    grey_alpha.save(path("grey_alpha.png"))

    # 16 bits: 2x1 RGBA and 2x1 grey, low bytes that 8 bits would lose.
    write_png16("rgba16.png", 2, 1, 6, 4, [0x1234, 0x5678, 0x9ABC, 0xFFFF, 0xFEDC, 0xBA98, 0x7654, 0x8000])
    write_png16("grey16.png", 2, 1, 0, 1, [0x0102, 0xF0E0])

    # 4x2: the aspect ratio matters for placement tests.
    wide = Image.new("RGBA", (4, 2), (0, 128, 255, 255))
    wide.save(path("wide4x2.png"))

    # 8x8 JPEGs of one colour each (quality 100: decoded within a few levels).
    Image.new("RGB", (8, 8), (200, 100, 50)).save(path("rgb.jpg"), quality=100, subsampling=0)
    Image.new("L", (8, 8), 128).save(path("grey.jpg"), quality=100)
    # CMYK: full magenta and yellow, i.e. red.
    Image.new("CMYK", (8, 8), (0, 255, 255, 0)).save(path("cmyk.jpg"), quality=100)

    # 2x2 GIF: red, green, blue, transparent.
    gif = Image.new("P", (2, 2))
    gif.putpalette([255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0])
    gif.putdata([0, 1, 2, 3])
    gif.save(path("rgb.gif"), transparency=3)

    # 2x2 lossless WebP with alpha.
    webp = Image.new("RGBA", (2, 2))
    webp.putdata([(255, 0, 0, 255), (0, 255, 0, 128), (0, 0, 255, 64), (200, 100, 50, 200)])
    webp.save(path("rgba.webp"), lossless=True)

    # SVG documents embedded by <image>: a 20x10 one drawing a rect and the
    # raster one folder up (relative to its own folder), as svg and svgz; a
    # document embedding itself; two embedding each other.
    inner = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10" viewBox="0 0 20 10">'
             '<rect width="20" height="10" fill="#00f"/>'
             '<image x="10" width="10" height="10" href="../rgba8.png" preserveAspectRatio="none"/></svg>\n')
    with open(path("nested/inner.svg"), "w") as f:
        f.write(inner)
    with open(path("nested/inner.svgz"), "wb") as f:
        f.write(gzip.compress(inner.encode(), mtime=0))
    with open(path("self.svg"), "w") as f:
        f.write('<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10">'
                '<rect width="10" height="10" fill="#0f0"/>'
                '<image x="2" y="2" width="6" height="6" href="self.svg"/></svg>\n')
    for me, other in (("cycle_a.svg", "cycle_b.svg"), ("cycle_b.svg", "cycle_a.svg")):
        with open(path(me), "w") as f:
            f.write('<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10">'
                    '<rect width="10" height="10" fill="#f00"/>'
                    '<image x="2" y="2" width="6" height="6" href="%s"/></svg>\n' % other)


if __name__ == "__main__":
    main()
