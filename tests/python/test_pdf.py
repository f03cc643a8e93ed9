"""mpvg.Document against pdf2png: the arrays are the pixels pdf2png writes
for the same options, exactly (RGB, 16 bits, grey, CMYK); page streaming,
errors, warnings and python -m mpvg."""
import os
import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mpvg
from conftest import FEATURES, PDFS, read_png, rgba, run


def read_tiff(path):
    """The pixels of an uncompressed, contiguous 8-bit TIFF (one IFD) as
    H x W x C: what pdf2png -tiffcompression none writes."""
    data = open(path, "rb").read()
    order = "<" if data[:2] == b"II" else ">"
    (ifd,) = struct.unpack(order + "I", data[4:8])
    (count,) = struct.unpack(order + "H", data[ifd:ifd + 2])
    tags = {}
    for k in range(count):
        tag, kind, n, value = struct.unpack(order + "HHII", data[ifd + 2 + 12 * k:ifd + 14 + 12 * k])
        size = {3: 2, 4: 4}.get(kind, 1)
        if kind == 3 and n == 1:
            value &= 0xFFFF if order == "<" else value >> 16
        if n * size > 4:  # an array elsewhere
            fmt = order + ("H" if kind == 3 else "I") * n
            value = list(struct.unpack(fmt, data[value:value + n * size]))
        tags[tag] = value if isinstance(value, list) else [value]
    width, height, channels = tags[256][0], tags[257][0], tags[277][0]
    assert tags.get(259, [1])[0] == 1 and tags[258][0] == 8, "not an uncompressed 8-bit TIFF"
    pixels = b"".join(data[o:o + n] for o, n in zip(tags[273], tags[279]))
    return np.frombuffer(pixels, dtype=np.uint8).reshape(height, width, channels)


@pytest.mark.parametrize("name,args,kw", [
    ("blend-modes", [], {}),
    ("shading-axial", ["--aa", "1x32", "-r", "72"], dict(aa="1x32", dpi=72)),
    ("image-smask", ["-r", "100", "--transparent"], dict(dpi=100, background=None)),
    ("clips", ["--bits", "16", "-r", "50"], dict(bits=16, dpi=50)),
    ("annotations", ["-hide-annotations", "--thin-lines", "snap", "--box", "media"],
     dict(annotations=False, thin_lines="snap", box="media")),
    ("blend-modes", ["-gray", "-r", "60"], dict(colorspace="gray", dpi=60)),
    ("image-smask", ["-gray", "-r", "40", "--transparent"], dict(colorspace="gray", dpi=40, background=None)),
    ("clips", ["-gray", "--bits", "16", "-r", "30"], dict(colorspace="gray", bits=16, dpi=30)),
])
def test_same_pixels_as_pdf2png(pdf2png, tmp_path, name, args, kw):
    pdf = os.path.join(FEATURES, name + ".pdf")
    out = str(tmp_path / name)
    run(pdf2png, "-q", "--backend", "cpu", "--singlefile", *args, pdf, out)
    want = read_png(out + ".png")
    got = mpvg.Document(pdf, backend="cpu").render(0, **kw)
    if kw.get("colorspace") == "gray":
        # One channel over an opaque background; grey and alpha over a
        # transparent one (the PNG drops alpha where every pixel is opaque).
        assert got.shape[2] == (2 if "background" in kw else 1)
        if got.shape[2] == 2 and want.shape[2] == 1:
            assert (got[..., 1] == 255).all()
            got = got[..., :1]
    else:
        want = rgba(want)
    assert got.shape == want.shape and got.dtype == want.dtype
    assert (got == want).all()


@pytest.mark.parametrize("name", ["print-preview.pdf", "rgb-inks.pdf", "features/colorspace-cmyk.pdf",
                                  "features/blend-modes.pdf"])
def test_cmyk_is_pdf2png_tiff(pdf2png, tmp_path, name):
    pdf = os.path.join(PDFS, name)
    name = os.path.basename(name)[:-4]
    out = str(tmp_path / name)
    r = run(pdf2png, "-q", "--backend", "cpu", "--singlefile", "--colorspace", "cmyk", "-tiffcompression", "none",
            "-r", "50", pdf, out, check=False, capture_output=True, text=True)
    if r.returncode != 0 and "TIFF" in r.stderr:
        pytest.skip("pdf2png writes no TIFF in this build: " + r.stderr.strip())
    assert r.returncode == 0, r.stderr
    want = read_tiff(out + ".tif")
    got = mpvg.Document(pdf, backend="cpu").render(0, dpi=50, colorspace="cmyk")
    assert got.dtype == np.uint8 and got.shape == want.shape and got.shape[2] == 4
    assert (got == want).all()


