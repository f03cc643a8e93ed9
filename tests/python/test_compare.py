"""mpvg-compare and mpvg.compare on hand-made pairs (identical, an edge
moved by a pixel, a change of antialiasing, a real change), with idiff's
exit codes; and mpvg.testing's golden helper."""
import json
import os

import numpy as np
import pytest

import mpvg
import mpvg.testing
from conftest import GOLDEN, run

# A disc, antialiased, on white.
DISC = ('<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64"><rect x="-8" y="-8" width="80" height="80" fill="white"/>'
        '<circle cx="{cx}" cy="32" r="{r}" fill="{fill}"/></svg>')


def disc(cx=32, r=20, fill="#2050a0", aa="4x4x32", seed=0):
    # (The white square overhangs the canvas: a wide filter sees no edge at the border.)
    return mpvg.Renderer("cpu").render_svg(DISC.format(cx=cx, r=r, fill=fill).encode(), aa=aa, seed=seed)


def test_identical():
    a = disc()
    r = mpvg.compare(a, a.copy())
    assert r and r.verdict == "PASS" and r.differing == 0 and r.max_difference == 0
    assert json.loads(r.json)["result"] == "PASS"


def test_change_of_antialiasing_passes_only_when_aware():
    a, b = disc(aa="4x4x32"), disc(aa="1x32", seed=7)
    strict = mpvg.compare(a, b, fail=1.5 / 255)
    assert not strict and strict.failed > 0
    aware = mpvg.compare(a, b, fail=1.5 / 255, antialiasing=True)
    assert aware, aware
    assert aware.antialiased >= strict.failed * 0.9


def test_edge_moved_by_a_fraction_passes_when_aware():
    a, b = disc(cx=32), disc(cx=32.4)
    assert not mpvg.compare(a, b, fail=1.5 / 255)
    assert mpvg.compare(a, b, fail=1.5 / 255, antialiasing=True)


def test_real_changes_fail():
    a = disc()
    for b in (disc(fill="#2060a0"), disc(r=23), disc(cx=36)):
        r = mpvg.compare(a, b, fail=1.5 / 255, antialiasing=True)
        assert not r and r.failed > 0, r
    # A missing hairline.
    line = mpvg.Renderer("cpu").render_svg(
        b'<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64"><rect x="-8" y="-8" width="80" height="80" fill="white"/>'
        b'<line x1="4" y1="20.5" x2="60" y2="20.5" stroke="black"/></svg>')
    blank = np.full_like(line, 255)
    assert not mpvg.compare(line, blank, fail=1.5 / 255, antialiasing=True)


def test_thresholds_and_percent():
    a = disc()
    b = a.copy()
    b[10, 10, :3] = [0, 0, 0]  # one pixel of 4096
    assert not mpvg.compare(a, b)
    assert mpvg.compare(a, b, failpercent=0.05)
    assert not mpvg.compare(a, b, failpercent=0.05, hardfail=0.5)
    warned = mpvg.compare(a, b, fail=1.0, warn=0.1)
    assert warned and warned.verdict == "WARNING"
    # Colour under no coverage is no difference.
    c = np.zeros((4, 4, 4), np.uint8)
    d = c.copy()
    d[..., 1] = 125
    assert mpvg.compare(c, d).differing == 0


def test_sizes_and_types():
    assert not mpvg.compare(np.zeros((4, 4, 4), np.uint8), np.zeros((4, 5, 4), np.uint8)).same_size
    grey = np.full((4, 4), 200, np.uint8)
    assert mpvg.compare(grey, np.repeat(grey[..., None], 3, axis=2))  # grey is R = G = B
    assert mpvg.compare(np.full((2, 2, 4), 65535, np.uint16), np.full((2, 2, 4), 255, np.uint8))
    with pytest.raises(TypeError):
        mpvg.compare(np.zeros((2, 2, 4), np.float32), np.zeros((2, 2, 4), np.float32))


def test_png_round_trip(tmp_path):
    a = disc()
    mpvg.write_png(tmp_path / "a.png", a)
    assert (mpvg.read_png(tmp_path / "a.png") == a).all()
    mpvg.write_png(tmp_path / "b.png", a)
    assert open(tmp_path / "a.png", "rb").read() == open(tmp_path / "b.png", "rb").read()


def test_command(compare_tool, tmp_path):
    a, b, c = tmp_path / "a.png", tmp_path / "b.png", tmp_path / "c.png"
    mpvg.write_png(a, disc())
    mpvg.write_png(b, disc(aa="1x32", seed=3))
    mpvg.write_png(c, disc(fill="#a02020"))
    assert run(compare_tool, a, a, check=False).returncode == 0
    assert run(compare_tool, a, b, "--fail", "0.006", check=False).returncode == 1
    assert run(compare_tool, a, b, "-fail", "0.006", "--aa", check=False).returncode == 0
    r = run(compare_tool, a, c, "--aa", "--fail", "0.006", "--json", "--diff", tmp_path / "d.png", check=False,
            capture_output=True, text=True)
    assert r.returncode == 1
    report = json.loads(r.stdout)
    assert report["result"] == "FAILURE" and report["failed"] > 500
    diff = mpvg.read_png(tmp_path / "d.png")
    assert (diff[32, 32] == [255, 0, 0, 255]).all() and (diff[2, 2, :3] > 200).all()
    assert run(compare_tool, a, tmp_path / "missing.png", check=False).returncode == 2
    assert run(compare_tool, a, check=False).returncode == 2
    assert run(compare_tool, a, b, "--fail", "x", check=False).returncode == 2


def test_golden_helper(tmp_path, monkeypatch):
    monkeypatch.delenv(mpvg.testing.UPDATE_VARIABLE, raising=False)
    golden = tmp_path / "goldens" / "disc.png"
    with pytest.raises(AssertionError, match="does not exist"):
        mpvg.testing.assert_matches_golden(disc(), golden)
    monkeypatch.setenv(mpvg.testing.UPDATE_VARIABLE, "1")
    mpvg.testing.assert_matches_golden(disc(), golden)
    monkeypatch.delenv(mpvg.testing.UPDATE_VARIABLE)
    assert mpvg.testing.assert_matches_golden(disc(aa="1x32", seed=5), golden)
    out = tmp_path / "out"
    with pytest.raises(AssertionError, match="does not match"):
        mpvg.testing.assert_matches_golden(disc(r=24), golden, output_dir=out)
    assert sorted(os.listdir(out)) == ["disc.actual.png", "disc.diff.png", "disc.expected.png"]
    assert (mpvg.read_png(golden) == disc()).all()  # the golden stays as it was
