"""Golden-image checks for test suites (pytest or any other).

    from mpvg.testing import assert_matches_golden

    def test_logo():
        img = mpvg.Renderer("cpu").render_svg("logo.svg", width=256)
        assert_matches_golden(img, "goldens/logo.png")

The image is compared with the golden PNG by mpvg.compare (antialiasing-
aware by default, channels within 1/255 elsewhere). On a mismatch the
expected, actual and diff images are written next to each other as
NAME.expected.png, NAME.actual.png and NAME.diff.png (in $MPVG_TEST_OUTPUT
when set, else beside the golden) and AssertionError says where and by how
much. With MPVG_UPDATE_GOLDEN=1 the golden is written from the image
instead, and the check passes: goldens change only when asked. A missing
golden is a failure that says how to make it.
"""
import os
from typing import Optional, Union

from . import _mpvg

UPDATE_VARIABLE = "MPVG_UPDATE_GOLDEN"
OUTPUT_VARIABLE = "MPVG_TEST_OUTPUT"


def assert_matches_golden(image, golden: Union[str, "os.PathLike[str]"], *, fail: float = 1.0 / 255 + 1e-6,
                          failpercent: float = 0.0, hardfail: Optional[float] = None, antialiasing: bool = True,
                          aa_ring: float = 0.3, output_dir: Optional[Union[str, "os.PathLike[str]"]] = None):
    """Asserts that `image` (an H x W [x C] uint8/uint16 array, or a PNG path) matches the golden PNG.

    fail, failpercent, hardfail, antialiasing, aa_ring: as mpvg.compare. Returns the CompareResult.
    """
    golden = os.fspath(golden)
    if os.environ.get(UPDATE_VARIABLE, "") not in ("", "0"):
        actual = _mpvg.read_png(image) if isinstance(image, (str, os.PathLike)) else image
        os.makedirs(os.path.dirname(os.path.abspath(golden)), exist_ok=True)
        _mpvg.write_png(golden, actual)
        return None
    if not os.path.exists(golden):
        raise AssertionError("golden %s does not exist: run with %s=1 to write it, then look at it before "
                             "committing it" % (golden, UPDATE_VARIABLE))
    result = _mpvg.compare(golden, image, fail=fail, failpercent=failpercent, hardfail=hardfail,
                           warn=fail, antialiasing=antialiasing, aa_ring=aa_ring, diff=True)
    if result.passed:
        return result
    folder = os.fspath(output_dir or os.environ.get(OUTPUT_VARIABLE) or os.path.dirname(os.path.abspath(golden)))
    os.makedirs(folder, exist_ok=True)
    stem = os.path.join(folder, os.path.splitext(os.path.basename(golden))[0])
    expected = _mpvg.read_png(golden)
    actual = _mpvg.read_png(image) if isinstance(image, (str, os.PathLike)) else image
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
