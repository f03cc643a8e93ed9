"""Fixtures of the Python package's tests (run by CTest as test_python:
python3 -m pytest tests/python, with PYTHONPATH at the build's package and
MPVG_SVG2PNG, MPVG_PDF2PNG, MPVG_COMPARE naming the command-line tools the
arrays are checked against; MPVG_SOURCE_DIR the source tree)."""
import os
import struct
import subprocess
import zlib

import numpy as np
import pytest

import mpvg

SRC = os.environ.get("MPVG_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
GOLDEN = os.path.join(SRC, "testdata", "golden")
FEATURES = os.path.join(SRC, "testdata", "pdf", "features")
PDFS = os.path.join(SRC, "testdata", "pdf")


def tool(variable):
    path = os.environ.get(variable, "")
    if not path or not os.path.exists(path):
        pytest.skip("%s is not set (the tool is not built)" % variable)
    return path


@pytest.fixture(scope="session")
def svg2png():
    return tool("MPVG_SVG2PNG")


@pytest.fixture(scope="session")
def pdf2png():
    return tool("MPVG_PDF2PNG")


@pytest.fixture(scope="session")
def compare_tool():
    return tool("MPVG_COMPARE")


@pytest.fixture(scope="session")
def cpu():
    return mpvg.Renderer("cpu")


def read_png(path):
    """Decodes an 8- or 16-bit grey, grey-alpha, RGB or RGBA PNG (not
    interlaced) to an H x W x C array, C as stored, by hand: independent of
    the encoder under test and of the library's decoder."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    assert colour in (0, 2, 4, 6) and depth in (8, 16) and interlace == 0, "unsupported PNG"
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
    bpp = channels * depth // 8
    row = width * bpp
    raw = zlib.decompress(idat)
    out = np.zeros((height, row), dtype=np.int32)
    prev = np.zeros(row, dtype=np.int32)
    for y in range(height):
        f = raw[y * (row + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=row, offset=y * (row + 1) + 1).astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 255
        else:  # Sub, Average, Paeth depend on the bytes to the left: byte by byte
            cur = line.copy()
            for i in range(row):
                a = int(cur[i - bpp]) if i >= bpp else 0
                b = int(prev[i])
                c = int(prev[i - bpp]) if i >= bpp else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (int(line[i]) + pred) & 255
        out[y] = cur
        prev = cur
    if depth == 16:
        return (out[:, 0::2] << 8 | out[:, 1::2]).astype(np.uint16).reshape(height, width, channels)
    return out.astype(np.uint8).reshape(height, width, channels)


def rgba(px):
    """RGB as RGBA (opaque), as pdf2png writes opaque pages as RGB."""
    if px.shape[2] == 3:
        full = 65535 if px.dtype == np.uint16 else 255
        px = np.concatenate([px, np.full(px.shape[:2] + (1,), full, dtype=px.dtype)], axis=2)
    return px


def run(*args, **kw):
    return subprocess.run([str(a) for a in args], check=kw.pop("check", True), **kw)
