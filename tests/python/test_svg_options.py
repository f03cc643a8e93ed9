"""render_svg's options that svg2png has beside the size and sampling:
font_dir, languages, max_memory, allow_read; each checked against
svg2png's pixels (or its message) for the same option."""
import os

import numpy as np
import pytest

import mpvg
from conftest import GOLDEN, SRC, read_png, rgba, run

FONTS = os.path.join(SRC, "testdata", "fonts")
VARIABLE = os.path.join(SRC, "testdata", "golden-text", "variable_weight.svg")
SWITCH = ('<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><switch>'
          '<rect width="10" height="10" fill="red" systemLanguage="de"/>'
          '<rect width="10" height="10" fill="lime"/></switch></svg>')


def svg2png_pixels(svg2png, tmp_path, svg, *args):
    out = tmp_path / "cli.png"
    run(svg2png, "-q", "--backend", "cpu", "--aa", "1x8", *args, svg, out)
    return rgba(read_png(out))


def test_font_dir(svg2png, cpu, tmp_path):
    want = svg2png_pixels(svg2png, tmp_path, VARIABLE, "--font-dir", FONTS)
    got = cpu.render_svg(VARIABLE, aa="1x8", font_dir=[FONTS])
    assert np.array_equal(got, want)
    # One folder alone, as a str, is a list of one.
    assert np.array_equal(cpu.render_svg(VARIABLE, aa="1x8", font_dir=FONTS), want)
    # Without it the test font is not found: other glyphs.
    assert not np.array_equal(cpu.render_svg(VARIABLE, aa="1x8"), want)


def test_languages(svg2png, cpu, tmp_path):
    svg = tmp_path / "lang.svg"
    svg.write_text(SWITCH)
    for tags, cli in ((["de-CH", "en"], "de-CH,en"), ("de-CH,en", "de-CH,en"), (["fr"], "fr")):
        want = svg2png_pixels(svg2png, tmp_path, svg, "--languages", cli)
        got = cpu.render_svg(str(svg), aa="1x8", languages=tags)
        assert np.array_equal(got, want), tags
    assert cpu.render_svg(SWITCH, aa="1x8", languages=["de"])[5, 5].tolist() == [255, 0, 0, 255]
    assert cpu.render_svg(SWITCH, aa="1x8")[5, 5].tolist() == [0, 255, 0, 255]  # default: en
    with pytest.raises(mpvg.OptionError):
        cpu.render_svg(SWITCH, languages=[])
    with pytest.raises(mpvg.OptionError):
        cpu.render_svg(SWITCH, languages=" , ")


def test_max_memory(svg2png, cpu, tmp_path):
    svg = os.path.join(GOLDEN, "arcs.svg")
    for size in ("12M", "16MiB", 20 << 20):
        cli = str(size)
        r = run(svg2png, "-q", "--backend", "cpu", "--max-memory", cli, "-w", "2500", svg, tmp_path / "x.png",
                check=False, capture_output=True, text=True)
        assert r.returncode == 1, r.stderr
        with pytest.raises(mpvg.MemoryLimitError) as e:
            cpu.render_svg(svg, width=2500, max_memory=size)
        assert r.stderr == "svg2png: %s\n" % e.value
    # A budget that fits renders what svg2png does.
    want = svg2png_pixels(svg2png, tmp_path, svg, "--max-memory", "64M", "-w", "300")
    assert np.array_equal(cpu.render_svg(svg, aa="1x8", width=300, max_memory="64M"), want)
    for bad in ("lots", "-5M", 0, "12X"):
        with pytest.raises(mpvg.OptionError):
            cpu.render_svg(svg, max_memory=bad)


def test_allow_read(svg2png, cpu, tmp_path):
    os.makedirs(tmp_path / "doc")
    os.makedirs(tmp_path / "images")
    (tmp_path / "images" / "green.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><rect width="4" height="4" fill="#00ff00"/></svg>')
    page = tmp_path / "doc" / "page.svg"
    page.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8">'
                    '<image width="8" height="8" href="../images/green.svg"/></svg>')
    # Outside the document's tree: not read, unless allowed, as svg2png.
    assert cpu.render_svg(str(page), aa="1x8")[4, 4].tolist() == [0, 0, 0, 0]
    want = svg2png_pixels(svg2png, tmp_path, page, "--allow-read", tmp_path / "images")
    assert want[4, 4].tolist() == [0, 255, 0, 255]
    assert np.array_equal(cpu.render_svg(str(page), aa="1x8", allow_read=[str(tmp_path / "images")]), want)
    assert np.array_equal(cpu.render_svg(page, aa="1x8", allow_read=tmp_path / "images"), want)
