"""python -m mpvg IN.svg OUT.png, or IN.pdf [OUT-PREFIX]: svg2png's and
pdf2png's quick use for one file from Python (console script `mpvg`).

SVG options (svg2png's spelling): -w/--width W, -h/--height H, -z/--zoom Z,
-a/--keep-aspect-ratio, --aa 4x4x32|1x32|1x8, --gamma linear|srgb,
-b/--background COLOUR, --bits 8|16, --seed N, --backend auto|cpu|cuda,
--allow-read DIR, --font-dir DIR (both repeatable), --languages LIST,
--max-memory SIZE, -q/--quiet. IN '-' reads standard input, OUT '-' writes to standard
output (not a terminal).

A PDF (its first bytes say %PDF) is written as pdf2png writes it:
OUT-PREFIX-1.png, ... (page numbers padded to the page count's digits;
-singlefile: OUT-PREFIX.png; no OUT-PREFIX, or '-': the one page selected on
standard output), with -r/--dpi N (default 150), -rx N, -ry N, -scale-to N,
-scale-to-x N, -scale-to-y N, -f N, -l N, --password P (also -upw, -opw),
--transparent, -gray, --box B, -hide-annotations, --thin-lines M, --aa,
--gamma (default srgb), --bits, --seed, --max-memory, --backend, -q. (Grey
pages are written as RGB PNGs of the same values: mpvg.write_png's.)

Exit codes, pdf2png's (pdftoppm's) for both: 0 done, 1 the document cannot
be opened (unreadable, malformed, encrypted), 2 an output file cannot be
written, 99 anything else (bad usage, a page that fails). Messages are one
line each on standard error, "mpvg: ...".
"""
import argparse
import os
import re
import sys
import tempfile
import warnings

import mpvg

EXIT_OK, EXIT_OPEN, EXIT_OUTPUT, EXIT_OTHER = 0, 1, 2, 99
EPILOG = ("Exit status, as pdf2png's (pdftoppm's): 0 done; 1 the document cannot be opened (missing, malformed, "
          "encrypted without --password or with a wrong one); 2 an output file cannot be written; 99 anything "
          "else: a bad option, a page that failed (the other pages are still written).")


class Usage(Exception):
    """A bad command line (exit 99)."""


class Parser(argparse.ArgumentParser):
    """argparse with pdf2png's usage failure: one line, exit 99 (argparse's own is 2, which is
    pdftoppm's 'output cannot be written')."""

    def error(self, message):
        raise Usage(message)


def say(message):
    print("mpvg: %s" % message, file=sys.stderr)


def open_message(e):
    """The line for a document that cannot be opened: a password failure names --password."""
    message = str(e)
    if isinstance(e, mpvg.PasswordError):
        message = message.replace(" (give it with password=...)", "")
        if "wrong password" not in message:
            message += " (give it with --password)"
    return message


def write_output(path, image):
    """Writes image as a PNG to path, or to standard output for '-'. Exit 2 (raised as OSError)
    when it cannot be written."""
    if path != "-":
        mpvg.write_png(path, image)
        return
    if sys.stdout.isatty():
        raise Usage("standard output is a terminal: redirect it, or name an output file")
    with tempfile.TemporaryDirectory() as tmp:
        name = os.path.join(tmp, "out.png")
        mpvg.write_png(name, image)
        with open(name, "rb") as f:
            sys.stdout.buffer.write(f.read())
        sys.stdout.buffer.flush()


