"""Type stubs of mpvg's extension (python/_mpvg.cpp)."""
import os
from typing import Iterator, Literal, Optional, Protocol, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class Error(RuntimeError):
    """Base of mpvg's errors; its message is the one line svg2png or pdf2png prints."""

class DocumentError(Error):
    """The document cannot be opened or read (base of ParseError and PasswordError)."""

class ParseError(DocumentError):
    """The document is malformed (XML, PDF syntax, an invalid root or page)."""

class PasswordError(DocumentError):
    """The PDF is encrypted and no password, or a wrong one, was given (password=)."""

class UnsupportedError(Error):
    """Valid, but beyond this build or backend (no PDF support, device output without CUDA)."""

class ResourceError(Error):
    """The input or the machine falls short (an unreadable file, input or memory limits, no CUDA device)."""

class MemoryLimitError(ResourceError, MemoryError):
    """The render needs more memory than its budget (max_memory) or the machine has."""

class OptionError(Error, ValueError):
    """An argument out of range, unknown, or not to be given with another one."""

class ClosedError(Error, ValueError):
    """The Document was closed."""

Background = Union[None, str, Tuple[float, float, float], Tuple[float, float, float, float]]
# The input rule: a path (os.PathLike, or a str that is not markup), data
# (bytes-like, or an object with .read()), or SVG text (a str starting
# with '<' after whitespace).
class _Readable(Protocol):
    def read(self) -> Union[bytes, str]: ...

Source = Union[str, os.PathLike[str], bytes, bytearray, memoryview, _Readable]
Data = Union[bytes, bytearray, memoryview, str]
Folders = Union[str, os.PathLike[str], Sequence[Union[str, os.PathLike[str]]]]
MemorySize = Union[None, int, str]

class Renderer:
    """Renders SVG documents on one backend, keeping its state (the CUDA
    context and device buffers) from call to call."""

    def __init__(self, backend: Literal["auto", "cpu", "cuda"] = "auto") -> None: ...
    @property
    def backend(self) -> Literal["cpu", "cuda"]: ...
    @property
    def note(self) -> str: ...
    @property
    def warnings(self) -> list[str]: ...
    def render_svg(
        self,
        svg: Optional[Source] = None,
        *,
        data: Optional[Data] = None,
        width: Optional[float] = None,
        height: Optional[float] = None,
        zoom: Optional[float] = None,
        keep_aspect_ratio: bool = False,
        aa: Literal["4x4x32", "1x32", "1x8"] = "4x4x32",
        gamma: Literal["linear", "srgb"] = "linear",
        background: Background = None,
        bits: Literal[8, 16] = 8,
        seed: int = 0,
        base_dir: Union[str, os.PathLike[str]] = ".",
        allow_read: Optional[Folders] = None,
        font_dir: Optional[Folders] = None,
        languages: Union[None, str, Sequence[str]] = None,
        max_memory: MemorySize = None,
    ) -> npt.NDArray[Union[np.uint8, np.uint16]]: ...

PageBox = Literal["media", "crop", "bleed", "trim", "art"]
Array = Union[npt.NDArray[Union[np.uint8, np.uint16]], "DeviceArray"]

class Document:
    """A PDF document (MuPDF interprets it), in PyMuPDF's shape: a context
    manager, len(doc), doc[i], iteration over its pages, close()."""

    def __init__(
        self,
        document: Optional[Source] = None,
        password: Optional[str] = None,
        backend: Literal["auto", "cpu", "cuda"] = "auto",
        *,
        data: Optional[Data] = None,
    ) -> None: ...
    def __enter__(self) -> "Document": ...
    def __exit__(self, *args: object) -> bool: ...
    def close(self) -> None: ...
    @property
    def is_closed(self) -> bool: ...
    @property
    def name(self) -> str: ...
    def __len__(self) -> int: ...
    @property
    def page_count(self) -> int: ...
    def __getitem__(self, index: int) -> "Page": ...
    def load_page(self, index: int) -> "Page": ...
    def __iter__(self) -> Iterator["Page"]: ...
    def page_size(self, page: int, box: PageBox = "crop") -> Tuple[float, float]: ...
    @property
    def warnings(self) -> list[str]: ...
    def render(
        self,
        page: int,
        *,
        dpi: float = 150.0,
        dpi_y: Optional[float] = None,
        scale_to: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        aa: Literal["4x4x32", "1x32", "1x8"] = "4x4x32",
        gamma: Literal["linear", "srgb"] = "srgb",
        background: Background = "white",
        bits: Literal[8, 16] = 8,
        seed: int = 0,
        box: PageBox = "crop",
        annotations: bool = True,
        thin_lines: Literal["exact", "snap"] = "exact",
        colorspace: Literal["rgb", "gray", "cmyk"] = "rgb",
        max_memory: MemorySize = None,
        device: Literal["cpu", "cuda"] = "cpu",
    ) -> Array: ...
    def render_batch(
        self,
        pages: Optional[Sequence[int]] = None,
        *,
        dpi: float = 150.0,
        dpi_y: Optional[float] = None,
        scale_to: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        aa: Literal["4x4x32", "1x32", "1x8"] = "4x4x32",
        gamma: Literal["linear", "srgb"] = "srgb",
        background: Background = "white",
        seed: int = 0,
        box: PageBox = "crop",
        annotations: bool = True,
        thin_lines: Literal["exact", "snap"] = "exact",
        threads: int = 0,
    ) -> "DeviceArray": ...
    def render_pages(
        self,
        pages: Optional[Sequence[int]] = None,
        *,
        dpi: float = 150.0,
        dpi_y: Optional[float] = None,
        scale_to: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        aa: Literal["4x4x32", "1x32", "1x8"] = "4x4x32",
        gamma: Literal["linear", "srgb"] = "srgb",
        background: Background = "white",
        bits: Literal[8, 16] = 8,
        seed: int = 0,
        box: PageBox = "crop",
        annotations: bool = True,
        thin_lines: Literal["exact", "snap"] = "exact",
        colorspace: Literal["rgb", "gray", "cmyk"] = "rgb",
        max_memory: MemorySize = None,
        threads: int = 0,
        device: Literal["cpu", "cuda"] = "cpu",
    ) -> "PageStream": ...

