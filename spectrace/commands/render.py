"""``spectrace render``: render Mitsuba XML scenes to EXR and PNG in passes.

Several scenes render one after the other in this process (the variant is set and the
plugins registered once, and Dr.Jit reuses the kernels they share). With ``--workers N`` or
``--scheduler ADDRESS`` the passes of each render run on a Dask cluster
(:func:`spectrace.cluster.render_passes_distributed`: the same pass seeds, the same image).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from pathlib import Path

from spectrace.commands import add_render_options, progress_bar
from spectrace.errors import UserError
from spectrace.passes import check_sample_counts, check_seed, scene_spp

FILMS = ("rgb", "spectral")
DEFAULT_BANDS = 16


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", nargs="+", help="Mitsuba XML scene file(s), rendered in one "
                        "process (plugins registered once, kernels reused)")
    parser.add_argument("-o", "--output", help="output EXR (default: out/<scene>.exr), or a "
                        "folder (FOLDER/) for <scene>.exr there, which several scenes need; "
                        "an sRGB PNG is written beside each EXR")
    add_render_options(parser)
    parser.add_argument("--film", choices=FILMS, default="rgb",
                        help="rgb: the scene's film; spectral: N bands, also OUT.spectral.exr")
    parser.add_argument("--bands", type=int, default=None,
                        help=f"spectral bands over 400-700 nm with --film spectral "
                        f"(default {DEFAULT_BANDS})")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="render the passes on a local Dask cluster of N worker processes")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="render the passes on the Dask cluster of this scheduler "
                       "(tcp://host:8786); workers read the scene at the same path")


def _is_folder(output: str) -> bool:
    return output.endswith(("/", os.sep)) or Path(output).is_dir()


def scene_outputs(scenes: list[Path], output: str | None, film: str) -> list[dict[str, Path]]:
    """The files of each scene: -o OUT.exr for one scene, -o FOLDER/ for any number."""
    if output is not None and _is_folder(output):
        outs = [str(Path(output) / f"{s.stem}.exr") for s in scenes]
    elif output is not None and len(scenes) > 1:
        raise UserError(f"-o {output}: with {len(scenes)} scenes, -o must be a folder "
                        "(end it with /)")
    else:
        outs = [output] * len(scenes)
    paths = [output_paths(s, o, film) for s, o in zip(scenes, outs, strict=True)]
    seen: dict[Path, Path] = {}
    for scene, p in zip(scenes, paths, strict=True):
        if p["exr"] in seen:
            raise UserError(f"scenes {seen[p['exr']]} and {scene} would both write {p['exr']}")
        seen[p["exr"]] = scene
    return paths


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
    import time

    from spectrace.images import check_writable

    scene_paths = [Path(s) for s in args.scene]
    check_sample_counts(args.spp, args.spp_per_pass)  # before loading anything
    check_seed(args.seed)
    if args.film == "spectral":
        if args.bands is None:
            args.bands = DEFAULT_BANDS
        if args.bands < 1:
            raise UserError(f"--bands must be a positive integer (got {args.bands})")
        if "spectral" not in args.variant:
            raise UserError(f"--film spectral needs a spectral variant (got {args.variant})")
    elif args.bands is not None:
        raise UserError("--bands applies only with --film spectral")
    if args.workers is not None and args.workers < 1:
        raise UserError(f"--workers must be a positive integer (got {args.workers})")
    all_paths = scene_outputs(scene_paths, args.output, args.film)

    from spectrace.scene import load_scene, parse_defines, read_scene_xml

    params = parse_defines(args.defines)
    roots = [read_scene_xml(p) for p in scene_paths]
    import spectrace

    spectrace.set_variant(args.variant, lazy=True)  # plugins registered as scenes load
    loaded = []  # every scene loads before anything renders: a bad one costs no output
    for scene_path, root in zip(scene_paths, roots, strict=True):
        wavelengths = None
        if args.film == "spectral":
            from spectrace.spectral_film import replace_film

            wavelengths = replace_film(root, bands=args.bands)
            scene = load_scene(scene_path, params, root=root)
        else:
            scene = load_scene(scene_path, params)
        loaded.append((scene, wavelengths))
    start = time.perf_counter()
    with contextlib.ExitStack() as stack:
        client = None
        if args.workers is not None or args.scheduler:  # before any folder is made
            from spectrace.cluster import connect

            client = stack.enter_context(connect(args.workers, args.scheduler,
                                                 variant=args.variant))
        for paths in all_paths:  # before rendering: a bad output path costs no render time
            for p in paths.values():
                check_writable(p)
        for scene_path, (scene, wavelengths), paths in zip(scene_paths, loaded, all_paths,
                                                            strict=True):
            code = _render_one(scene_path, scene, wavelengths, paths, params, args, client)
            if code:
                return code
    if len(scene_paths) > 1:
        print(f"total: {len(scene_paths)} scenes in {time.perf_counter() - start:.2f} s")
    return 0


def _render_one(scene_path, scene, wavelengths, paths, params, args, client) -> int:
    spp = args.spp or scene_spp(scene)
    where = ""
    if client is not None:
        where = f", {len(client.scheduler_info(n_workers=-1)['workers'])} workers"
    print(f"rendering {scene_path.name}: {spp} spp, {args.variant}, seed {args.seed}{where}",
          file=sys.stderr, flush=True)
    result = _render_with_progress(scene, spp, args, client, scene_path, params)
    if result.spp == 0:
        print("interrupted before the first pass finished: nothing written", file=sys.stderr)
        return 130
    if result.nonfinite:
        print(f"warning: {result.nonfinite} pixel values were NaN or infinite and were set to 0",
              file=sys.stderr)
    _write_outputs(result, paths, wavelengths, args, scene_path)
    rate = result.samples_per_second
    passes = f"{result.passes} pass{'' if result.passes == 1 else 'es'}"
    print(f"{scene_path.name}: {result.spp} spp in {passes}, {result.seconds:.2f} s, "
          f"{rate / 1e6:.2f} M samples/s -> {paths['exr']}", flush=True)
    if result.interrupted:
        print(f"interrupted: saved {result.spp} of {spp} spp", file=sys.stderr)
        return 130
    return 0


def _render_with_progress(scene, spp, args, client=None, scene_path=None, params=None):
    from spectrace.passes import render_passes

    with progress_bar(spp, "spp", args.quiet) as on_pass:
        if client is not None:
            from spectrace.cluster import SceneSpec, render_passes_distributed
            from spectrace.passes import scene_spp_per_pass

            bands = args.bands if args.film == "spectral" else None
            spec = SceneSpec.make(scene_path, params, args.variant, bands)
            per_pass = scene_spp_per_pass(scene, spp, args.spp_per_pass)  # the local default
            return render_passes_distributed(client, spec, spp, seed=args.seed,
                                             spp_per_pass=per_pass, on_pass=on_pass)
        return render_passes(scene, spp, seed=args.seed, spp_per_pass=args.spp_per_pass,
                             on_pass=on_pass)


def _write_outputs(result, paths, wavelengths, args, scene_path) -> None:
    from spectrace.images import write_exr, write_png

    header = {
        "spp": int(result.spp),
        "variant": args.variant,
        "seed": int(args.seed),
        "scene": os.path.abspath(scene_path),
        "film": args.film,
    }
    rgb = result.pixels  # a Dr.Jit tensor from the local loop: written by mi.Bitmap
    if wavelengths is not None:
        from spectrace.spectral import write_spectral_exr
        from spectrace.spectral_film import bands_to_linear_srgb, film_to_bands

        bands = film_to_bands(result.image, wavelengths)  # radiance per nm, band-averaged
        rgb = bands_to_linear_srgb(bands, wavelengths)
        write_spectral_exr(paths["spectral"], bands, wavelengths, preview=rgb,
                           attributes=header)
    write_exr(paths["exr"], rgb, header)
    write_png(paths["png"], rgb)