def pdf_main(argv):
    ap = Parser(prog="python -m mpvg", allow_abbrev=False, add_help=False, epilog=EPILOG,
                description="Renders PDF pages to PNGs with mpvg (as pdf2png does: its options, its names "
                            "OUT-PREFIX-N.png).")
    ap.add_argument("input")
    ap.add_argument("prefix", nargs="?", default="-")
    ap.add_argument("-h", "-help", "--help", action="help")
    ap.add_argument("-r", "--dpi", type=float, default=150)
    ap.add_argument("-rx", type=float)
    ap.add_argument("-ry", type=float)
    ap.add_argument("-scale-to", "--scale-to", type=int, dest="scale_to")
    ap.add_argument("-scale-to-x", "--scale-to-x", type=int, dest="scale_to_x")
    ap.add_argument("-scale-to-y", "--scale-to-y", type=int, dest="scale_to_y")
    ap.add_argument("-f", type=int, default=1)
    ap.add_argument("-l", type=int, default=0)
    ap.add_argument("-singlefile", "--singlefile", action="store_true")
    ap.add_argument("--password", "-upw", "-opw", dest="password")
    ap.add_argument("--transparent", action="store_true")
    ap.add_argument("-gray", "--gray", action="store_true")
    ap.add_argument("--box", default="crop", choices=["media", "crop", "bleed", "trim", "art"])
    ap.add_argument("-hide-annotations", "--hide-annotations", action="store_true", dest="hide_annotations")
    ap.add_argument("--thin-lines", default="exact", choices=["exact", "snap"])
    ap.add_argument("--aa", default="4x4x32", choices=["4x4x32", "1x32", "1x8"])
    ap.add_argument("--gamma", default="srgb", choices=["linear", "srgb"])
    ap.add_argument("--bits", type=int, default=8, choices=[8, 16])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--max-memory")
    ap.add_argument("--backend", default="auto", choices=["auto", "cpu", "cuda"])
    ap.add_argument("-q", "--quiet", action="store_true", help="no warnings")
    args = ap.parse_args(argv)
    # -scale-to-x/-y as pdftoppm takes them (lib/pipeline/pdf_page_job.h): the
    # other axis keeps its resolution unless it is -1. render() takes
    # width/height (aspect kept when alone) and scale_to; the resolution
    # of an axis not given is dpi (or -rx/-ry).
    size = {}
    dpi = args.rx or args.dpi
    dpi_y = args.ry or (args.dpi if args.rx else None)
    sx, sy = args.scale_to_x or 0, args.scale_to_y or 0
    if 0 in (args.scale_to_x, args.scale_to_y) or min(sx, sy) < -1:
        raise Usage("-scale-to-x and -scale-to-y take a number of pixels, or -1 (keep the aspect ratio)")
    if args.scale_to:
        size = dict(scale_to=args.scale_to)
    elif sx > 0 and sy > 0:
        size = dict(width=sx, height=sy)
    elif sx > 0:
        size = dict(width=sx) if sy == -1 else dict(width=sx, height=None)
    elif sy > 0:
        size = dict(height=sy) if sx == -1 else dict(height=sy, width=None)
    try:
        doc = mpvg.Document(sys.stdin.buffer if args.input == "-" else args.input, password=args.password,
                            backend=args.backend)
    except (mpvg.Error, OSError) as e:
        say(open_message(e))
        return EXIT_OPEN
    with doc:
        n = len(doc)
        if n == 0:
            say("'%s' has no pages" % args.input)
            return EXIT_OTHER
        last = n if args.l <= 0 else min(args.l, n)
        if args.f < 1 or args.f > last:
            say("no pages to render (-f %d, -l %d, %d pages)" % (args.f, last, n))
            return EXIT_OTHER
        pages = list(range(args.f - 1, last))
        if args.singlefile:
            pages = pages[:1]
        if args.prefix == "-" and len(pages) != 1:
            raise Usage("%d pages to standard output: give an OUTPUT-PREFIX (or -singlefile, -f N -l N)" % len(pages))
        digits = len(str(n))
        options = dict(aa=args.aa, gamma=args.gamma, bits=args.bits, seed=args.seed, box=args.box,
                       annotations=not args.hide_annotations, thin_lines=args.thin_lines,
                       colorspace="gray" if args.gray else "rgb", max_memory=args.max_memory,
                       background=None if args.transparent else "white")
        failed = 0
        for p in pages:
            # One axis given alone keeps the other's resolution (not the
            # aspect ratio), as pdftoppm: that axis's resolution is the one
            # giving it its pixels (W * 72 / width in points), the other's dpi.
            kw, page_dpi, page_dpi_y = dict(size), dpi, dpi_y
            if kw.get("height", 0) is None or kw.get("width", 0) is None:
                w, h = doc[p].box_size(args.box)
                if kw.pop("width") is None:
                    page_dpi_y = kw.pop("height") * 72.0 / h
                else:
                    page_dpi_y = dpi_y or dpi
                    page_dpi = sx * 72.0 / w
                    kw.pop("height")
            try:
                # The page's warnings as pdf2png prints them, one line each.
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    image = doc.render(p, dpi=page_dpi, dpi_y=page_dpi_y, **kw, **options)
            except mpvg.OptionError as e:
                raise Usage(str(e))
            except mpvg.Error as e:
                say(e)
                failed += 1
                continue
            if not args.quiet:
                for w in caught:  # "page N: WHAT" (Document.render's) as pdf2png's "page N: warning: WHAT"
                    say(re.sub(r"^(page \d+: )?", lambda m: (m.group(1) or "") + "warning: ", str(w.message),
                               count=1))
            if args.prefix == "-":
                name = "-"
            elif args.singlefile:
                name = args.prefix + ".png"
            else:
                name = "%s-%0*d.png" % (args.prefix, digits, p + 1)
            try:
                write_output(name, image)
            except (mpvg.Error, OSError) as e:
                say(e)
                return EXIT_OUTPUT
        return EXIT_OTHER if failed else EXIT_OK


