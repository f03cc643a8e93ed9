"""mpvg: SVG documents rendered by the massively-parallel vector graphics
pipeline (CPU or CUDA), as NumPy arrays of straight-alpha sRGB RGBA pixels,
the same values svg2png writes.

    import mpvg
    r = mpvg.Renderer()                            # "auto", "cpu" or "cuda"
    img = r.render_svg("drawing.svg", width=512)   # H x W x 4 uint8
    doc = mpvg.Document("paper.pdf")               # or its bytes
    page = doc.render(0, dpi=150)                  # pdf2png -r 150's pixels
    mpvg.compare(img, "golden.png", antialiasing=True)  # mpvg-compare's test

`python -m mpvg IN.svg OUT.png [-w W]` renders one file from a shell;
mpvg.testing.assert_matches_golden is the golden-image check for pytest.

"""
from ._mpvg import (CompareResult, DeviceArray, Document, Error, PageStream, ParseError, Renderer, ResourceError,
                    UnsupportedError, __version__, compare, read_png, write_png)

__all__ = ["CompareResult", "DeviceArray", "Document", "Error", "PageStream", "ParseError", "Renderer",
           "ResourceError", "UnsupportedError", "__version__", "compare", "read_png", "write_png"]
