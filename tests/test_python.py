"""The Python module against svg2png: the arrays mpvg.Renderer.render_svg
returns are the pixels svg2png writes into its PNGs for the same options,
exactly; bytes input, 16 bits, errors, warnings and the GIL are checked too.

usage: PYTHONPATH=BUILD/python python3 test_python.py SVG2PNG SOURCE_DIR [PDF2PNG]
Exits 77 (skipped) where numpy is missing. With PDF2PNG, mpvg.Document's
pages are checked against pdf2png's PNGs the same way.
"""
import os
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

try:
    import numpy as np
except ImportError:
    print("test_python: skipped, numpy is missing")
    sys.exit(77)

import mpvg

SVG2PNG, SRC = sys.argv[1], sys.argv[2]
PDF2PNG = sys.argv[3] if len(sys.argv) > 3 else None
failures = 0


def check(ok, what):
    global failures
    print(("ok: " if ok else "FAILED: ") + what)
    if not ok:
        failures += 1


def read_png(path):
    """Decodes an 8- or 16-bit RGB or RGBA PNG (not interlaced) to an
    H x W x 4 array; RGB gets an opaque alpha. By hand, so that 16-bit
    values are read exactly."""
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
    assert colour in (2, 6) and depth in (8, 16) and interlace == 0, "unsupported PNG"
    channels = 4 if colour == 6 else 3
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
        px = (out[:, 0::2] << 8 | out[:, 1::2]).astype(np.uint16).reshape(height, width, channels)
    else:
        px = out.astype(np.uint8).reshape(height, width, channels)
    if channels == 3:
        alpha = np.full((height, width, 1), 65535 if depth == 16 else 255, dtype=px.dtype)
        px = np.concatenate([px, alpha], axis=2)
    return px


def svg2png(svg, args, tmp):
    out = os.path.join(tmp, "out.png")
    subprocess.run([SVG2PNG, "-q", "--backend", "cpu", *args, svg, out], check=True)
    return read_png(out)


renderer = mpvg.Renderer("cpu")
check(renderer.backend == "cpu", "Renderer('cpu') renders on the CPU")
auto = mpvg.Renderer()
check(auto.backend in ("cpu", "cuda") and (auto.backend == "cuda" or auto.note != ""),
      "Renderer() resolves auto, with a note when it takes the CPU: " + auto.note)

