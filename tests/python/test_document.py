"""mpvg.Document and mpvg.Page as a PyMuPDF user expects them (a context
manager, len, indexing, iteration, close and ClosedError), the input rule
shared with render_svg, pdftoppm's sizes (-scale-to, -scale-to-x/-y: sizes
and pixels equal to pdf2png's) and the error hierarchy."""
import io
import os
import pathlib

import numpy as np
import pytest

import mpvg
from conftest import FEATURES, GOLDEN, PDFS, read_png, rgba, run

THREE = os.path.join(PDFS, "three-pages.pdf")
# A page that is not square, 260 x 180 pt (the sizes below tell the two
# axes apart).
TALL = os.path.join(PDFS, "page-boxes.pdf")


def test_context_manager_len_index_iterate():
    with mpvg.open(THREE, backend="cpu") as doc:
        assert isinstance(doc, mpvg.Document) and not doc.is_closed
        assert len(doc) == doc.page_count == 3 and doc.name == THREE
        pages = list(doc)
        assert [p.number for p in pages] == [0, 1, 2]
        assert doc[-1].number == 2 and doc[-3].number == 0 and doc.load_page(1).number == 1
        for bad in (3, -4, 100):
            with pytest.raises(IndexError):
                doc[bad]
        page = doc[1]
        assert isinstance(page, mpvg.Page) and page.parent is doc
        assert page.size == (100.0, 100.0) and page.rect == (0.0, 0.0, 100.0, 100.0)
        # page.render is doc.render of its number; the three pages differ
        # (red, green, blue squares).
        img = page.render(dpi=36, aa="1x8")
        assert np.array_equal(img, doc.render(1, dpi=36, aa="1x8"))
        assert img.shape == (50, 50, 4)
        centres = [tuple(p.render(dpi=36, aa="1x8")[25, 25, :3]) for p in doc]
        assert centres == [(255, 0, 0), (0, 153, 0), (0, 0, 255)]
        assert "3 pages" in repr(doc) and "100 x 100" in repr(page)
    assert doc.is_closed and "closed" in repr(doc)


def test_closed_document_raises_closed_error():
    doc = mpvg.Document(THREE, backend="cpu")
    page = doc[0]
    doc.close()
    doc.close()  # twice is fine, as files
    for use in (lambda: len(doc), lambda: doc[0], lambda: doc.render(0), lambda: page.render(),
                lambda: page.size, lambda: list(doc), lambda: doc.page_size(0), lambda: doc.render_pages(),
                lambda: doc.warnings):
        with pytest.raises(mpvg.ClosedError, match="^the document is closed$"):
            use()
    assert issubclass(mpvg.ClosedError, ValueError) and issubclass(mpvg.ClosedError, mpvg.Error)
    with pytest.raises(ValueError):
        len(doc)
    # A stream already running keeps its handle: close() does not pull the
    # document from under it.
    doc = mpvg.Document(THREE, backend="cpu")
    want = [doc.render(p, dpi=20) for p in range(3)]
    stream = doc.render_pages(dpi=20)
    doc.close()
    got = list(stream)
    assert len(got) == 3 and all(np.array_equal(g, w) for g, w in zip(got, want))


def test_exit_closes_on_an_exception():
    with pytest.raises(KeyError):
        with mpvg.Document(THREE, backend="cpu") as doc:
            raise KeyError("x")
    assert doc.is_closed


def test_input_rule_for_documents():
    data = open(THREE, "rb").read()
    want = mpvg.Document(THREE, backend="cpu").render(2, dpi=20)
    for source in (pathlib.Path(THREE), data, bytearray(data), memoryview(data), io.BytesIO(data),
                   open(THREE, "rb")):
        with mpvg.Document(source, backend="cpu") as doc:
            assert np.array_equal(doc.render(2, dpi=20), want), type(source)
    with mpvg.Document(data=data, backend="cpu") as doc:
        assert doc.name == "" and np.array_equal(doc.render(2, dpi=20), want)
    with pytest.raises(mpvg.OptionError, match="not both"):
        mpvg.Document(THREE, data=data)
    with pytest.raises(TypeError):
        mpvg.Document(42)
    with pytest.raises(TypeError):
        mpvg.Document()
    # A str starting with '<' is SVG text, whatever the call: Document
    # says what renders it.
    with pytest.raises(mpvg.UnsupportedError, match="render_svg"):
        mpvg.Document('  <svg xmlns="http://www.w3.org/2000/svg"/>')


def test_input_rule_for_svg(cpu, tmp_path):
    path = os.path.join(GOLDEN, "stroke_joins.svg")
    want = cpu.render_svg(path, width=64)
    text = open(path, encoding="utf-8").read()
    assert np.array_equal(cpu.render_svg(text, width=64), want)              # SVG text
    assert np.array_equal(cpu.render_svg("\n  " + text, width=64), want)     # after whitespace
    assert np.array_equal(cpu.render_svg(data=text, width=64), want)         # data= as str
    assert np.array_equal(cpu.render_svg(data=text.encode(), width=64), want)
    assert np.array_equal(cpu.render_svg(io.BytesIO(text.encode()), width=64), want)
    assert np.array_equal(cpu.render_svg(io.StringIO(text), width=64), want)
    with open(path, "rb") as f:
        assert np.array_equal(cpu.render_svg(f, width=64), want)
    # A str not starting with '<' is a path, even one that looks odd.
    odd = tmp_path / "svg text.svg"
    odd.write_text(text)
    assert np.array_equal(cpu.render_svg(str(odd), width=64), want)
    with pytest.raises(mpvg.ResourceError, match="cannot read"):
        cpu.render_svg("svg xmlns=not-a-file")
    with pytest.raises(mpvg.OptionError):
        cpu.render_svg(path, data=text)
    with pytest.raises(TypeError):
        cpu.render_svg()


