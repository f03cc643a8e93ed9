"""python -m mpvg for one file, against svg2png and pdf2png: the same
pixels, pdf2png's (pdftoppm's) exit codes (0, 1 cannot open, 2 cannot
write, 99 usage or a failed page), one-line messages, a password refusal
that names --password."""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import GOLDEN, PDFS, read_png, rgba, run

THREE = os.path.join(PDFS, "three-pages.pdf")
LOCKED = os.path.join(PDFS, "encrypted-password-secret.pdf")


def pixels(path):
    """A PNG's pixels as RGBA: pdf2png -gray writes grey PNGs, mpvg.write_png RGB ones of the same values."""
    px = read_png(path)
    if px.shape[2] <= 2:
        px = np.concatenate([px[..., :1]] * 3 + [px[..., 1:]], axis=2)
    return rgba(px)


def mpvg_m(*args, **kw):
    return subprocess.run([sys.executable, "-m", "mpvg", *[str(a) for a in args]], capture_output=True, **kw)


def one_line(stderr):
    lines = stderr.decode().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mpvg: "), lines
    return lines[0]


def test_svg_same_pixels_as_svg2png(svg2png, tmp_path):
    svg = os.path.join(GOLDEN, "stroke_joins.svg")
    fonts = os.path.join(os.path.dirname(GOLDEN), "fonts")
    args = ["--backend", "cpu", "-w", "120", "--aa", "1x32", "-b", "#336699", "--seed", "2", "--font-dir", fonts,
            "--languages", "de,en", "--max-memory", "256M"]
    run(svg2png, "-q", *args, svg, tmp_path / "cli.png")
    r = mpvg_m(*args, svg, tmp_path / "mod.png")
    assert r.returncode == 0, r.stderr
    assert np.array_equal(rgba(read_png(tmp_path / "cli.png")), rgba(read_png(tmp_path / "mod.png")))
    # Standard input and output.
    with open(svg, "rb") as f:
        r = subprocess.run([sys.executable, "-m", "mpvg", *args, "-", "-"], stdin=f, capture_output=True)
    assert r.returncode == 0 and r.stdout[:8] == b"\x89PNG\r\n\x1a\n"
    (tmp_path / "piped.png").write_bytes(r.stdout)
    assert np.array_equal(read_png(tmp_path / "piped.png"), read_png(tmp_path / "mod.png"))


def test_pdf_sizes_same_as_pdf2png(pdf2png, tmp_path):
    for args in (["-scale-to", "64"], ["-scale-to-x", "80", "-scale-to-y", "30"], ["-scale-to-x", "50", "-scale-to-y", "-1"],
                 ["-scale-to-x", "80"], ["-r", "40", "-scale-to-y", "33"], ["-rx", "50", "-scale-to-y", "33"],
                 ["-r", "30", "-ry", "45"], ["-r", "40", "-gray"]):
        for d in ("cli", "mod"):
            os.makedirs(tmp_path / d, exist_ok=True)
        run(pdf2png, "-q", "--backend", "cpu", "--aa", "1x8", *args, "-f", "2", THREE, tmp_path / "cli" / "p")
        r = mpvg_m("--backend", "cpu", "--aa", "1x8", *args, "-f", "2", THREE, tmp_path / "mod" / "p")
        assert r.returncode == 0, r.stderr
        assert sorted(os.listdir(tmp_path / "cli")) == sorted(os.listdir(tmp_path / "mod")) == ["p-2.png", "p-3.png"]
        for n in ("p-2.png", "p-3.png"):
            assert np.array_equal(pixels(tmp_path / "cli" / n), pixels(tmp_path / "mod" / n)), (args, n)
    # -singlefile and standard output (one page, no prefix).
    r = mpvg_m("--backend", "cpu", "-r", "20", "-singlefile", THREE, tmp_path / "single")
    assert r.returncode == 0 and os.path.exists(tmp_path / "single.png")
    r = mpvg_m("--backend", "cpu", "-r", "20", "-f", "3", "-l", "3", THREE)
    assert r.returncode == 0 and r.stdout[:4] == b"\x89PNG"


