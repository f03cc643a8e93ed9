#!/usr/bin/env python3
"""Seed corpora for the fuzz targets, made from testdata/ (fuzz/README.md).

    fuzz/make_seeds.py OUTDIR    # OUTDIR/<target>/ for svg css path_data pdf image

svg: every SVG document of testdata/. css: the .css files, every <style>
block and style attribute of those documents, and the sheets of the CSS
tests (tests/test_svg_css.cpp). path_data: every d and points
attribute. pdf: every PDF. image: every PNG, JPEG, GIF and WebP of
testdata/images/, the images embedded as base64 data: URIs in the documents,
and the svgz files (gzip). Files are named by the SHA-1 of their bytes, so
reruns add nothing twice."""
import base64
import hashlib
import html
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
TESTDATA = ROOT / "testdata"
MAX_BYTES = 64 * 1024  # larger seeds slow every run and add little


def put(out, target, data):
    if isinstance(data, str):
        data = data.encode("utf-8")
    if not data or len(data) > (1 << 20 if target == "pdf" else MAX_BYTES):
        return 0
    d = out / target
    d.mkdir(parents=True, exist_ok=True)
    f = d / hashlib.sha1(data).hexdigest()
    if f.exists():
        return 0
    f.write_bytes(data)
    return 1


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = pathlib.Path(sys.argv[1])
    # The committed corpora of testdata/fuzz are not seeds (they are passed
    # to the fuzzers as corpora of their own).
    files = [p for p in sorted(TESTDATA.rglob("*")) if p.is_file() and "fuzz" not in p.relative_to(TESTDATA).parts]
    n = {t: 0 for t in ("svg", "css", "path_data", "pdf", "image")}
    for p in files:
        ext = p.suffix.lower()
        data = p.read_bytes()
        if ext == ".svg":
            n["svg"] += put(out, "svg", data)
            text = data.decode("utf-8", "replace")
            for m in re.finditer(r"<style[^>]*>(.*?)</style>", text, re.S):
                sheet = m.group(1).replace("<![CDATA[", "").replace("]]>", "")
                n["css"] += put(out, "css", sheet)
            for m in re.finditer(r"\sstyle\s*=\s*(\"[^\"]*\"|'[^']*')", text):
                n["css"] += put(out, "css", html.unescape(m.group(1)[1:-1]))
            for m in re.finditer(r"\s(?:d|points)\s*=\s*(\"[^\"]*\"|'[^']*')", text):
                n["path_data"] += put(out, "path_data", html.unescape(m.group(1)[1:-1]))
            for m in re.finditer(r"data:image/[a-z+.-]+;base64,([A-Za-z0-9+/=\s]+)", text):
                try:
                    n["image"] += put(out, "image", base64.b64decode(re.sub(r"\s", "", m.group(1))))
                except ValueError:
                    pass
        elif ext == ".css":
            n["css"] += put(out, "css", data)
        elif ext == ".pdf":
            n["pdf"] += put(out, "pdf", data)
        elif ext in (".png", ".jpg", ".jpeg", ".gif", ".webp") and p.parent.name == "images":
            n["image"] += put(out, "image", data)
        elif ext == ".svgz":
            n["image"] += put(out, "image", data)
    # The sheets of the CSS tests (tests/test_svg_css.cpp), in C++ string
    # literals: '\\"' unescaped.
    css_tests = (ROOT / "tests" / "test_svg_css.cpp")
    if css_tests.exists():
        text = css_tests.read_text("utf-8", "replace")
        for st in re.finditer(r"<style[^>]*>(.*?)</style>", text, re.S):
            sheet = st.group(1).replace('\\"', '"').replace("<![CDATA[", "").replace("]]>", "")
            n["css"] += put(out, "css", sheet)
    for t, k in n.items():
        print(f"{t}: {k} new seeds in {out / t}")


if __name__ == "__main__":
    main()