golden = os.path.join(SRC, "testdata", "golden")
cases = [
    # (document, svg2png options, the same as keyword arguments)
    ("opacity.svg", [], {}),
    ("stroke_joins.svg", ["-w", "200", "--aa", "1x32", "--gamma", "srgb", "-b", "#336699"],
     dict(width=200, aa="1x32", gamma="srgb", background="#336699")),
    ("image_rendering.svg", ["-z", "0.75", "--aa", "1x8", "--seed", "3"], dict(zoom=0.75, aa="1x8", seed=3)),
    ("gradient_reflect.svg", ["-w", "90", "-h", "50"], dict(width=90, height=50)),
    ("arcs.svg", ["-w", "100", "-h", "100", "-a", "-b", "rgba(255,0,0,0.5)"],
     dict(width=100, height=100, keep_aspect_ratio=True, background=(1.0, 0.0, 0.0, 0.5))),
]
with tempfile.TemporaryDirectory() as tmp:
    for name, args, kwargs in cases:
        path = os.path.join(golden, name)
        want = svg2png(path, args, tmp)
        got = renderer.render_svg(path, **kwargs)
        check(got.dtype == np.uint8 and got.shape == want.shape and np.array_equal(got, want),
              "%s %s: the same pixels as svg2png (%s vs %s)" % (name, " ".join(args), got.shape, want.shape))

    # The document as bytes, bytearray and memoryview, and a path-like.
    path = os.path.join(golden, "stroke_joins.svg")
    by_path = renderer.render_svg(path, width=64)
    text = open(path, "rb").read()
    check(np.array_equal(renderer.render_svg(text, width=64), by_path), "bytes render as the file does")
    check(np.array_equal(renderer.render_svg(bytearray(text), width=64), by_path), "bytearray renders as bytes")
    check(np.array_equal(renderer.render_svg(memoryview(text), width=64), by_path), "memoryview renders as bytes")
    import pathlib
    check(np.array_equal(renderer.render_svg(pathlib.Path(path), width=64), by_path), "a pathlib.Path is a file")

    # 16 bits, against svg2png --bits 16.
    path = os.path.join(golden, "gradient_repeat.svg")
    want = svg2png(path, ["--bits", "16", "--aa", "1x32"], tmp)
    got = renderer.render_svg(path, bits=16, aa="1x32")
    check(got.dtype == np.uint16 and got.ndim == 3 and got.shape[2] == 4, "bits=16 gives H x W x 4 uint16")
    check(got.shape == want.shape and np.array_equal(got, want), "bits=16: the same values as svg2png --bits 16")
    check(int(got.max()) > 255 and bool(np.any(got % 257 != 0)), "bits=16 carries more than 8 bits")

    # Relative image references resolve against base_dir, inside its tree
    # (or allow_read's) only.
    os.makedirs(os.path.join(tmp, "doc"))
    green = ('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
             '<rect width="4" height="4" fill="#00ff00"/></svg>')
    for name in ("doc/inside.svg", "outside.svg"):
        with open(os.path.join(tmp, name), "w") as f:
            f.write(green)
    def page(href):
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8">'
                '<image width="8" height="8" href="%s"/></svg>' % href).encode()
    doc = os.path.join(tmp, "doc")
    img = renderer.render_svg(page("inside.svg"), aa="1x8", base_dir=doc)
    check(img[4, 4].tolist() == [0, 255, 0, 255], "an image in base_dir's tree is drawn")
    img = renderer.render_svg(page("../outside.svg"), aa="1x8", base_dir=doc)
    check(img[4, 4].tolist() == [0, 0, 0, 0] and len(renderer.warnings) > 0,
          "an image outside base_dir's tree is not read, with a warning: %s" % renderer.warnings)
    img = renderer.render_svg(page("../outside.svg"), aa="1x8", base_dir=doc, allow_read=[tmp])
    check(img[4, 4].tolist() == [0, 255, 0, 255], "allow_read lets it be read")

# Errors.
try:
    renderer.render_svg(b'<svg xmlns="http://www.w3.org/2000/svg"><rect</svg>')
    check(False, "malformed SVG raises")
except mpvg.Error as e:
    check(isinstance(e, RuntimeError) and "XML parse error" in str(e), "malformed SVG raises mpvg.Error: %s" % e)
try:
    renderer.render_svg(os.path.join(SRC, "testdata", "no-such-file.svg"))
    check(False, "a missing file raises")
except RuntimeError as e:
    check("cannot read" in str(e), "a missing file raises mpvg.Error: %s" % e)
for bad in (dict(aa="2x2"), dict(gamma="log"), dict(bits=12), dict(width=-5), dict(background="notacolour")):
    try:
        renderer.render_svg(os.path.join(golden, "arcs.svg"), **bad)
        check(False, "%s raises" % bad)
    except (ValueError, mpvg.Error) as e:
        check(True, "%s raises %s: %s" % (bad, type(e).__name__, e))
try:
    renderer.render_svg(42)
    check(False, "an int raises TypeError")
except TypeError:
    check(True, "an int raises TypeError")
try:
    mpvg.Renderer("opengl")
    check(False, "an unknown backend raises")
except ValueError:
    check(True, "an unknown backend raises ValueError")

# The GIL is released while rendering: this thread keeps running Python
# while another renders. Held, the longest pause here would be the whole
# render.
example = os.path.join(SRC, "testdata", "example.svg")
t0 = time.perf_counter()
renderer.render_svg(example, width=400)
alone = time.perf_counter() - t0
worker = threading.Thread(target=lambda: renderer.render_svg(example, width=400))
last = time.perf_counter()
longest = 0.0
worker.start()
while worker.is_alive():
    now = time.perf_counter()
    longest = max(longest, now - last)
    last = now
worker.join()
check(alone > 0.05 and longest < alone / 2,
      "the GIL is released while rendering (render %.0f ms, longest pause %.0f ms)" % (alone * 1e3, longest * 1e3))