def test_exit_codes(pdf2png, svg2png, tmp_path):
    missing = tmp_path / "missing.pdf"
    broken = tmp_path / "broken.svg"
    broken.write_text('<svg xmlns="http://www.w3.org/2000/svg"><rect</svg>')
    svg = os.path.join(GOLDEN, "arcs.svg")
    # 1: the document cannot be opened (as pdf2png: missing, encrypted).
    for args in ([missing, tmp_path / "o"], [LOCKED, tmp_path / "o"], [broken, tmp_path / "o.png"],
                 [tmp_path / "missing.svg", tmp_path / "o.png"]):
        r = mpvg_m("--backend", "cpu", *args)
        assert r.returncode == 1, (args, r.stderr)
        one_line(r.stderr)
    for pdf in (missing, LOCKED):
        r = run(pdf2png, "-q", pdf, tmp_path / "o", check=False, capture_output=True)
        assert r.returncode == 1
    # The password refusal names the option that gives it.
    r = mpvg_m(LOCKED, tmp_path / "o")
    assert "--password" in one_line(r.stderr)
    r = mpvg_m("--password", "guess", LOCKED, tmp_path / "o")
    assert r.returncode == 1 and "wrong password" in one_line(r.stderr)
    r = mpvg_m("--backend", "cpu", "--password", "secret", "-r", "10", LOCKED, tmp_path / "ok")
    assert r.returncode == 0 and os.path.exists(tmp_path / "ok-1.png")
    # 2: an output that cannot be written.
    for args in ([THREE, tmp_path / "no" / "such" / "dir" / "p"], [svg, tmp_path / "no" / "such.png"]):
        r = mpvg_m("--backend", "cpu", "-r", "10", *args) if args[0] == THREE else mpvg_m("--backend", "cpu", *args)
        assert r.returncode == 2, (args, r.stderr)
        one_line(r.stderr)
    r = run(pdf2png, "-q", "-r", "10", THREE, tmp_path / "no" / "such" / "dir" / "p", check=False,
            capture_output=True)
    assert r.returncode == 2
    # 99: usage (unknown options, bad values) and a page that fails.
    for args in (["--no-such-option", THREE, tmp_path / "o"], ["-scale-to-x", "0", THREE, tmp_path / "o"],
                 ["--bits", "12", svg, tmp_path / "o.png"], ["-w", "-4", svg, tmp_path / "o.png"], [],
                 ["-r", "10", THREE]):
        r = mpvg_m(*args)
        assert r.returncode == 99, (args, r.stderr)
        one_line(r.stderr)
    r = run(pdf2png, "-q", "--no-such-option", THREE, tmp_path / "o", check=False, capture_output=True)
    assert r.returncode == 99
    r = mpvg_m("--backend", "cpu", "-r", "10", os.path.join(PDFS, "three-pages-bad-page2.pdf"), tmp_path / "bad")
    assert r.returncode == 99 and sorted(p for p in os.listdir(tmp_path) if p.startswith("bad")) == [
        "bad-1.png", "bad-3.png"]
    r = run(pdf2png, "-q", "-r", "10", os.path.join(PDFS, "three-pages-bad-page2.pdf"), tmp_path / "bad2",
            check=False, capture_output=True)
    assert r.returncode == 99


def test_help():
    for args in (["--help"], ["-h", THREE]):
        r = mpvg_m(*args)
        assert r.returncode == 0 and b"usage: python -m mpvg" in r.stdout
    assert b"pdf2png" in mpvg_m("-h", THREE).stdout and b"svg2png" in mpvg_m("--help").stdout


def test_warnings_are_the_cli_s_lines(pdf2png, tmp_path):
    # (colorspace-iccbased warns where MuPDF has no ICC support, as Debian's.)
    pdf = os.path.join(os.path.dirname(THREE), "features", "colorspace-iccbased.pdf")
    cli = run(pdf2png, "--backend", "cpu", "-r", "20", pdf, tmp_path / "cli", capture_output=True, text=True)
    r = mpvg_m("--backend", "cpu", "-r", "20", pdf, tmp_path / "mod")
    assert r.returncode == 0 and cli.stderr
    assert r.stderr.decode().replace("mpvg: ", "pdf2png: ") == cli.stderr
    r = mpvg_m("-q", "--backend", "cpu", "-r", "20", pdf, tmp_path / "mod")
    assert r.returncode == 0 and r.stderr == b""
    assert b"Exit status" in mpvg_m("-h", pdf).stdout and b"99" in mpvg_m("--help").stdout
