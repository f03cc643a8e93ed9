"""Golden-image checks for test suites (pytest or any other).

    from mpvg.testing import assert_matches_golden

    def test_logo():
        img = mpvg.Renderer("cpu").render_svg("logo.svg", width=256)
        result = assert_matches_golden(img, "goldens/logo.png")
        assert result.max_difference < 0.01   # the comparison, for more checks

With pytest the module is also a plugin (the `pytest11` entry point of an
installed mpvg; else `-p mpvg.testing` or `pytest_plugins = ["mpvg.testing"]`)
with a fixture that names goldens after the test:

    def test_logo(mpvg_golden):
        mpvg_golden(mpvg.Renderer("cpu").render_svg("logo.svg", width=256))
        # compares with goldens/test_logo.png beside the test file

The image is compared with the golden PNG by mpvg.compare (antialiasing-
aware by default, channels within 1/255 elsewhere). On a mismatch the
expected, actual and diff images are written next to each other as
NAME.expected.png, NAME.actual.png and NAME.diff.png (in $MPVG_TEST_OUTPUT
when set, else beside the golden) and AssertionError says where and by how
much; pytest shows the assertion, not this module's frames. With
MPVG_UPDATE_GOLDEN=1 (pytest: --mpvg-update-golden) the golden is written
from the image instead, and the check passes: goldens change only when
asked. A missing golden is a failure that says how to make it.
"""
import os
import re
from typing import Optional, Union

from . import _mpvg

UPDATE_VARIABLE = "MPVG_UPDATE_GOLDEN"
OUTPUT_VARIABLE = "MPVG_TEST_OUTPUT"

PathLike = Union[str, "os.PathLike[str]"]


def _image(image):
    return _mpvg.read_png(image) if isinstance(image, (str, os.PathLike)) else image


def assert_matches_golden(image, golden: PathLike, *, fail: float = 1.0 / 255 + 1e-6, failpercent: float = 0.0,
                          hardfail: Optional[float] = None, antialiasing: bool = True, aa_ring: float = 0.3,
                          output_dir: Optional[PathLike] = None,
                          update: Optional[bool] = None) -> "_mpvg.CompareResult":
    """Asserts that `image` (an H x W [x C] uint8/uint16 array, or a PNG path) matches the golden PNG,
    and returns the mpvg.CompareResult of the comparison (true, as it passed).

    fail, failpercent, hardfail, antialiasing, aa_ring: as mpvg.compare. output_dir: where the
    expected/actual/diff images of a mismatch go (default $MPVG_TEST_OUTPUT, else beside the
    golden). update: write the golden from the image instead (default: $MPVG_UPDATE_GOLDEN set and
    not 0); the result is then the image compared with itself.
    Raises AssertionError on a mismatch or a missing golden.
    """
    __tracebackhide__ = True  # pytest reports the caller's line
    golden = os.fspath(golden)
    if update is None:
        update = os.environ.get(UPDATE_VARIABLE, "") not in ("", "0")
    if update:
        actual = _image(image)
        os.makedirs(os.path.dirname(os.path.abspath(golden)), exist_ok=True)
        _mpvg.write_png(golden, actual)
        return _mpvg.compare(golden, actual, fail=fail, failpercent=failpercent, hardfail=hardfail, warn=fail,
                             antialiasing=antialiasing, aa_ring=aa_ring)
    if not os.path.exists(golden):
        raise AssertionError("golden %s does not exist: run with %s=1 (pytest: --mpvg-update-golden) to write it, "
                             "then look at it before committing it" % (golden, UPDATE_VARIABLE))
    result = _mpvg.compare(golden, image, fail=fail, failpercent=failpercent, hardfail=hardfail,
                           warn=fail, antialiasing=antialiasing, aa_ring=aa_ring, diff=True)
    if result.passed:
        return result
    folder = os.fspath(output_dir or os.environ.get(OUTPUT_VARIABLE) or os.path.dirname(os.path.abspath(golden)))
    os.makedirs(folder, exist_ok=True)
    stem = os.path.join(folder, os.path.splitext(os.path.basename(golden))[0])
    expected = _mpvg.read_png(golden)
    actual = _image(image)
    _mpvg.write_png(stem + ".expected.png", expected)
    _mpvg.write_png(stem + ".actual.png", actual)
    if result.diff is not None:
        _mpvg.write_png(stem + ".diff.png", result.diff)
    if not result.same_size:
        why = "sizes differ: golden %dx%d, image %dx%d" % (expected.shape[1], expected.shape[0], actual.shape[1],
                                                           actual.shape[0])
    else:
        why = "%d of %d pixels over %.4g (max %.4g at %s; %d forgiven as antialiasing)" % (
            result.failed, result.pixels, fail, result.max_difference, result.max_at, result.antialiased)
    raise AssertionError("image does not match golden %s: %s; see %s.{expected,actual,diff}.png (%s=1 updates "
                         "the golden)" % (golden, why, stem, UPDATE_VARIABLE))


# ---- the pytest plugin (entry point pytest11: mpvg = mpvg.testing) ----
try:
    import pytest
except ImportError:  # the module serves other test runners without pytest
    pytest = None

if pytest is not None:

    def pytest_addoption(parser):
        group = parser.getgroup("mpvg", "mpvg golden images")
        group.addoption("--mpvg-update-golden", action="store_true", default=False,
                        help="write the goldens of mpvg_golden checks from the images (as %s=1)" % UPDATE_VARIABLE)
        parser.addini("mpvg_golden_dir", "folder of mpvg_golden's goldens, relative to each test file's folder "
                      "(default: goldens)", default="goldens")

    @pytest.fixture
    def mpvg_golden(request):
        """check(image, name=None, **options) -> mpvg.CompareResult: assert_matches_golden against
        the golden NAME.png (default: the test's name) in the folder `mpvg_golden_dir` (ini; default
        goldens/) beside the test file. --mpvg-update-golden (or MPVG_UPDATE_GOLDEN=1) writes the
        goldens instead. Options as assert_matches_golden's."""
        folder = os.path.join(os.path.dirname(str(request.node.fspath)), request.config.getini("mpvg_golden_dir"))
        update = request.config.getoption("mpvg_update_golden") or None

        def check(image, name: Optional[str] = None, **options):
            __tracebackhide__ = True
            stem = name or re.sub(r"[^A-Za-z0-9_.-]+", "_", request.node.name).strip("_")
            if not stem.endswith(".png"):
                stem += ".png"
            options.setdefault("update", update)
            return assert_matches_golden(image, os.path.join(folder, stem), **options)

        return check
