"""``spectrace relight LAYERS.exr -L GROUP=SCALE[,SPECTRUM] ... -o OUT.exr``: new light
intensities from the light-group layers of one render, without rendering again.

LAYERS.exr is what ``spectrace render --light-groups`` (or ``--light-group``) writes. Each
``-L`` scales one group's layer (0 switches it off, 0.3 dims it to 30 %); groups not named
keep their intensity. OUT.exr holds the new beauty (R, G, B) and the scaled layers, so it
can be relit again; an sRGB PNG is written beside it. A new lamp spectrum (``,SPECTRUM``)
needs spectral layers, which these RGB layers are not: it is refused (see
:mod:`spectrace.lightgroups`). Bad input (a group not in the file, a scale < 0 or NaN):
one line, exit 2, nothing written.
"""

from __future__ import annotations

from pathlib import Path

from spectrace.errors import UsageError


def add_arguments(parser) -> None:
    parser.add_argument("layers", help="EXR with light-group layers (spectrace render "
                        "--light-groups)")
    parser.add_argument("-L", dest="lights", action="append", default=[],
                        metavar="GROUP=SCALE[,SPECTRUM]",
                        help="scale the layer of GROUP (repeatable; others keep scale 1)")
    parser.add_argument("-o", "--output", required=True, help="output EXR (a PNG beside it)")


def run(args) -> int:
    import time

    from spectrace import lightgroups
    from spectrace.images import check_writable, write_png

    out = Path(args.output)
    if out.suffix.lower() != ".exr":
        raise UsageError(f"-o {out}: must end in .exr (the PNG is written beside it)")
    scales, spectra = {}, {}
    for item in args.lights:
        group, scale, spectrum = lightgroups.parse_scale(item)
        if group in scales:
            raise UsageError(f"-L {item}: group {group!r} is given twice")
        scales[group] = scale
        if spectrum is not None:
            spectra[group] = spectrum
    start = time.perf_counter()
    _, layers, header = lightgroups.read_layers_exr(args.layers)
    image, scaled = lightgroups.relight(layers, scales, spectra)
    seconds = time.perf_counter() - start
    png = out.with_suffix(".png")
    for p in (out, png):
        check_writable(p)
    header = {k: v for k, v in header.items() if k in ("spp", "variant", "seed", "scene")}
    header["relight"] = ";".join(f"{g}={s:g}" for g, s in scales.items())
    lightgroups.write_layers_exr(out, image, scaled, header)
    write_png(png, image)
    factors = ", ".join(f"{g} x{scales.get(g, 1.0):g}" for g in layers)
    print(f"relit {len(layers)} layers ({factors}) in {seconds * 1e3:.0f} ms -> {out}")
    return 0