def svg_main(argv):
    # -h is svg2png's height: help is --help alone.
    ap = Parser(prog="python -m mpvg", add_help=False, allow_abbrev=False, epilog=EPILOG,
                description="Renders an SVG document to a PNG with mpvg (as svg2png does, with its options), or "
                            "a PDF's pages (python -m mpvg -h IN.pdf: pdf2png's options).")
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
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--backend", default="auto", choices=["auto", "cpu", "cuda"])
    ap.add_argument("--allow-read", action="append", default=[])
    ap.add_argument("--font-dir", action="append", default=[])
    ap.add_argument("--languages")
    ap.add_argument("--max-memory")
    ap.add_argument("-q", "--quiet", action="store_true", help="no warnings")
    ap.add_argument("--help", action="help")
    args = ap.parse_args(argv)
    if args.output == "-" and sys.stdout.isatty():
        raise Usage("standard output is a terminal: redirect it, or name an output file")
    # The document first: reading or parsing it failing is exit 1.
    try:
        if args.input == "-":
            source = dict(data=sys.stdin.buffer.read())
        else:
            with open(args.input, "rb") as f:
                source = dict(data=f.read(), base_dir=os.path.dirname(args.input) or ".")
    except OSError as e:
        say("cannot read '%s': %s" % (args.input, e.strerror or e))
        return EXIT_OPEN
    try:
        r = mpvg.Renderer(args.backend)
        image = r.render_svg(**source, width=args.width, height=args.height, zoom=args.zoom,
                             keep_aspect_ratio=args.keep_aspect_ratio, aa=args.aa, gamma=args.gamma,
                             background=args.background, bits=args.bits, seed=args.seed,
                             allow_read=args.allow_read, font_dir=args.font_dir, languages=args.languages,
                             max_memory=args.max_memory)
    except mpvg.OptionError as e:
        raise Usage(str(e))
    except mpvg.DocumentError as e:
        say(e)
        return EXIT_OPEN
    except mpvg.Error as e:
        say(e)
        return EXIT_OTHER
    if not args.quiet:
        for w in r.warnings:
            say("warning: %s" % w)
    try:
        write_output(args.output, image)
    except (mpvg.Error, OSError) as e:
        say(e)
        return EXIT_OUTPUT
    return EXIT_OK


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    # A PDF input (its first bytes, not its name, say so) goes to pdf_main.
    is_pdf = False
    for a in argv:
        if not a.startswith("-") and os.path.isfile(a):
            with open(a, "rb") as f:
                is_pdf = f.read(5) == b"%PDF-"
            break
    try:
        return pdf_main(argv) if is_pdf else svg_main(argv)
    except Usage as e:
        say(e)
        return EXIT_OTHER


if __name__ == "__main__":
    sys.exit(main())
