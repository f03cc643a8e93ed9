#!/usr/bin/env python3
"""The layout's include arrows (issue 48): a file may include its own
top-level folder and the folders below it, never one above or beside it.

    apps, python, fuzz  ->  lib (and include/)  ->  parsers  ->  text
      ->  cpu, gpu  ->  frame  ->  stroker  ->  core

(frame/: what the host does to a scene before either executor runs it.)
tests/ and scripts/ may include anything; nothing else is excepted. Also
refused: an include circle between two modules (a header and its source
file, x.h and x.cpp, taken as one).

    python3 tests/check_layout.py [SOURCE_DIR]
"""
import os
import re
import subprocess
import sys

LEVEL = {"core": 0, "stroker": 1, "frame": 2, "cpu": 3, "gpu": 3, "text": 4, "parsers": 5, "include": 6, "lib": 6,
         "apps": 7, "python": 7, "fuzz": 7}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    files = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout.split()
    sources = [f for f in files if re.search(r"\.(h|hpp|cpp|cu|cuh|inc)$", f)]
    upward, edges = set(), {}
    for f in sources:
        top = f.split("/")[0]
        text = open(os.path.join(root, f), errors="replace").read()
        targets = INCLUDE.findall(text)
        edges[f] = [t for t in targets if t in sources or os.path.exists(os.path.join(root, t))]
        if top not in LEVEL:
            continue
        for t in targets:
            to = t.split("/")[0]
            if to in LEVEL and to != top and LEVEL[to] >= LEVEL[top]:
                upward.add(f + " -> " + t)
    failures = 0
    for arrow in sorted(upward):
        print("upward include: " + arrow)
        failures += 1
    # Two modules (a header with its source file: x.h and x.cpp) that include
    # each other: x.h declares what y's files use and x's files include y.h.
    module = lambda path: os.path.splitext(path)[0]
    uses = {}
    for f, targets in edges.items():
        for t in targets:
            if module(t) != module(f):
                uses.setdefault(module(f), set()).add(module(t))
    for a in sorted(uses):
        for b in sorted(uses[a]):
            if a < b and a in uses.get(b, ()):
                print("include circle: %s <-> %s" % (a, b))
                failures += 1
    print("%d files, %d failures" % (len(sources), failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
