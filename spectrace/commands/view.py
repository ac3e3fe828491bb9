"""``spectrace view IMAGE.exr -o OUT.png``: develop an EXR again without rendering, as a
raw converter does: exposure, white balance, view transform, encoding
(:mod:`spectrace.display`).

Reads spectrace's EXRs (linear sRGB R, G, B), the half-float EXR that Mitsuba's
``mitsuba`` writes, one-channel ``Y`` EXRs, and Fichet 2021 spectral EXRs (their R, G, B
preview when present, else the spectra through
:func:`spectrace.spectral.spectral_image_to_linear_srgb`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from spectrace.commands import add_display_options, display_settings
from spectrace.errors import UsageError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("image", help="EXR file: linear sRGB (spectrace's or Mitsuba's), or "
                        "a spectral EXR (Fichet 2021 layout)")
    parser.add_argument("-o", "--output", help="output PNG (default: IMAGE with .png)")
    add_display_options(parser)


def run(args) -> int:
    from spectrace.images import check_writable

    image = Path(args.image)
    out = Path(args.output) if args.output else image.with_suffix(".png")
    if out.suffix.lower() != ".png":
        raise UsageError(f"-o {out}: must end in .png")
    if out.resolve() == image.resolve():
        raise UsageError(f"-o {out}: would overwrite the input")
    settings = display_settings(args)
    if image.suffix.lower() != ".exr":
        raise UsageError(f"{image}: spectrace view reads EXR files")
    check_writable(out)
    from spectrace.display import write_display_png
    from spectrace.images import read_linear_srgb

    display_exr = out.with_suffix(".display.exr") if args.display_exr else None
    if display_exr is not None:
        check_writable(display_exr)
    rgb = read_linear_srgb(image)
    developed = write_display_png(out, rgb, settings, display_exr)
    for note in developed.notes:
        print(note)
    h, w = developed.codes.shape[:2]
    print(f"{image.name}: {settings.view}, {settings.display}, {settings.png_bits}-bit "
          f"{w} x {h} -> {out}")
    return 0