# ---- PDF: mpvg.Document against pdf2png's PNGs, byte for byte.
if PDF2PNG:
    features = os.path.join(SRC, "testdata", "pdf", "features")
    with tempfile.TemporaryDirectory() as tmp:
        for name, args, kw in [
                ("blend-modes", [], {}),
                ("shading-axial", ["--aa", "1x32", "-r", "72"], dict(aa="1x32", dpi=72)),
                ("image-smask", ["-r", "100", "--transparent"], dict(dpi=100, background=None)),
                ("clips", ["--bits", "16", "-r", "50"], dict(bits=16, dpi=50)),
                ("annotations", ["-hide-annotations", "--thin-lines", "snap", "--box", "media"],
                 dict(annotations=False, thin_lines="snap", box="media"))]:
            pdf = os.path.join(features, name + ".pdf")
            out = os.path.join(tmp, name)
            subprocess.run([PDF2PNG, "-q", "--backend", "cpu", "--singlefile"] + args + [pdf, out], check=True)
            want = read_png(out + ".png")
            doc = mpvg.Document(pdf, backend="cpu")
            got = doc.render(0, **kw)
            check(got.shape == want.shape and got.dtype == want.dtype and (got == want).all(),
                  "Document('%s').render(0, %s) is pdf2png %s's pixels" % (name, kw, " ".join(args)))
    doc = mpvg.Document(os.path.join(SRC, "testdata", "pdf", "three-pages.pdf"), backend="cpu")
    check(len(doc) == 3, "len(Document) is the page count (%d)" % len(doc))
    check(doc.page_size(0) == (100.0, 100.0) and doc.page_size(-1) == doc.page_size(2),
          "page_size in points, -1 the last page")
    data = open(os.path.join(features, "blend-modes.pdf"), "rb").read()
    check((mpvg.Document(data, backend="cpu").render(0, dpi=40) ==
           mpvg.Document(os.path.join(features, "blend-modes.pdf"), backend="cpu").render(0, dpi=40)).all(),
          "a Document of bytes renders as the file does")
    for bad, exc in [(lambda: mpvg.Document(os.path.join(SRC, "testdata", "pdf", "encrypted-password-secret.pdf")),
                      mpvg.Error),
                     (lambda: mpvg.Document(b"not a pdf"), mpvg.Error),
                     (lambda: doc.render(3), IndexError),
                     (lambda: doc.render(0, box="paper"), ValueError),
                     (lambda: doc.render(0, dpi=0), mpvg.Error)]:
        try:
            bad()
            check(False, "%s raised" % exc.__name__)
        except exc as e:
            check(True, "%s: %s" % (exc.__name__, e))
    # render_pages: pdf2png's pipeline, arrays in the order asked, each
    # what render() gives; a page that fails raises at its turn.
    three = mpvg.Document(os.path.join(SRC, "testdata", "pdf", "three-pages.pdf"), backend="cpu")
    order = [2, 0, 1, 2, -1]
    got = list(three.render_pages(order, dpi=36, aa="1x8", threads=2))
    want = [three.render(p, dpi=36, aa="1x8") for p in order]
    check(len(got) == 5 and all(g.shape == w.shape and (g == w).all() for g, w in zip(got, want)),
          "render_pages yields render()'s arrays in the order asked (%s)" % order)
    bad = mpvg.Document(os.path.join(SRC, "testdata", "pdf", "three-pages-bad-page2.pdf"), backend="cpu")
    stream = bad.render_pages(dpi=20)
    results = []
    for k in range(3):
        try:
            results.append(next(stream).shape)
        except mpvg.Error as e:
            results.append("Error: " + str(e))
    check(isinstance(results[0], tuple) and str(results[1]).startswith("Error: page 2") and
          isinstance(results[2], tuple), "a page that fails raises mpvg.Error at its turn, the others render (%s)"
          % results)
    try:
        next(stream)
        check(False, "the stream ends after the last page")
    except StopIteration:
        check(True, "the stream ends after the last page")
    stream = three.render_pages(dpi=20)
    first = next(stream)
    stream.close()
    check(first.shape[2] == 4, "close() stops a stream early")
    if mpvg.Renderer("auto").backend == "cpu":  # (the GPU host checks batches: scripts/gpu-python-check.sh)
        try:
            cpu_doc0 = mpvg.Document(os.path.join(features, "blend-modes.pdf"), backend="cpu")
            cpu_doc0.render_batch([0])
            check(False, "render_batch without a CUDA device raises mpvg.Error")
        except mpvg.Error as e:
            check(True, "render_batch without a CUDA device raises mpvg.Error: %s" % e)
    import warnings as pywarnings
    # (colorspace-iccbased warns where MuPDF has no ICC support, as Debian's.)
    ann = mpvg.Document(os.path.join(features, "colorspace-iccbased.pdf"), backend="cpu")
    with pywarnings.catch_warnings(record=True) as caught:
        pywarnings.simplefilter("always")
        ann.render(0, dpi=20)
    texts = [str(w.message) for w in caught]
    check(texts == ["page 1: " + w for w in ann.warnings],
          "render's warnings go to Python's warnings module as well (%s)" % texts)
    quiet = mpvg.Document(os.path.join(features, "blend-modes.pdf"), backend="cpu")
    with pywarnings.catch_warnings(record=True) as caught:
        pywarnings.simplefilter("always")
        quiet.render(0, dpi=20)
    check(not caught and not quiet.warnings, "a page without warnings warns nothing")
    cpu_doc = mpvg.Document(os.path.join(features, "blend-modes.pdf"), backend="cpu")
    for bad, exc in [(lambda: cpu_doc.render(0, device="cuda"), mpvg.Error),
                     (lambda: cpu_doc.render(0, device="tpu"), ValueError)]:
        try:
            bad()
            check(False, "%s raised" % exc.__name__)
        except exc as e:
            check(True, "device output: %s: %s" % (exc.__name__, e))
    # python -m mpvg IN.pdf PREFIX: pdf2png's files and pixels.
    three_pdf = os.path.join(SRC, "testdata", "pdf", "three-pages.pdf")
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([PDF2PNG, "-q", "--backend", "cpu", "-r", "40", "-f", "2", three_pdf, os.path.join(tmp, "cli")],
                       check=True)
        rc = subprocess.run([sys.executable, "-m", "mpvg", "--backend", "cpu", "-r", "40", "-f", "2", three_pdf,
                             os.path.join(tmp, "mod")]).returncode
        names = sorted(f for f in os.listdir(tmp))
        same = rc == 0 and all((read_png(os.path.join(tmp, "cli-%d.png" % k)) ==
                                read_png(os.path.join(tmp, "mod-%d.png" % k))).all() for k in (2, 3))
        check(same and names == ["cli-2.png", "cli-3.png", "mod-2.png", "mod-3.png"],
              "python -m mpvg IN.pdf PREFIX writes pdf2png's files and pixels (%s)" % names)
    # The kinds of mpvg.Error.
    for what, bad, kind in [
            ("malformed XML", lambda: mpvg.Renderer("cpu").render_svg(b"<svg"), mpvg.ParseError),
            ("a broken PDF", lambda: mpvg.Document(b"%PDF-1.7 not really"), mpvg.ParseError),
            ("a missing SVG file", lambda: mpvg.Renderer("cpu").render_svg("/nonexistent/x.svg"), mpvg.ResourceError),
            ("a missing PDF file", lambda: mpvg.Document("/nonexistent/x.pdf"), mpvg.ResourceError),
            ("device output on the CPU", lambda: cpu_doc.render(0, device="cuda"), mpvg.UnsupportedError)]:
        try:
            bad()
            check(False, "%s raises %s" % (what, kind.__name__))
        except mpvg.Error as e:
            check(type(e) is kind, "%s raises %s, an mpvg.Error (%s: %s)" % (what, kind.__name__, type(e).__name__, e))
    locked = mpvg.Document(os.path.join(SRC, "testdata", "pdf", "encrypted-password-secret.pdf"), password="secret",
                           backend="cpu")
    check(len(locked) >= 1, "an encrypted document opens with its password")

print("%d failure(s)" % failures)
sys.exit(1 if failures else 0)
