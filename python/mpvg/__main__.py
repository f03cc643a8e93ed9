"""python -m mpvg IN.svg OUT.png, or IN.pdf OUT-PREFIX: svg2png's and
pdf2png's quick use from Python.

SVG options (svg2png's spelling): -w/--width W, -h/--height H, -z/--zoom Z,
-a/--keep-aspect-ratio, --aa 4x4x32|1x32|1x8, --gamma linear|srgb,
-b/--background COLOUR, --bits 8|16, --backend auto|cpu|cuda,
--allow-read DIR (repeatable). OUT.png '-' writes to standard output.

A PDF (its first bytes say %PDF) is written as pdf2png writes it:
OUT-PREFIX-1.png, ... (page numbers padded to the page count's digits),
with -r/--dpi N (default 150), -f N and -l N (first and last page),
--password P, --transparent, and --aa, --gamma (default srgb), --bits,
--backend as above.
"""
import argparse
import os
import sys

import mpvg


def pdf_main(argv):
    ap = argparse.ArgumentParser(prog="python -m mpvg", description="Renders PDF pages to PNGs (as pdf2png does).")
    ap.add_argument("input")
    ap.add_argument("prefix")
    ap.add_argument("-r", "--dpi", type=float, default=150)
    ap.add_argument("-f", type=int, default=1)
    ap.add_argument("-l", type=int, default=0)
    ap.add_argument("--password")
    ap.add_argument("--transparent", action="store_true")
    ap.add_argument("--aa", default="4x4x32", choices=["4x4x32", "1x32", "1x8"])
    ap.add_argument("--gamma", default="srgb", choices=["linear", "srgb"])
    ap.add_argument("--bits", type=int, default=8, choices=[8, 16])
    ap.add_argument("--backend", default="auto", choices=["auto", "cpu", "cuda"])
    args = ap.parse_args(argv)
    try:
        doc = mpvg.Document(args.input, password=args.password, backend=args.backend)
        n = len(doc)
        last = n if args.l <= 0 else min(args.l, n)
        if args.f < 1 or args.f > last:
            raise ValueError("no pages to render (-f %d, -l %d, %d pages)" % (args.f, last, n))
        pages = list(range(args.f - 1, last))
        digits = len(str(n))
        failed = 0
        stream = doc.render_pages(pages, dpi=args.dpi, aa=args.aa, gamma=args.gamma, bits=args.bits,
                                  background=None if args.transparent else "white")
        for p in pages:
            try:
                image = next(stream)
            except mpvg.Error as e:
                print("mpvg: %s" % e, file=sys.stderr)
                failed += 1
                continue
            mpvg.write_png("%s-%0*d.png" % (args.prefix, digits, p + 1), image)
        return 1 if failed else 0
    except (mpvg.Error, OSError, ValueError) as e:
        print("mpvg: %s" % e, file=sys.stderr)
        return 1


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    # A PDF input (its first bytes, not its name, say so) goes to pdf_main.
    for a in argv:
        if not a.startswith("-") and os.path.isfile(a):
            with open(a, "rb") as f:
                if f.read(5) == b"%PDF-":
                    return pdf_main(argv)
            break
    ap = argparse.ArgumentParser(prog="python -m mpvg", add_help=False,
                                 description="Renders an SVG document to a PNG with mpvg (as svg2png does).")
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("-w", "--width", type=float)
    ap.add_argument("-h", "--height", type=float)
    ap.add_argument("-z", "--zoom", type=float)
    ap.add_argument("-a", "--keep-aspect-ratio", action="store_true")
    ap.add_argument("--aa", default="4x4x32", choices=["4x4x32", "1x32", "1x8"])
    ap.add_argument("--gamma", default="linear", choices=["linear", "srgb"])
    ap.add_argument("-b", "--background")
    ap.add_argument("--bits", type=int, default=8, choices=[8, 16])
    ap.add_argument("--backend", default="auto", choices=["auto", "cpu", "cuda"])
    ap.add_argument("--allow-read", action="append", default=[])
    ap.add_argument("--help", action="help")
    args = ap.parse_args(argv)
    return svg_main(args)


def svg_main(args):
    try:
        r = mpvg.Renderer(args.backend)
        svg = sys.stdin.buffer.read() if args.input == "-" else args.input
        image = r.render_svg(svg, width=args.width, height=args.height, zoom=args.zoom,
                             keep_aspect_ratio=args.keep_aspect_ratio, aa=args.aa, gamma=args.gamma,
                             background=args.background, bits=args.bits, allow_read=args.allow_read)
        for w in r.warnings:
            print("mpvg: warning: %s" % w, file=sys.stderr)
        mpvg.write_png(args.output, image)
    except (mpvg.Error, OSError, ValueError) as e:
        print("mpvg: %s" % e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
