"""mpvg.Renderer.render_svg against svg2png: the arrays are the pixels
svg2png writes into its PNGs for the same options, exactly; bytes input, 16
bits, errors, warnings and the GIL are checked too."""
import os
import pathlib
import threading
import time

import numpy as np
import pytest

import mpvg
from conftest import GOLDEN, SRC, read_png, rgba, run


def svg2png_pixels(svg2png, svg, args, tmp):
    out = os.path.join(tmp, "out.png")
    run(svg2png, "-q", "--backend", "cpu", *args, svg, out)
    return rgba(read_png(out))


def test_backends():
    assert mpvg.Renderer("cpu").backend == "cpu"
    auto = mpvg.Renderer()
    assert auto.backend in ("cpu", "cuda") and (auto.backend == "cuda" or auto.note != "")
    with pytest.raises(ValueError):
        mpvg.Renderer("opengl")


@pytest.mark.parametrize("name,args,kwargs", [
    ("opacity.svg", [], {}),
    ("stroke_joins.svg", ["-w", "200", "--aa", "1x32", "--gamma", "srgb", "-b", "#336699"],
     dict(width=200, aa="1x32", gamma="srgb", background="#336699")),
    ("image_rendering.svg", ["-z", "0.75", "--aa", "1x8", "--seed", "3"], dict(zoom=0.75, aa="1x8", seed=3)),
    ("gradient_reflect.svg", ["-w", "90", "-h", "50"], dict(width=90, height=50)),
    ("arcs.svg", ["-w", "100", "-h", "100", "-a", "-b", "rgba(255,0,0,0.5)"],
     dict(width=100, height=100, keep_aspect_ratio=True, background=(1.0, 0.0, 0.0, 0.5))),
])
def test_same_pixels_as_svg2png(svg2png, cpu, tmp_path, name, args, kwargs):
    path = os.path.join(GOLDEN, name)
    want = svg2png_pixels(svg2png, path, args, str(tmp_path))
    got = cpu.render_svg(path, **kwargs)
    assert got.dtype == np.uint8 and got.shape == want.shape
    assert np.array_equal(got, want)


def test_inputs(cpu):
    path = os.path.join(GOLDEN, "stroke_joins.svg")
    by_path = cpu.render_svg(path, width=64)
    text = open(path, "rb").read()
    assert np.array_equal(cpu.render_svg(text, width=64), by_path)
    assert np.array_equal(cpu.render_svg(bytearray(text), width=64), by_path)
    assert np.array_equal(cpu.render_svg(memoryview(text), width=64), by_path)
    assert np.array_equal(cpu.render_svg(pathlib.Path(path), width=64), by_path)
    with pytest.raises(TypeError):
        cpu.render_svg(42)


def test_16_bits(svg2png, cpu, tmp_path):
    path = os.path.join(GOLDEN, "gradient_repeat.svg")
    want = svg2png_pixels(svg2png, path, ["--bits", "16", "--aa", "1x32"], str(tmp_path))
    got = cpu.render_svg(path, bits=16, aa="1x32")
    assert got.dtype == np.uint16 and got.ndim == 3 and got.shape[2] == 4
    assert got.shape == want.shape and np.array_equal(got, want)
    assert int(got.max()) > 255 and bool(np.any(got % 257 != 0))


def test_image_references_stay_inside(cpu, tmp_path):
    os.makedirs(tmp_path / "doc")
    green = ('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
             '<rect width="4" height="4" fill="#00ff00"/></svg>')
    for name in ("doc/inside.svg", "outside.svg"):
        (tmp_path / name).write_text(green)

    def page(href):
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8">'
                '<image width="8" height="8" href="%s"/></svg>' % href).encode()
    doc = str(tmp_path / "doc")
    assert cpu.render_svg(page("inside.svg"), aa="1x8", base_dir=doc)[4, 4].tolist() == [0, 255, 0, 255]
    assert cpu.render_svg(page("../outside.svg"), aa="1x8", base_dir=doc)[4, 4].tolist() == [0, 0, 0, 0]
    assert len(cpu.warnings) > 0
    img = cpu.render_svg(page("../outside.svg"), aa="1x8", base_dir=doc, allow_read=[str(tmp_path)])
    assert img[4, 4].tolist() == [0, 255, 0, 255]


def test_errors(cpu):
    with pytest.raises(mpvg.ParseError, match="XML parse error"):
        cpu.render_svg(b'<svg xmlns="http://www.w3.org/2000/svg"><rect</svg>')
    with pytest.raises(mpvg.ResourceError, match="cannot read"):
        cpu.render_svg(os.path.join(SRC, "testdata", "no-such-file.svg"))
    for bad in (dict(aa="2x2"), dict(gamma="log"), dict(bits=12), dict(width=-5), dict(background="notacolour")):
        with pytest.raises((ValueError, mpvg.Error)):
            cpu.render_svg(os.path.join(GOLDEN, "arcs.svg"), **bad)


def test_gil_released_while_rendering(cpu):
    # This thread keeps running Python while another renders: held, the
    # longest pause here would be the whole render.
    example = os.path.join(SRC, "testdata", "example.svg")
    t0 = time.perf_counter()
    cpu.render_svg(example, width=400)
    alone = time.perf_counter() - t0
    worker = threading.Thread(target=lambda: cpu.render_svg(example, width=400))
    last = time.perf_counter()
    longest = 0.0
    worker.start()
    while worker.is_alive():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    worker.join()
    assert alone > 0.05 and longest < alone / 2, (alone, longest)


def test_transparent_pixels_are_canonical(cpu):
    # Issue 32: where alpha is 0 the colour is 0 too, at 8 and 16 bits.
    rng = np.random.default_rng(5)
    for k in range(6):
        shapes = "".join('<circle cx="%.2f" cy="%.2f" r="%.2f" fill="#%06x" fill-opacity="%.3f"/>' % (
            rng.uniform(0, 64), rng.uniform(0, 64), rng.uniform(0.3, 20), rng.integers(0, 1 << 24),
            rng.uniform(0.001, 1)) for _ in range(12))
        svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64">%s</svg>' % shapes).encode()
        for bits in (8, 16):
            for aa in ("4x4x32", "1x32"):
                img = cpu.render_svg(svg, aa=aa, bits=bits, seed=k)
                clear = img[..., 3] == 0
                assert clear.any() and not img[clear].any(), (k, bits, aa)
