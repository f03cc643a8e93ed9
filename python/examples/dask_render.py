"""Batch rendering with Dask: every SVG of a folder, and every page of its
PDFs, to PNGs, with one mpvg.Renderer (and one open mpvg.Document a PDF) per
worker thread, made on first use and kept for the worker's later tasks: CUDA
starts once per worker, not once per file.

    python3 dask_render.py IN_DIR OUT_DIR [--width W] [--dpi N]
                           [--scheduler threads|processes|distributed] [--workers N]

    IN_DIR/a.svg     -> OUT_DIR/a.png       (svg2png -w W, or its own size)
    IN_DIR/b.pdf     -> OUT_DIR/b-1.png ... (pdf2png -r N, numbers padded)

--scheduler threads or processes runs a dask.bag on the local scheduler of
that kind; distributed starts a dask.distributed LocalCluster of --workers
processes, one thread each (on a cluster, pass its Client instead: render()
takes any). Prints one line a file written, "OUT WxH", and exits 1 when any
item failed (each failure said on standard error).

From Python: render(in_dir, out_dir, width=..., dpi=..., scheduler=...)
returns [(output path, width, height, error or None), ...] in the order of
the items (SVGs, then PDF pages, by name).
"""
import argparse
import os
import sys
import threading

import dask.bag as db

import mpvg

# The worker's own renderer and documents, kept on its thread (a Renderer
# is for one thread at a time): one per worker thread whatever the
# scheduler. On the Thread object, not in a module global: Dask ships a
# script's functions to worker processes by value, globals and all, and a
# threading.local does not pickle.
def _cache():
    return threading.current_thread().__dict__.setdefault("mpvg_dask_render", {})


def _renderer(backend):
    key = ("renderer", mpvg.Renderer, backend)
    cache = _cache()
    if key not in cache:
        cache[key] = mpvg.Renderer(backend)
    return cache[key]


def _document(path, backend):
    key = ("document", mpvg.Document, path, backend)
    cache = _cache()
    if key not in cache:
        cache[key] = mpvg.Document(path, backend=backend)
    return cache[key]


def items(in_dir):
    """The work: ("svg", path, None, out name) for each SVG, ("pdf", path, page, out name) for
    each page of each PDF (pages counted here, on the client), sorted by name."""
    names = sorted(os.listdir(in_dir))
    work = []
    for n in names:
        path = os.path.join(in_dir, n)
        stem, ext = os.path.splitext(n)
        if ext.lower() in (".svg", ".svgz"):
            work.append(("svg", path, None, stem + ".png"))
    for n in names:
        path = os.path.join(in_dir, n)
        stem, ext = os.path.splitext(n)
        if ext.lower() == ".pdf":
            try:
                with mpvg.Document(path, backend="cpu") as doc:
                    count = len(doc)
            except mpvg.Error as e:
                work.append(("pdf", path, -1, "%s: %s" % (n, e)))
                continue
            digits = len(str(count))
            for p in range(count):
                work.append(("pdf", path, p, "%s-%0*d.png" % (stem, digits, p + 1)))
    return work


def render_item(item, out_dir, width=None, dpi=150.0, backend="auto"):
    """Renders one item on this worker; returns (output path, width, height, error or None)."""
    kind, path, page, name = item
    if page == -1:  # a PDF that did not open on the client
        return (None, 0, 0, name)
    out = os.path.join(out_dir, name)
    try:
        if kind == "svg":
            image = _renderer(backend).render_svg(path, width=width)
        else:
            image = _document(path, backend).render(page, dpi=dpi)
        mpvg.write_png(out, image)
        return (out, int(image.shape[1]), int(image.shape[0]), None)
    except mpvg.Error as e:
        return (out, 0, 0, "%s: %s" % (os.path.basename(path), e))


def render(in_dir, out_dir, width=None, dpi=150.0, backend="auto", scheduler="threads", workers=2, client=None):
    """Renders IN_DIR's SVGs and PDF pages into OUT_DIR through Dask (see the module's text)."""
    os.makedirs(out_dir, exist_ok=True)
    work = items(in_dir)
    bag = db.from_sequence(work, npartitions=max(1, min(len(work), 4 * workers)))
    results = bag.map(render_item, out_dir, width=width, dpi=dpi, backend=backend)
    if client is not None:
        return client.compute(results).result()
    if scheduler == "distributed":
        from dask.distributed import Client, LocalCluster
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as c:
            return c.compute(results).result()
    return results.compute(scheduler=scheduler, num_workers=workers)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Renders a folder of SVGs and PDFs to PNGs with mpvg and Dask.")
    ap.add_argument("in_dir")
    ap.add_argument("out_dir")
    ap.add_argument("--width", type=float, help="SVG output width in pixels (default: the document's own)")
    ap.add_argument("--dpi", type=float, default=150, help="PDF resolution (default 150)")
    ap.add_argument("--backend", default="auto", choices=["auto", "cpu", "cuda"])
    ap.add_argument("--scheduler", default="threads", choices=["threads", "processes", "distributed"])
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    results = render(args.in_dir, args.out_dir, width=args.width, dpi=args.dpi, backend=args.backend,
                     scheduler=args.scheduler, workers=args.workers)
    failed = 0
    for out, w, h, error in results:
        if error:
            print("dask_render: %s" % error, file=sys.stderr)
            failed += 1
        else:
            print("%s %dx%d" % (out, w, h))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
