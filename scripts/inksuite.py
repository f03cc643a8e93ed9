#!/usr/bin/python3
"""inksuite.py - print preview against Ghostscript: pdf2png --colorspace cmyk
against `gs -sDEVICE=tiff32nc -sOverprint=simulate`, and --separations
against `gs -sDEVICE=tiffsep`, page by page.

usage:
  scripts/inksuite.py --pdf2png build/apps/pdf2png --pdf-dir DIR
                      [--pages-per-doc N] [--dpi 150] [--jobs N] [--mode cmyk|separations]
                      [--json OUT.json] [pdf2png options after --]

Ghostscript renders each page at 4 x DPI, averaged down over 4 x 4 pixel
blocks (an object-precision reference, as tools/pdfsuite.py makes MuPDF's),
with -sOverprint=simulate for CMYK. Both are compared ink by ink with
pdfsuite's metric: 2 x 2 block averages, a pixel bad when an ink differs by
more than 0.15, a page passing when at most 0.3 % of its pixels are bad.
Separations compare the plates of the inks both name. Pages are chosen as
pdfsuite chooses them: N spread evenly, the first always included.
The last line printed is "overall: P/N pages passed (R%)". Needs python3
with numpy and PIL (not the test suite's business: a measuring tool).
"""
import argparse
import concurrent.futures
import glob
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

Image.MAX_IMAGE_PIXELS = None


def page_count(pdf):
    out = subprocess.run(["mutool", "info", pdf], capture_output=True, text=True).stdout
    m = re.search(r"Pages:\s*(\d+)", out)
    return int(m.group(1)) if m else 0


def pick(n, k):
    if n <= k:
        return list(range(1, n + 1))
    return sorted({1 + round(i * (n - 1) / (k - 1)) for i in range(k)})


def blocks(a, k):
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    a = a[:h, :w].astype(np.float64)
    return a.reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


def load(path):
    with open(path, "rb") as f:
        im = Image.open(f)
        im.load()
        a = np.array(im)
    return a[..., None] if a.ndim == 2 else a


def to_rgb(cmyk):
    c = cmyk / 255.0
    return 255.0 * (1.0 - np.minimum(1.0, c[..., :3] + c[..., 3:4]))


def compare(ours, ref):
    h, w = min(ours.shape[0], ref.shape[0]), min(ours.shape[1], ref.shape[1])
    if abs(ours.shape[0] - ref.shape[0]) > 1 or abs(ours.shape[1] - ref.shape[1]) > 1:
        return None
    d = np.abs(blocks(ours[:h, :w], 2) - blocks(ref[:h, :w], 2)).max(axis=2) / 255
    return float((d > 0.15).mean())


def one(args, pdf, page, work):
    base = os.path.join(work, "%s-%d" % (os.path.basename(pdf), page))
    os.makedirs(base, exist_ok=True)
    r4 = args.dpi * 4
    flag = ["--colorspace", "cmyk"] if args.mode == "cmyk" else ["--separations"]
    cmd = [args.pdf2png, "-q", "-r", str(args.dpi), "-f", str(page), "-l", str(page), "--singlefile"] + flag + \
        args.extra + [pdf, os.path.join(base, "ours")]
    if subprocess.run(cmd, capture_output=True, timeout=300).returncode != 0:
        return {"pdf": pdf, "page": page, "status": "error"}
    dev = ["-sDEVICE=tiff32nc", "-sOverprint=simulate"] if args.mode == "cmyk" else ["-sDEVICE=tiffsep"]
    subprocess.run(["gs", "-q", "-dNOPAUSE", "-dBATCH", "-dSAFER", "-r%d" % r4, "-dFirstPage=%d" % page,
                    "-dLastPage=%d" % page] + dev + args.gs_arg + ["-sOutputFile=" + os.path.join(base, "gs.tif"), pdf],
                   capture_output=True, timeout=600)
    pairs = []
    if args.mode == "cmyk":
        pairs.append(("CMYK", os.path.join(base, "ours.tif"), os.path.join(base, "gs.tif")))
    else:
        for ref in glob.glob(os.path.join(base, "gs(*).tif")):
            name = ref[len(os.path.join(base, "gs(")):-len(").tif")]
            mine = os.path.join(base, "ours(%s).tif" % name)
            pairs.append((name, mine, ref))
    worst, missing = 0.0, []
    for name, mine, ref in pairs:
        if not os.path.exists(mine) or not os.path.exists(ref):
            missing.append(name)
            continue
        g = blocks(load(ref), 4)
        m = load(mine).astype(np.float64)
        if args.as_rgb:
            m, g = to_rgb(m), to_rgb(g)
        f = compare(m, g)
        if f is None:
            return {"pdf": pdf, "page": page, "status": "size"}
        worst = max(worst, f)
    ok = worst <= 0.003 and not missing
    return {"pdf": pdf, "page": page, "status": "pass" if ok else "fail", "bad": worst, "missing": missing}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pdf2png", required=True)
    ap.add_argument("--pdf-dir", required=True)
    ap.add_argument("--pages-per-doc", type=int, default=5)
    ap.add_argument("--dpi", type=int, default=150)
    ap.add_argument("--jobs", type=int, default=os.cpu_count())
    ap.add_argument("--mode", choices=["cmyk", "separations"], default="cmyk")
    ap.add_argument("--json")
    ap.add_argument("--as-rgb", action="store_true",
                    help="cmyk: compare both as RGB (r = 1 - min(1, c + k), ...), which sets aside how each "
                         "converts RGB and grey to CMYK (colour management: Ghostscript's ICC profiles give "
                         "RGB black as rich black, MuPDF without ICC as K alone)")
    ap.add_argument("--gs-arg", action="append", default=[],
                    help="more Ghostscript options (e.g. -dUseFastColor=true: no ICC, PDF's default conversions)")
    ap.add_argument("extra", nargs="*")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="inksuite-")
    tasks = [(pdf, p) for pdf in sorted(glob.glob(os.path.join(args.pdf_dir, "*.pdf")))
             for p in pick(page_count(pdf), args.pages_per_doc)]
    # Processes, not threads: PIL's libtiff reader closes file descriptors
    # that other threads' pipes may have reused.
    with concurrent.futures.ProcessPoolExecutor(args.jobs) as ex:
        results = list(ex.map(one, [args] * len(tasks), [t[0] for t in tasks], [t[1] for t in tasks],
                              [work] * len(tasks)))
    for r in results:
        print("%-28s p%-4d %s %s" % (os.path.basename(r["pdf"]), r["page"], r["status"],
                                     "%.4f" % r["bad"] if "bad" in r else ""))
    passed = sum(r["status"] == "pass" for r in results)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    print("overall: %d/%d pages passed (%.1f%%)" % (passed, len(results), 100.0 * passed / max(1, len(results))))


if __name__ == "__main__":
    main()
