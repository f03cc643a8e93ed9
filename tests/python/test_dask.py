"""python/examples/dask_render.py on testdata: a folder of SVGs and PDFs
rendered through dask.bag (threads and processes) and dask.distributed,
each output equal to what svg2png or pdf2png writes for it. Skipped, saying
so, where dask (python3-dask, python3-distributed) is not importable."""
import importlib.util
import os
import shutil
import subprocess
import sys
import types

import numpy as np
import pytest

from conftest import GOLDEN, PDFS, SRC, read_png, rgba, run

dask = pytest.importorskip("dask", reason="dask is not installed (Debian: python3-dask)")
EXAMPLE = os.path.join(SRC, "python", "examples", "dask_render.py")
SVGS = ["arcs.svg", "stroke_joins.svg", "gradient_reflect.svg"]


def load_example():
    spec = importlib.util.spec_from_file_location("dask_render", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("in")
    for n in SVGS:
        shutil.copy(os.path.join(GOLDEN, n), folder / n)
    shutil.copy(os.path.join(PDFS, "three-pages.pdf"), folder / "three.pdf")
    return folder


@pytest.fixture(scope="module")
def expected(inputs, svg2png, pdf2png, tmp_path_factory):
    """What the CLIs write for each output name."""
    out = tmp_path_factory.mktemp("cli")
    want = {}
    for n in SVGS:
        run(svg2png, "-q", "--backend", "cpu", "-w", "96", inputs / n, out / n.replace(".svg", ".png"))
    run(pdf2png, "-q", "--backend", "cpu", "-r", "36", inputs / "three.pdf", out / "three")
    for n in os.listdir(out):
        want[n] = rgba(read_png(out / n))
    assert sorted(want) == sorted([n.replace(".svg", ".png") for n in SVGS] + ["three-1.png", "three-2.png",
                                                                              "three-3.png"])
    return want


def check_outputs(folder, results, expected):
    assert sorted(os.listdir(folder)) == sorted(expected)
    for out, w, h, error in results:
        assert error is None
        name = os.path.basename(out)
        got = rgba(read_png(out))
        assert got.shape == (h, w, 4) and np.array_equal(got, expected[name]), name


@pytest.mark.parametrize("scheduler", ["threads", "processes"])
def test_dask_bag(inputs, expected, tmp_path, scheduler):
    example = load_example()
    results = example.render(str(inputs), str(tmp_path / "out"), width=96, dpi=36, backend="cpu",
                             scheduler=scheduler, workers=2)
    assert len(results) == 6
    check_outputs(tmp_path / "out", results, expected)


def test_dask_distributed_command_line(inputs, expected, tmp_path):
    pytest.importorskip("distributed", reason="dask.distributed is not installed (Debian: python3-distributed)")
    r = subprocess.run([sys.executable, EXAMPLE, str(inputs), str(tmp_path / "out"), "--width", "96", "--dpi", "36",
                        "--backend", "cpu", "--scheduler", "distributed", "--workers", "2"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split("\n")[:-1]
    assert len(lines) == 6 and lines[-1].endswith("three-3.png 50x50"), lines
    results = []
    for line in lines:
        out, size = line.rsplit(" ", 1)
        w, h = map(int, size.split("x"))
        results.append((out, w, h, None))
    check_outputs(tmp_path / "out", results, expected)


def test_one_renderer_per_worker(inputs, tmp_path):
    example = load_example()
    made = []
    real = example.mpvg.Renderer

    class Counting(real):
        def __init__(self, *a, **kw):
            made.append(1)
            super().__init__(*a, **kw)

    example.mpvg = types.SimpleNamespace(**dict(vars(example.mpvg), Renderer=Counting))
    example.render(str(inputs), str(tmp_path / "out"), width=96, dpi=36, backend="cpu", scheduler="threads",
                   workers=2)
    # Three SVGs over two worker threads: at most one Renderer each.
    assert 1 <= len(made) <= 2
