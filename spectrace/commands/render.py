"""``spectrace render``: render a Mitsuba XML scene to EXR and PNG in passes."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from spectrace import DEFAULT_VARIANT
from spectrace.errors import UserError
from spectrace.passes import DEFAULT_SPP_PER_PASS, check_sample_counts, scene_spp

FILMS = ("rgb", "spectral")
DEFAULT_BANDS = 16


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", help="Mitsuba XML scene file")
    parser.add_argument("-o", "--output", help="output EXR (default: out/<scene>.exr); "
                        "an sRGB PNG is written beside it")
    parser.add_argument("--variant", default=DEFAULT_VARIANT,
                        help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    parser.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    parser.add_argument("--spp-per-pass", type=int, default=DEFAULT_SPP_PER_PASS,
                        help=f"samples per pixel in one pass (default {DEFAULT_SPP_PER_PASS})")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                        help="set the scene parameter $NAME (XML <default>), repeatable")
    parser.add_argument("--film", choices=FILMS, default="rgb",
                        help="rgb: the scene's film; spectral: N bands, also OUT.spectral.exr")
    parser.add_argument("--bands", type=int, default=DEFAULT_BANDS,
                        help=f"spectral bands over 400-700 nm with --film spectral "
                        f"(default {DEFAULT_BANDS})")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def output_paths(scene: Path, output: str | None, film: str) -> dict[str, Path]:
    """The files a render writes: EXR, PNG beside it, and the spectral EXR for that film."""
    exr = Path(output) if output else Path("out") / f"{scene.stem}.exr"
    if exr.suffix.lower() != ".exr":
        raise UserError(f"output {exr}: must end in .exr (the PNG is written beside it)")
    paths = {"exr": exr, "png": exr.with_suffix(".png")}
    if film == "spectral":
        paths["spectral"] = exr.with_suffix(".spectral.exr")
    return paths


def run(args) -> int:
    from spectrace.images import check_writable

    scene_path = Path(args.scene)
    check_sample_counts(args.spp, args.spp_per_pass)  # before loading anything
    if args.film == "spectral":
        if args.bands < 1:
            raise UserError(f"--bands must be a positive integer (got {args.bands})")
        if "spectral" not in args.variant:
            raise UserError(f"--film spectral needs a spectral variant (got {args.variant})")
    paths = output_paths(scene_path, args.output, args.film)

    from spectrace.scene import load_scene, parse_defines, read_scene_xml

    params = parse_defines(args.defines)
    root = read_scene_xml(scene_path)
    import spectrace

    spectrace.set_variant(args.variant)
    wavelengths = None
    if args.film == "spectral":
        from spectrace.spectral_film import replace_film

        wavelengths = replace_film(root, bands=args.bands)
        scene = load_scene(scene_path, params, root=root)
    else:
        scene = load_scene(scene_path, params)
    for p in paths.values():  # before rendering: a bad output path costs no render time
        check_writable(p)
    spp = args.spp or scene_spp(scene)
    print(f"rendering {scene_path.name}: {spp} spp, {args.variant}, seed {args.seed}",
          file=sys.stderr, flush=True)
    result = _render_with_progress(scene, spp, args)
    if result.spp == 0:
        print("interrupted before the first pass finished: nothing written", file=sys.stderr)
        return 130
    if result.nonfinite:
        print(f"warning: {result.nonfinite} pixel values were NaN or infinite and were set to 0",
              file=sys.stderr)
    _write_outputs(result, paths, wavelengths, args, scene_path)
    rate = result.samples_per_second
    print(f"{scene_path.name}: {result.spp} spp in {result.passes} passes, "
          f"{result.seconds:.2f} s, {rate / 1e6:.2f} M samples/s -> {paths['exr']}")
    if result.interrupted:
        print(f"interrupted: saved {result.spp} of {spp} spp", file=sys.stderr)
        return 130
    return 0


def _render_with_progress(scene, spp, args):
    from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn,
                               TimeRemainingColumn)

    from spectrace.passes import render_passes

    quiet = args.quiet or not sys.stderr.isatty()
    with Progress("[progress.description]{task.description}", BarColumn(),
                  MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                  disable=quiet,
                  transient=True) as progress:
        task = progress.add_task("spp", total=spp)
        return render_passes(scene, spp, seed=args.seed, spp_per_pass=args.spp_per_pass,
                             on_pass=lambda done, total: progress.update(task, completed=done))


def _write_outputs(result, paths, wavelengths, args, scene_path) -> None:
    from spectrace.images import write_exr, write_png

    header = {
        "spp": int(result.spp),
        "variant": args.variant,
        "seed": int(args.seed),
        "scene": os.path.abspath(scene_path),
        "film": args.film,
    }
    rgb = result.image[..., :3]
    if wavelengths is not None:
        from spectrace.spectral import write_spectral_exr
        from spectrace.spectral_film import bands_to_linear_srgb, film_to_bands

        bands = film_to_bands(result.image, wavelengths)  # radiance per nm, band-averaged
        rgb = bands_to_linear_srgb(bands, wavelengths)
        write_spectral_exr(paths["spectral"], bands, wavelengths, preview=rgb,
                           attributes=header)
    write_exr(paths["exr"], rgb, header)
    write_png(paths["png"], rgb)
