"""help(mpvg) reads cleanly: every public class, function and method has a
docstring naming its arguments (pybind11 signatures from py::arg), and the
type stub python/mpvg/_mpvg.pyi has the same functions with the same
arguments as the extension."""
import ast
import os
import pydoc
import re

import mpvg
from conftest import SRC

STUB = os.path.join(SRC, "python", "mpvg", "_mpvg.pyi")


def extension_signature(doc):
    """The argument names (self dropped, '*' kept) of a pybind11 docstring's first signature."""
    first = doc.strip().splitlines()[0]
    m = re.match(r"^\w+\((.*)\)( -> .*)?$", first)
    assert m, first
    names = []
    depth, part = 0, ""
    for ch in m.group(1) + ",":
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            part = part.strip()
            if part:
                names.append(part.split(":")[0].split("=")[0].strip())
            part = ""
        else:
            part += ch
    return [n for n in names if n not in ("self", "arg0")]


def stub_signatures():
    tree = ast.parse(open(STUB).read())
    out = {}

    def args_of(f):
        a = f.args
        names = [x.arg for x in a.posonlyargs + a.args]
        if a.kwonlyargs:
            names.append("*")
            names += [x.arg for x in a.kwonlyargs]
        return [n for n in names if n != "self"]
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            out[node.name] = args_of(node)
        elif isinstance(node, ast.ClassDef):
            out[node.name] = None
            for f in node.body:
                if isinstance(f, ast.FunctionDef):
                    out[node.name + "." + f.name] = args_of(f)
    return out


def public_callables():
    for name in mpvg.__all__:
        obj = getattr(mpvg, name)
        if isinstance(obj, type) and not issubclass(obj, BaseException):
            for attr, member in vars(obj).items():
                if (not attr.startswith("_") or attr in ("__init__", "__getitem__", "__len__", "__iter__")) and \
                        callable(member) and getattr(member, "__doc__", None) and \
                        not member.__doc__.startswith("Initialize self"):  # (no constructor: object's)
                    yield "%s.%s" % (name, attr), member
        elif callable(obj) and not isinstance(obj, type) and name != "open":
            yield name, obj


def test_everything_public_is_documented():
    for name in mpvg.__all__:
        obj = getattr(mpvg, name)
        if name != "__version__":
            assert obj.__doc__ and obj.__doc__.strip(), name
    for name, f in public_callables():
        doc = f.__doc__
        assert doc and "arg0" not in doc, (name, doc)  # py::arg names every argument
    text = pydoc.render_doc(mpvg, renderer=pydoc.plaintext)
    for needle in ("Input rule", "DocumentError", "PasswordError", "MemoryLimitError", "ClosedError",
                   "class Document", "class Page", "scale_to", "render_svg", "font_dir", "max_memory"):
        assert needle in text, needle
    page = pydoc.render_doc(mpvg.Page, renderer=pydoc.plaintext)
    assert "render(self" in page and "-scale-to" in page and "number" in page


def test_stub_matches_the_extension():
    stub = stub_signatures()
    for name, f in public_callables():
        if name.endswith(".__init__"):
            cls = name.split(".")[0]
            key = cls + ".__init__"
        else:
            key = name
        assert key in stub, "%s is not in _mpvg.pyi" % key
        assert extension_signature(f.__doc__) == stub[key], name
    for name in mpvg.__all__:
        if name not in ("open", "__version__"):
            assert name in stub, name


def test_help_names_no_cpp_types():
    """Every type a signature names is a Python one (mpvg._mpvg.PageStream), never the C++ type
    behind it ('(anonymous namespace)::PyDocument::PageStream')."""
    for obj in (mpvg, mpvg.Renderer, mpvg.Document, mpvg.Page, mpvg.PageStream, mpvg.DeviceArray,
                mpvg.CompareResult):
        text = pydoc.render_doc(obj, renderer=pydoc.plaintext)
        assert "::" not in text and "anonymous namespace" not in text, obj
