"""``spectrace relight LAYERS.exr -L GROUP=SCALE[,SPECTRUM] ... -o OUT.exr``: new light
intensities, and from spectral layers new lamp spectra, from the light-group layers of one
render, without rendering again.

LAYERS.exr is what ``spectrace render --light-groups`` (or ``--light-group``) writes; with
``--film spectral`` it also writes LAYERS.spectral.exr, the spectral layers. Each ``-L``
scales one group's layer (0 switches it off, 0.3 dims it to 30 %); groups not named keep
their intensity. ``,SPECTRUM`` (an SPD file or a colour-science name: FL2, A, D65, LED
names...) gives the group's lamps that spectrum at the same luminous output; it needs the
spectral layers and is refused on RGB ones (see :mod:`spectrace.lightgroups`). OUT.exr
holds the new beauty (R, G, B) and the scaled layers, so it can be relit again, an sRGB
PNG is written beside it, and from spectral layers OUT.spectral.exr too. Bad input (a
group not in the file, a scale < 0 or NaN, an unknown or negative SPD): one line, exit 2,
nothing written.
"""

from __future__ import annotations

from pathlib import Path

from spectrace.commands import add_display_options, display_settings, write_picture
from spectrace.errors import UsageError


def add_arguments(parser) -> None:
    parser.add_argument("layers", help="EXR with light-group layers (spectrace render "
                        "--light-groups)")
    parser.add_argument("-L", dest="lights", action="append", default=[],
                        metavar="GROUP=SCALE[,SPECTRUM]",
                        help="scale the layer of GROUP (repeatable; others keep scale 1)")
    parser.add_argument("-o", "--output", required=True, help="output EXR (a PNG beside it)")
    add_display_options(parser)


def run(args) -> int:
    import time

    from spectrace import lightgroups
    from spectrace.images import check_writable

    settings = display_settings(args)  # a bad display option: nothing read or written
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
    png = out.with_suffix(".png")
    if lightgroups.is_spectral_layers_file(args.layers):
        return _relight_spectral(args.layers, out, png, scales, spectra, settings,
                                 args.display_exr)
    start = time.perf_counter()
    _, layers, header = lightgroups.read_layers_exr(args.layers)
    if spectra:
        raise UsageError(f"-L {next(iter(spectra))}=...,SPECTRUM: {args.layers} has RGB "
                         "layers; a new lamp spectrum needs the spectral layers "
                         "(OUT.spectral.exr of render --film spectral --light-groups)")
    image, scaled = lightgroups.relight(layers, scales)
    seconds = time.perf_counter() - start
    display_exr = out.with_suffix(".display.exr") if args.display_exr else None
    for p in (out, png, display_exr):
        if p is not None:
            check_writable(p)
    header = _header(header, scales, spectra)
    lightgroups.write_layers_exr(out, image, scaled, header)
    notes = write_picture(png, image, settings, display_exr)
    _report(layers, scales, seconds, out, notes)
    return 0


def _header(header, scales, spectra):
    kept = {k: v for k, v in header.items() if k in ("spp", "variant", "seed", "scene")}
    kept["relight"] = ";".join([f"{g}={s:g}" for g, s in scales.items()]
                               + [f"{g}:{v}" for g, v in spectra.items()])
    return kept


def _report(layers, scales, seconds, out, notes=()):
    factors = ", ".join(f"{g} x{scales.get(g, 1.0):g}" for g in layers)
    print(f"relit {len(layers)} layers ({factors}) in {seconds * 1e3:.0f} ms -> {out}")
    for note in notes:
        print(note)


def _relight_spectral(path, out, png, scales, spectra, settings, display) -> int:
    """Spectral layers: new intensities and lamp spectra; writes OUT.spectral.exr (the
    relit spectral layers), OUT.exr (their RGB) and the PNG."""
    import time

    from spectrace import lightgroups
    from spectrace.images import check_writable
    from spectrace.spectral import load_spd
    from spectrace.spectral_film import bands_to_linear_srgb

    start = time.perf_counter()
    _, layers, wavelengths, old, header = lightgroups.read_spectral_layers_exr(path)
    new = {g: load_spd(source)[:2] for g, source in spectra.items()}
    image, scaled = lightgroups.relight_spectral(layers, wavelengths, scales, new, old)
    seconds = time.perf_counter() - start
    spectral = out.with_suffix(".spectral.exr")
    display_exr = out.with_suffix(".display.exr") if display else None
    for p in (out, png, spectral, display_exr):
        if p is not None:
            check_writable(p)
    recorded = dict(old)
    for g, (wl, values) in new.items():  # the new lamp spectrum, peak 1, for a next relight
        v = lightgroups.band_averages(wl, values, wavelengths)
        recorded[g] = v / v.max()
    rgb = bands_to_linear_srgb(image, wavelengths)
    header = _header(header, scales, spectra)
    lightgroups.write_spectral_layers_exr(spectral, image, scaled, wavelengths, rgb,
                                          recorded, header)
    lightgroups.write_layers_exr(out, rgb, {g: bands_to_linear_srgb(v, wavelengths)
                                            for g, v in scaled.items()}, header)
    notes = write_picture(png, rgb, settings, display_exr)
    _report(layers, scales, seconds, spectral, notes)
    return 0
