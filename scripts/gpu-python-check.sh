#!/usr/bin/env bash
# The Python package's device output on the GPU host (issue 31), where
# pip cannot fetch anything: the extension is compiled there against that
# host's Python and the pybind11 headers PyTorch ships, linked with
# libmpvg.so built here with CUDA; then DeviceArray is checked against
# host arrays through __cuda_array_interface__ (ctypes and cudart) and
# torch.from_dlpack, and render_pages is timed on asymptote and pgfmanual
# into device tensors, against mutool draw over every core (.gpu/mutool.tar.xz:
# Debian's mutool and its libraries; .gpu/asym.pdf, .gpu/pgf.pdf from the corpus).
#
# Here:   mkdir -p .gpu/lm/lib .gpu/lm/deps && cp -L build/lib/libmpvg.so.0 .gpu/lm/lib/ &&
#         scripts/carry-libs.sh .gpu/lm/lib .gpu/lm/deps && mv .gpu/lm/deps/* .gpu/lm/lib/ &&
#         rmdir .gpu/lm/deps && tar -C .gpu -cf - lm | xz -T8 -3 > .gpu/lm.tar.xz &&
#         cp ../shared/pdf-corpus/asymptote.pdf .gpu/asym.pdf
# There:  scripts/gpu-python-check.sh   (carry .gpu/lm.tar.xz and .gpu/asym.pdf)
set -u
[ -d /tmp/lm ] || tar -C /tmp -xJf .gpu/lm.tar.xz  # (unpacked already: one archive with mutool's)
ln -sf libmpvg.so.0 /tmp/lm/lib/libmpvg.so
PY=$(which python3)
PYBIND=$($PY -c "import torch, os; print(os.path.join(os.path.dirname(torch.__file__), 'include'))" 2>/dev/null)
[ -d "$PYBIND/pybind11" ] || PYBIND=$($PY -c "import pybind11; print(pybind11.get_include())" 2>/dev/null)
echo "python $($PY --version), pybind11 headers: $PYBIND"
mkdir -p /tmp/pkg/mpvg && cp python/mpvg/*.py /tmp/pkg/mpvg/
t0=$(date +%s)
g++ -O2 -shared -fPIC -std=c++17 -DMPVG_VERSION='"0.1"' python/_mpvg.cpp -Iinclude -I"$PYBIND" \
  $($PY -c "import sysconfig; print('-I' + sysconfig.get_paths()['include'])") -L/tmp/lm/lib -lmpvg \
  -Wl,-rpath,/tmp/lm/lib -o /tmp/pkg/mpvg/_mpvg$($PY -c "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))") || exit 1
echo "extension compiled in $(( $(date +%s) - t0 )) s"
export LD_LIBRARY_PATH=/tmp/lm/lib
PYTHONPATH=/tmp/pkg $PY - <<'PYEOF'
import ctypes, time, os
import numpy as np
import mpvg
print("mpvg", mpvg.__version__)
cudart = ctypes.CDLL("libcudart.so")
def from_interface(a):
    ai = a.__cuda_array_interface__
    h, w, c = ai["shape"]
    out = np.empty((h, w, c), np.uint8)
    rc = cudart.cudaMemcpy(out.ctypes.data_as(ctypes.c_void_p), ctypes.c_void_p(ai["data"][0]), ctypes.c_size_t(out.nbytes), 2)
    assert rc == 0, rc
    return out
fails = 0
for name in ["blend-modes", "shading-axial", "image-smask", "knockout-group", "mesh-type4"]:
    doc = mpvg.Document("testdata/pdf/features/%s.pdf" % name, backend="cuda")
    host = doc.render(0, dpi=100)
    dev = doc.render(0, dpi=100, device="cuda")
    ok1 = dev.shape == host.shape and (dev.to_host() == host).all()
    ok2 = (from_interface(dev) == host).all()
    try:
        import torch
        t = torch.from_dlpack(dev)
        ok3 = t.is_cuda and tuple(t.shape) == host.shape and (t.cpu().numpy() == host).all()
        del t
    except ImportError:
        ok3 = "no torch"
    print(name, "to_host", ok1, "cuda_array_interface", ok2, "torch.from_dlpack", ok3, "dlpack_device", dev.__dlpack_device__())
    fails += not (ok1 and ok2 and ok3 in (True, "no torch"))
# The device memory outlives the DeviceArray when a tensor holds it.
try:
    import torch
    doc = mpvg.Document("testdata/pdf/features/blend-modes.pdf", backend="cuda")
    t = torch.from_dlpack(doc.render(0, dpi=100, device="cuda"))
    for _ in range(3): doc.render(0, dpi=50, device="cuda")
    ok = (t.cpu().numpy() == doc.render(0, dpi=100)).all()
    print("a tensor from DLPack keeps the image alive:", ok); fails += not ok
except ImportError:
    pass
# render_batch: one N x H x W x 4 device tensor, page k at [k].
doc = mpvg.Document("testdata/pdf/three-pages.pdf", backend="cuda")
batch = doc.render_batch([2, 0, 1], dpi=72)
want = np.stack([doc.render(p, dpi=72) for p in (2, 0, 1)])
ok = batch.shape == want.shape and (batch.to_host() == want).all()
try:
    import torch
    t = torch.from_dlpack(batch)
    ok = ok and tuple(t.shape) == want.shape and (t.cpu().numpy() == want).all()
except ImportError:
    pass
print("render_batch: N x H x W x 4 equal to the pages rendered alone:", ok, batch.shape); fails += not ok
doc = mpvg.Document(".gpu/asym.pdf", backend="cuda")
for rnd in range(2):
    t0 = time.time()
    b = doc.render_batch(dpi=150)
    dt = time.time() - t0
    print("render_batch asymptote 150 dpi: %d pages in %.2f s, %.1f pages/s into one device tensor %s (round %d)"
          % (b.shape[0], dt, b.shape[0] / dt, b.shape, rnd + 1))
    del b
for rnd in range(2):
    t0 = time.time(); n = 0
    for a in doc.render_pages(dpi=150):
        n += 1
    dt = time.time() - t0
    print("render_pages asymptote 150 dpi: %d pages in %.2f s, %.1f pages/s (round %d)" % (n, dt, n / dt, rnd + 1))
# render_pages(device="cuda"): a DeviceArray a page, in the order asked,
# each render()'s pixels.
doc3 = mpvg.Document("testdata/pdf/three-pages.pdf", backend="cuda")
got = list(doc3.render_pages([2, 0, 1, 2], dpi=72, device="cuda"))
ok = all(isinstance(g, mpvg.DeviceArray) and (g.to_host() == doc3.render(p, dpi=72)).all()
         for g, p in zip(got, [2, 0, 1, 2])) and len(got) == 4
print("render_pages(device='cuda'): DeviceArrays equal to render()'s pixels, in order:", ok); fails += not ok
for path in [".gpu/asym.pdf", ".gpu/pgf.pdf"]:
    if not os.path.exists(path):
        continue
    d = mpvg.Document(path, backend="cuda")
    for rnd in range(2):
        t0 = time.time(); n = 0
        for a in d.render_pages(dpi=150, device="cuda"):
            n += 1
        dt = time.time() - t0
        print("render_pages(device='cuda') %s 150 dpi: %d pages in %.2f s, %.1f pages/s (round %d)"
              % (os.path.basename(path), n, dt, n / dt, rnd + 1))
t0 = time.time()
for p in range(len(doc)):
    doc.render(p, dpi=150, device="cuda")
dt = time.time() - t0
print("render(device='cuda') one page at a time: %.1f pages/s" % (len(doc) / dt))
print("FAILURES", fails)
PYEOF
# The baseline on the same host: mutool draw over every core (one process
# per core over equal page ranges, as PyMuPDF's get_pixmap in a
# multiprocessing pool would run), rendering to PAM (no compression: the
# pixels, as get_pixmap gives them) and to PNG.
if [ -d /tmp/mt ] || [ -f .gpu/mutool.tar.xz ]; then
  [ -d /tmp/mt ] || tar -C /tmp -xJf .gpu/mutool.tar.xz
  cores=$(nproc)
  for f in .gpu/asym.pdf .gpu/pgf.pdf; do
    [ -f "$f" ] || continue
    n=$(LD_LIBRARY_PATH=/tmp/mt/lib /tmp/mt/bin/mutool info -M "$f" 2>/dev/null | sed -n 's/^Pages: *//p')
    for fmt in pam png; do
      rm -rf /tmp/mo && mkdir -p /tmp/mo
      t0=$(date +%s%N)
      for k in $(seq 0 $((cores - 1))); do
        a=$((k * n / cores + 1)) b=$(((k + 1) * n / cores))
        [ "$a" -le "$b" ] && LD_LIBRARY_PATH=/tmp/mt/lib /tmp/mt/bin/mutool draw -q -r 150 -o "/tmp/mo/m$k-%d.$fmt" "$f" "$a-$b" 2>/dev/null &
      done
      wait
      t1=$(date +%s%N)
      echo "mutool draw -r 150 ($fmt), $cores processes, $(basename "$f"): $n pages, $(awk "BEGIN{printf \"%.1f\", $n / (($t1 - $t0) / 1e9)}") pages/s"
    done
  done
fi
