"""mpvg.testing as pytest users meet it: assert_matches_golden returns the
comparison and hides its frames from tracebacks; the plugin's mpvg_golden
fixture, loaded with -p mpvg.testing and through the pytest11 entry point
that pyproject.toml declares (a dist-info made here, as an installed
package has), in pytest runs of their own."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import mpvg
from mpvg.testing import assert_matches_golden
from conftest import SRC

SQUARE = ('<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16">'
          '<rect x="4" y="4" width="8" height="8" fill="%s"/></svg>')

TESTS = textwrap.dedent('''
    import mpvg

    SQUARE = %r

    def render(colour):
        return mpvg.Renderer("cpu").render_svg(SQUARE %% colour, aa="1x8")

    def test_blue(mpvg_golden):
        result = mpvg_golden(render("blue"))
        assert result.passed and result.max_difference == 0

    def test_named(mpvg_golden):
        mpvg_golden(render("red"), "red-square")

    def test_mismatch(mpvg_golden):
        mpvg_golden(render("lime"), "red-square")
''') % SQUARE


def test_assert_matches_golden_returns_the_result(cpu, tmp_path):
    img = cpu.render_svg(SQUARE % "blue", aa="1x8")
    golden = tmp_path / "g.png"
    made = assert_matches_golden(img, golden, update=True)
    assert os.path.exists(golden) and made.passed and made.max_difference == 0
    result = assert_matches_golden(img, golden)
    assert isinstance(result, mpvg.CompareResult) and result.passed and result.pixels == 256
    assert np.array_equal(mpvg.read_png(golden), img)
    src = open(mpvg.testing.__file__).read()
    assert src.count("__tracebackhide__ = True") >= 2


def pytest_run(folder, *args, env_extra=None):
    env = dict(os.environ)
    env.pop("MPVG_UPDATE_GOLDEN", None)
    env.update(env_extra or {})
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args, str(folder)],
                          cwd=str(folder), capture_output=True, text=True, env=env)


def write_suite(folder):
    os.makedirs(folder, exist_ok=True)
    (folder / "test_suite.py").write_text(TESTS)


def test_plugin_with_p_option(tmp_path):
    suite = tmp_path / "suite"
    write_suite(suite)
    # No goldens yet: every check fails, saying how to make them.
    r = pytest_run(suite, "-p", "mpvg.testing")
    assert "3 failed" in r.stdout and "--mpvg-update-golden" in r.stdout, r.stdout
    # --mpvg-update-golden writes them, named after the test or as asked.
    r = pytest_run(suite, "-p", "mpvg.testing", "--mpvg-update-golden", "-k", "not mismatch")
    assert "2 passed" in r.stdout, r.stdout
    assert sorted(os.listdir(suite / "goldens")) == ["red-square.png", "test_blue.png"]
    blue = mpvg.read_png(suite / "goldens" / "test_blue.png")
    assert blue[8, 8].tolist() == [0, 0, 255, 255] and blue[0, 0].tolist() == [0, 0, 0, 0]
    # Then they hold; the lime square fails against the red golden, the
    # assertion shown at the test's line, not inside mpvg.testing.
    r = pytest_run(suite, "-p", "mpvg.testing", env_extra={"MPVG_TEST_OUTPUT": str(tmp_path / "out")})
    assert "1 failed, 2 passed" in r.stdout, r.stdout
    assert "does not match golden" in r.stdout and "64 of 256 pixels" in r.stdout
    assert 'mpvg_golden(render("lime"), "red-square")' in r.stdout
    assert "def check(" not in r.stdout and "def assert_matches_golden(" not in r.stdout
    assert sorted(os.listdir(tmp_path / "out")) == ["red-square.actual.png", "red-square.diff.png",
                                                   "red-square.expected.png"]


def test_plugin_through_the_pytest11_entry_point(tmp_path):
    # The entry point as pyproject.toml declares it...
    text = open(os.path.join(SRC, "pyproject.toml")).read()
    assert '[project.entry-points.pytest11]\nmpvg = "mpvg.testing"' in text
    # ...and as an installed package's dist-info carries it: pytest loads
    # the plugin without -p.
    site = tmp_path / "site"
    info = site / "mpvg-0.dist-info"
    os.makedirs(info)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: mpvg\nVersion: 0\n")
    (info / "entry_points.txt").write_text("[pytest11]\nmpvg = mpvg.testing\n")
    suite = tmp_path / "suite"
    write_suite(suite)
    env = {"PYTHONPATH": os.pathsep.join([str(site), os.environ.get("PYTHONPATH", "")])}
    r = pytest_run(suite, "--mpvg-update-golden", "-k", "blue", env_extra=env)
    assert "1 passed" in r.stdout, r.stdout + r.stderr
    r = pytest_run(suite, "-k", "blue", env_extra=env)
    assert "1 passed" in r.stdout, r.stdout + r.stderr
    # Without the entry point (nor -p) the fixture is unknown.
    r = pytest_run(suite, "-k", "blue")
    assert "fixture 'mpvg_golden' not found" in r.stdout, r.stdout