def pdf2png_image(pdf2png, tmp_path, pdf, *args):
    out = str(tmp_path / "cli")
    run(pdf2png, "-q", "--backend", "cpu", "--singlefile", *args, pdf, out)
    return rgba(read_png(out + ".png"))


@pytest.mark.parametrize("pdf", [TALL, THREE])
@pytest.mark.parametrize("cli,kw", [
    (["-scale-to", "120"], dict(scale_to=120)),
    (["-scale-to", "37"], dict(scale_to=37)),
    (["-scale-to-x", "90", "-scale-to-y", "-1"], dict(width=90)),
    (["-scale-to-x", "-1", "-scale-to-y", "70"], dict(height=70)),
    (["-scale-to-x", "90", "-scale-to-y", "40"], dict(width=90, height=40)),
    (["-r", "50", "-ry", "80"], dict(dpi=50, dpi_y=80)),
])
def test_sizes_are_pdf2png_s(pdf2png, tmp_path, pdf, cli, kw):
    want = pdf2png_image(pdf2png, tmp_path, pdf, "--aa", "1x8", *cli)
    with mpvg.Document(pdf, backend="cpu") as doc:
        got = doc[0].render(aa="1x8", **kw)
        assert got.shape == want.shape, (cli, got.shape, want.shape)
        assert np.array_equal(got, want)
        # The same through render_pages (pdf2png's pipeline).
        assert np.array_equal(next(doc.render_pages([0], aa="1x8", **kw)), want)


def test_size_semantics():
    with mpvg.Document(TALL, backend="cpu") as doc:
        w, h = doc[0].size
        assert (w, h) == (260.0, 180.0) and doc[0].box_size("media") == (300.0, 200.0)
        assert doc[0].render(box="media", dpi=72, aa="1x8").shape[:2] == (200, 300)
        img = doc[0].render(scale_to=200, aa="1x8")
        assert max(img.shape[:2]) == 200
        wide = doc[0].render(width=150, aa="1x8")
        assert wide.shape[1] == 150 and abs(wide.shape[0] - round(150 * h / w)) <= 1
        both = doc[0].render(width=33, height=77, aa="1x8")
        assert both.shape[:2] == (77, 33)
        for bad in (dict(scale_to=0), dict(width=-3), dict(scale_to=10, width=5), dict(dpi_y=0)):
            with pytest.raises(mpvg.OptionError):
                doc[0].render(**bad)


def test_error_hierarchy():
    tree = {mpvg.DocumentError: mpvg.Error, mpvg.ParseError: mpvg.DocumentError,
            mpvg.PasswordError: mpvg.DocumentError, mpvg.UnsupportedError: mpvg.Error,
            mpvg.ResourceError: mpvg.Error, mpvg.MemoryLimitError: mpvg.ResourceError,
            mpvg.OptionError: mpvg.Error, mpvg.ClosedError: mpvg.Error}
    for kind, base in tree.items():
        assert issubclass(kind, base), kind
        assert kind.__module__ == "mpvg" and kind.__doc__
    assert issubclass(mpvg.Error, RuntimeError)
    assert issubclass(mpvg.OptionError, ValueError) and issubclass(mpvg.MemoryLimitError, MemoryError)
    assert not issubclass(mpvg.PasswordError, mpvg.ParseError)
    locked = os.path.join(PDFS, "encrypted-password-secret.pdf")
    with pytest.raises(mpvg.PasswordError, match="password=") as e:
        mpvg.Document(locked)
    assert "\n" not in str(e.value)
    with pytest.raises(mpvg.PasswordError, match="wrong password"):
        mpvg.Document(locked, password="guess")
    with pytest.raises(mpvg.ParseError):
        mpvg.Document(b"%PDF-1.7 not really")
    with pytest.raises(mpvg.DocumentError):
        mpvg.Document(b"%PDF-1.7 not really")
    with pytest.raises(mpvg.OptionError, match="unknown page box"):
        mpvg.Document(THREE).render(0, box="paper")
    with pytest.raises(mpvg.OptionError, match="resolution must be positive"):
        mpvg.Document(THREE).render(0, dpi=0)
    with pytest.raises(mpvg.OptionError):
        mpvg.Renderer("opengl")


def test_memory_limit_is_the_cli_s_line(svg2png, pdf2png, cpu, tmp_path):
    svg = os.path.join(GOLDEN, "arcs.svg")
    r = run(svg2png, "-q", "--backend", "cpu", "--max-memory", "16M", "-w", "3000", svg, tmp_path / "x.png",
            check=False, capture_output=True, text=True)
    assert r.returncode == 1
    with pytest.raises(mpvg.MemoryLimitError) as e:
        cpu.render_svg(svg, width=3000, max_memory="16M")
    assert "svg2png: %s\n" % e.value == r.stderr
    with pytest.raises(MemoryError):
        cpu.render_svg(svg, width=3000, max_memory=16 << 20)
    pdf = os.path.join(FEATURES, "blend-modes.pdf")
    r = run(pdf2png, "-q", "--backend", "cpu", "--max-memory", "16M", "-r", "2000", pdf, tmp_path / "p",
            check=False, capture_output=True, text=True)
    with pytest.raises(mpvg.MemoryLimitError) as e:
        mpvg.Document(pdf, backend="cpu").render(0, dpi=2000, max_memory="16M")
    assert r.returncode == 99 and ("pdf2png: page 1: %s\n" % e.value == r.stderr or str(e.value) in r.stderr)