class Page:
    """A page of an mpvg.Document (doc[i], `for page in doc`)."""

    @property
    def number(self) -> int: ...
    @property
    def parent(self) -> Document: ...
    @property
    def size(self) -> Tuple[float, float]: ...
    @property
    def rect(self) -> Tuple[float, float, float, float]: ...
    def box_size(self, box: PageBox = "crop") -> Tuple[float, float]: ...
    def render(
        self,
        *,
        dpi: float = 150.0,
        dpi_y: Optional[float] = None,
        scale_to: Optional[int] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        aa: Literal["4x4x32", "1x32", "1x8"] = "4x4x32",
        gamma: Literal["linear", "srgb"] = "srgb",
        background: Background = "white",
        bits: Literal[8, 16] = 8,
        seed: int = 0,
        box: PageBox = "crop",
        annotations: bool = True,
        thin_lines: Literal["exact", "snap"] = "exact",
        colorspace: Literal["rgb", "gray", "cmyk"] = "rgb",
        max_memory: MemorySize = None,
        device: Literal["cpu", "cuda"] = "cpu",
    ) -> Array: ...

class PageStream:
    """The pages of Document.render_pages, in the order asked."""

    def __iter__(self) -> "PageStream": ...
    def __next__(self) -> Union[npt.NDArray[Union[np.uint8, np.uint16]], "DeviceArray"]: ...
    def close(self) -> None: ...

class DeviceArray:
    """An H x W x 4 uint8 image in CUDA memory owned by mpvg
    (render(..., device="cuda")): torch.from_dlpack(a) or cupy.asarray(a)
    take it without a copy."""

    @property
    def shape(self) -> Tuple[int, int, int]: ...
    @property
    def dtype(self) -> np.dtype: ...
    @property
    def device(self) -> int: ...
    @property
    def __cuda_array_interface__(self) -> dict: ...
    def __dlpack__(self, stream: Optional[int] = None) -> object: ...
    def __dlpack_device__(self) -> Tuple[int, int]: ...
    def to_host(self) -> npt.NDArray[np.uint8]: ...

Image = Union[npt.NDArray[Union[np.uint8, np.uint16]], str, os.PathLike[str]]

class CompareResult:
    """What mpvg.compare found (mpvg-compare's report); true when the images pass."""

    @property
    def passed(self) -> bool: ...
    def __bool__(self) -> bool: ...
    @property
    def verdict(self) -> Literal["PASS", "WARNING", "FAILURE"]: ...
    @property
    def same_size(self) -> bool: ...
    @property
    def pixels(self) -> int: ...
    @property
    def differing(self) -> int: ...
    @property
    def failed(self) -> int: ...
    @property
    def warned(self) -> int: ...
    @property
    def antialiased(self) -> int: ...
    @property
    def max_difference(self) -> float: ...
    @property
    def max_at(self) -> Tuple[int, int]: ...
    @property
    def mean_difference(self) -> float: ...
    @property
    def rms_difference(self) -> float: ...
    @property
    def psnr(self) -> float: ...
    @property
    def diff(self) -> Optional[npt.NDArray[np.uint8]]: ...
    @property
    def json(self) -> str: ...

def compare(
    a: Image,
    b: Image,
    *,
    fail: float = 1e-6,
    failpercent: float = 0.0,
    hardfail: Optional[float] = None,
    warn: float = 1e-6,
    warnpercent: float = 0.0,
    hardwarn: Optional[float] = None,
    antialiasing: bool = False,
    aa_ring: float = 0.3,
    diff: Union[None, bool, str, os.PathLike[str]] = None,
) -> CompareResult: ...
def read_png(path: Union[str, os.PathLike[str]]) -> npt.NDArray[Union[np.uint8, np.uint16]]: ...
def write_png(path: Union[str, os.PathLike[str]], image: npt.NDArray[Union[np.uint8, np.uint16]]) -> None: ...
