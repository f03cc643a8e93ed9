#!/usr/bin/env python3
"""The layout's include arrows (issue 48): a file may include its own
top-level folder and the folders below it, never one above or beside it.

    apps, python, fuzz  ->  lib (and include/)  ->  parsers  ->  text
      ->  cpu, gpu  ->  stroker  ->  core

tests/ and scripts/ may include anything. KNOWN lists the arrows that still
run upward, each to be removed (a file that breaks the rule and is not
listed fails the check; a listed arrow that is gone fails it too, so the
list only shrinks). Also refused: an include circle between two files.

    python3 tests/check_layout.py [SOURCE_DIR]
"""
import os
import re
import subprocess
import sys

LEVEL = {"core": 0, "stroker": 1, "cpu": 2, "gpu": 2, "text": 3, "parsers": 4, "include": 5, "lib": 5,
         "apps": 6, "python": 6, "fuzz": 6}

# Arrows that still run upward (file -> included file), issue 48's work left.
KNOWN = {
    # The CPU frame (core/renderer.cpp) and the encoding, which builds the
    # stroke stage's input, are still in core/: they leave it.
    "core/renderer.cpp -> cpu/cpu_stages.h",
    "core/encoding.h -> stroker/stroke_input.h",
}

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
    for arrow in sorted(upward - KNOWN):
        print("upward include: " + arrow)
        failures += 1
    for arrow in sorted(KNOWN - upward):
        print("gone, remove it from KNOWN: " + arrow)
        failures += 1
    # Two files that include each other (directly).
    for f, targets in edges.items():
        for t in targets:
            if f in edges.get(t, []) and f < t:
                print("include circle: %s <-> %s" % (f, t))
                failures += 1
    print("%d files, %d upward arrows known (issue 48), %d failures" % (len(sources), len(KNOWN & upward), failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
