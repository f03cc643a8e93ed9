"""mpvg: SVG and PDF documents rendered by the massively-parallel vector
graphics pipeline (CPU or CUDA), as NumPy arrays of straight-alpha sRGB RGBA
pixels, the same values svg2png and pdf2png write.

    import mpvg
    r = mpvg.Renderer()                            # "auto", "cpu" or "cuda"
    img = r.render_svg("drawing.svg", width=512)   # H x W x 4 uint8
    img = r.render_svg('<svg xmlns="http://www.w3.org/2000/svg" .../>')

    with mpvg.open("paper.pdf") as doc:            # mpvg.Document, as PyMuPDF's
        for page in doc:                           # or doc[0], doc[-1], len(doc)
            img = page.render(dpi=150)             # pdf2png -r 150's pixels
            img = page.render(scale_to=1024)       # pdf2png -scale-to 1024
    mpvg.compare(img, "golden.png", antialiasing=True)  # mpvg-compare's test

Input rule, wherever a document is taken (Renderer.render_svg, Document,
open): an os.PathLike, or a str that is a path, names a file; bytes,
bytearray, memoryview or an object with .read() is the document's data; a
str whose first character after whitespace is '<' is SVG text; data= gives
the data explicitly.

Errors: every failure of the library is an mpvg.Error (a RuntimeError) with
the one-line message the CLIs print:

    Error
    +-- DocumentError         the document cannot be opened or read
    |   +-- ParseError        malformed (XML, PDF syntax, an invalid root or page)
    |   +-- PasswordError     encrypted: no password or a wrong one
    +-- UnsupportedError      beyond this build or backend
    +-- ResourceError         an unreadable file, input limits, no CUDA device
    |   +-- MemoryLimitError  past max_memory or the machine's memory (a MemoryError too)
    +-- OptionError           a bad argument (a ValueError too)
    +-- ClosedError           a closed Document used (a ValueError too)

`python -m mpvg IN.svg OUT.png [-w W]` (or IN.pdf OUT-PREFIX) renders one
file from a shell as svg2png and pdf2png do; mpvg.testing is the
golden-image check for pytest (the `mpvg_golden` fixture).
"""
from ._mpvg import (ClosedError, CompareResult, DeviceArray, Document, DocumentError, Error, MemoryLimitError,
                    OptionError, Page, PageStream, ParseError, PasswordError, Renderer, ResourceError,
                    UnsupportedError, __version__, compare, read_png, write_png)


def open(document=None, password=None, backend="auto", *, data=None):  # noqa: A001 (PyMuPDF's name)
    """Opens a PDF document: mpvg.Document(document, password, backend, data=data), PyMuPDF's
    pymupdf.open(). Use it as `with mpvg.open(path) as doc:`.

    document: the PDF. Input rule: an os.PathLike, or a str that is a path, names a file; bytes,
    bytearray, memoryview or an object with .read() (an open binary file, io.BytesIO) is the
    document's data; a str whose first character after whitespace is '<' is SVG text (refused:
    Renderer.render_svg renders it); data= gives the data explicitly.
    password: for an encrypted one. backend: 'auto', 'cpu' or 'cuda'.
    Raises mpvg.PasswordError, mpvg.ParseError, mpvg.ResourceError.
    """
    return Document(document, password, backend, data=data)


__all__ = ["ClosedError", "CompareResult", "DeviceArray", "Document", "DocumentError", "Error", "MemoryLimitError",
           "OptionError", "Page", "PageStream", "ParseError", "PasswordError", "Renderer", "ResourceError",
           "UnsupportedError", "__version__", "compare", "open", "read_png", "write_png"]