def test_document_basics():
    doc = mpvg.Document(os.path.join(PDFS, "three-pages.pdf"), backend="cpu")
    assert len(doc) == 3
    assert doc.page_size(0) == (100.0, 100.0) and doc.page_size(-1) == doc.page_size(2)
    path = os.path.join(FEATURES, "blend-modes.pdf")
    data = open(path, "rb").read()
    assert (mpvg.Document(data, backend="cpu").render(0, dpi=40) ==
            mpvg.Document(path, backend="cpu").render(0, dpi=40)).all()
    locked = mpvg.Document(os.path.join(PDFS, "encrypted-password-secret.pdf"), password="secret", backend="cpu")
    assert len(locked) >= 1


def test_errors():
    doc = mpvg.Document(os.path.join(PDFS, "three-pages.pdf"), backend="cpu")
    cpu_doc = mpvg.Document(os.path.join(FEATURES, "blend-modes.pdf"), backend="cpu")
    for bad, kind in [
            (lambda: mpvg.Document(os.path.join(PDFS, "encrypted-password-secret.pdf")), mpvg.Error),
            (lambda: mpvg.Document(b"not a pdf"), mpvg.Error),
            (lambda: mpvg.Document(b"%PDF-1.7 not really"), mpvg.ParseError),
            (lambda: mpvg.Document("/nonexistent/x.pdf"), mpvg.ResourceError),
            (lambda: doc.render(3), IndexError),
            (lambda: doc.render(0, box="paper"), ValueError),
            (lambda: doc.render(0, dpi=0), mpvg.Error),
            (lambda: doc.render(0, colorspace="lab"), ValueError),
            (lambda: doc.render(0, colorspace="cmyk", bits=16), ValueError),
            (lambda: doc.render(0, colorspace="gray", device="cuda"), ValueError),
            (lambda: cpu_doc.render(0, device="tpu"), ValueError),
            (lambda: cpu_doc.render(0, device="cuda"), mpvg.UnsupportedError),
            (lambda: cpu_doc.render_pages([0], device="cuda"), ValueError)]:
        with pytest.raises(kind):
            bad()


def test_render_pages_order_and_failures():
    three = mpvg.Document(os.path.join(PDFS, "three-pages.pdf"), backend="cpu")
    order = [2, 0, 1, 2, -1]
    got = list(three.render_pages(order, dpi=36, aa="1x8", threads=2))
    want = [three.render(p, dpi=36, aa="1x8") for p in order]
    assert len(got) == 5 and all(g.shape == w.shape and (g == w).all() for g, w in zip(got, want))
    gray = list(three.render_pages([1], dpi=36, colorspace="gray"))
    assert gray[0].shape[2] == 1 and (gray[0] == three.render(1, dpi=36, colorspace="gray")).all()
    # A page that fails raises at its turn; the others render.
    bad = mpvg.Document(os.path.join(PDFS, "three-pages-bad-page2.pdf"), backend="cpu")
    stream = bad.render_pages(dpi=20)
    assert next(stream).ndim == 3
    with pytest.raises(mpvg.Error, match="^page 2"):
        next(stream)
    assert next(stream).ndim == 3
    with pytest.raises(StopIteration):
        next(stream)
    stream = three.render_pages(dpi=20)
    assert next(stream).shape[2] == 4
    stream.close()


def test_render_batch_needs_cuda():
    if mpvg.Renderer("auto").backend != "cpu":
        pytest.skip("a CUDA device is present (the GPU host checks batches: scripts/gpu-python-check.sh)")
    with pytest.raises(mpvg.Error):
        mpvg.Document(os.path.join(FEATURES, "blend-modes.pdf"), backend="cpu").render_batch([0])


def test_warnings():
    # (colorspace-iccbased warns where MuPDF has no ICC support, as Debian's.)
    doc = mpvg.Document(os.path.join(FEATURES, "colorspace-iccbased.pdf"), backend="cpu")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        doc.render(0, dpi=20)
    assert [str(w.message) for w in caught] == ["page 1: " + w for w in doc.warnings]
    quiet = mpvg.Document(os.path.join(FEATURES, "blend-modes.pdf"), backend="cpu")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        quiet.render(0, dpi=20)
    assert not caught and not quiet.warnings


def test_python_m_mpvg(pdf2png, tmp_path):
    three = os.path.join(PDFS, "three-pages.pdf")
    run(pdf2png, "-q", "--backend", "cpu", "-r", "40", "-f", "2", three, tmp_path / "cli")
    run(sys.executable, "-m", "mpvg", "--backend", "cpu", "-r", "40", "-f", "2", three, tmp_path / "mod")
    assert sorted(os.listdir(tmp_path)) == ["cli-2.png", "cli-3.png", "mod-2.png", "mod-3.png"]
    for k in (2, 3):
        assert (read_png(tmp_path / ("cli-%d.png" % k)) == read_png(tmp_path / ("mod-%d.png" % k))).all()
