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

from spectrace.commands import (
    EXIT_INTERRUPTED,
    add_display_options,
    add_render_options,
    check_render_options,
    display_settings,
    parse_defines,
    progress_bar,
    write_picture,
)
from spectrace.errors import UsageError
from spectrace.memory import check_pass
from spectrace.passes import scene_spp, scene_spp_per_pass

FILMS = ("rgb", "spectral")
DEFAULT_BANDS = 16


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", nargs="+", help="Mitsuba XML scene file(s), rendered in one "
                        "process (plugins registered once, kernels reused)")
    parser.add_argument("-o", "--output", help="output EXR (default: out/<scene>.exr), or a "
                        "folder (FOLDER/) for <scene>.exr there, which several scenes need; "
                        "an sRGB PNG is written beside each EXR (-o OUT.png: the PNG, and the "
                        "EXR beside it)")
    add_render_options(parser)
    parser.add_argument("-t", "--threads", type=int, metavar="N",
                        help="render with N threads (default: one per core)")
    parser.add_argument("--noise", type=float, metavar="TARGET",
                        help="render until the estimated relative error of the image (from "
                        "the spread between passes) is below TARGET, e.g. 0.01; --spp is then "
                        "the most it renders")
    parser.add_argument("--denoise", action="store_true",
                        help="also write OUT.denoised.exr (Intel Open Image Denoise with albedo "
                        "and normal buffers; needs pyoidn) and make the PNG from it; OUT.exr "
                        "stays the noisy render")
    parser.add_argument("--time", type=float, metavar="SECONDS",
                        help="stop at the first pass that ends after SECONDS; --spp is then "
                        "the most it renders")
    parser.add_argument("--film", choices=FILMS, default="rgb",
                        help="rgb: the scene's film; spectral: N bands, also OUT.spectral.exr")
    parser.add_argument("--bands", type=int, default=None,
                        help=f"spectral bands over 400-700 nm with --film spectral "
                        f"(default {DEFAULT_BANDS})")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    groups = parser.add_mutually_exclusive_group()
    groups.add_argument("--light-groups", action="store_true",
                        help="also write one layer per emitter (<id>.R/G/B in the EXR; "
                        "the scene's integrator must be path, direct or local; "
                        "local adds a layer 'ambient')")
    groups.add_argument("--light-group", action="append", metavar="NAME=ID1,ID2",
                        dest="light_group", help="a layer NAME of these emitters (repeat "
                        "the option for more; emitters in no group form the group 'rest')")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="render the passes on a local Dask cluster of N worker processes")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="render the passes on the Dask cluster of this scheduler "
                       "(tcp://host:8786); workers read the scene at the same path")
    add_display_options(parser)


def _is_folder(output: str) -> bool:
    return output.endswith(("/", os.sep)) or Path(output).is_dir()


def scene_outputs(scenes: list[Path], output: str | None, film: str,
                  denoise: bool = False, display_exr: bool = False) -> list[dict[str, Path]]:
    """The files of each scene: -o OUT.exr for one scene, -o FOLDER/ for any number."""
    if output is not None and _is_folder(output):
        outs = [str(Path(output) / f"{s.stem}.exr") for s in scenes]
    elif output is not None and len(scenes) > 1:
        raise UsageError(f"-o {output}: with {len(scenes)} scenes, -o must be a folder "
                         "(end it with /)")
    else:
        outs = [output] * len(scenes)
    paths = [output_paths(s, o, film, denoise, display_exr)
             for s, o in zip(scenes, outs, strict=True)]
    seen: dict[Path, Path] = {}
    for scene, p in zip(scenes, paths, strict=True):
        if p["exr"] in seen:
            raise UsageError(f"scenes {seen[p['exr']]} and {scene} would both write {p['exr']}")
        seen[p["exr"]] = scene
    return paths


def output_paths(scene: Path, output: str | None, film: str,
                 denoise: bool = False, display_exr: bool = False) -> dict[str, Path]:
    """The files a render writes: EXR, PNG beside it, and the spectral EXR for that film."""
    exr = Path(output) if output else Path("out") / f"{scene.stem}.exr"
    png = exr.with_suffix(".png")
    if exr.suffix.lower() == ".png":
        exr, png = exr.with_suffix(".exr"), exr
    if exr.suffix.lower() != ".exr":
        raise UsageError(f"output {exr}: must end in .exr or .png (the other is written "
                         "beside it)")
    paths = {"exr": exr, "png": png}
    if denoise:
        paths["denoised"] = exr.with_suffix(".denoised.exr")
    if display_exr:
        paths["display"] = exr.with_suffix(".display.exr")
    if film == "spectral":
        paths["spectral"] = exr.with_suffix(".spectral.exr")
    return paths


def run(args) -> int:
    import time

    from spectrace.images import check_writable

    scene_paths = [Path(s) for s in args.scene]
    check_render_options(args)  # before loading anything
    if args.film == "spectral":
        if args.bands is None:
            args.bands = DEFAULT_BANDS
        if args.bands < 1:
            raise UsageError(f"--bands must be a positive integer (got {args.bands})")
        if "spectral" not in args.variant:
            raise UsageError(f"--film spectral needs a spectral variant (got {args.variant})")
    elif args.bands is not None:
        raise UsageError("--bands applies only with --film spectral")
    light_groups = _light_groups(args)
    if args.workers is not None and args.workers < 1:
        raise UsageError(f"--workers must be a positive integer (got {args.workers})")
    _check_run_options(args)
    display_settings(args)  # a bad display option costs no render
    if args.workers is not None and not args.scheduler:
        from spectrace.cluster import start_forkserver

        start_forkserver()  # it imports Dask while this process loads the scenes
    if args.denoise:
        if args.film == "spectral":
            raise UsageError("--denoise works with --film rgb")
        from spectrace.denoise import check_denoiser
        from spectrace.errors import ParameterError

        try:
            check_denoiser()
        except ParameterError as e:
            raise UsageError(f"--denoise: {e}") from None
    all_paths = scene_outputs(scene_paths, args.output, args.film, args.denoise,
                              args.display_exr)

    from spectrace.scene import load_scene, read_scene_xml

    params = parse_defines(args.defines)
    roots = [read_scene_xml(p) for p in scene_paths]
    import spectrace

    spectrace.set_variant(args.variant, lazy=True)  # plugins registered as scenes load
    loaded = []  # every scene loads before anything renders: a bad one costs no output
    for scene_path, root in zip(scene_paths, roots, strict=True):
        wavelengths = None
        if args.film == "spectral" and light_groups is not None:
            # spectral layers on the scene's own film (lightgroups' band_wavelengths)
            from spectrace.spectral_film import band_centres

            wavelengths = band_centres(args.bands)
            scene = load_scene(scene_path, params)
        elif args.film == "spectral":
            from spectrace.spectral_film import replace_film

            wavelengths = replace_film(root, bands=args.bands)
            scene = load_scene(scene_path, params, root=root)
        else:
            scene = load_scene(scene_path, params)
        check_pass(scene, scene_spp_per_pass(scene, args.spp or scene_spp(scene),
                                             args.spp_per_pass), name="--spp-per-pass")
        integrator = None
        if light_groups is not None:  # a bad group costs no render
            from spectrace.lightgroups import integrator_for

            integrator = integrator_for(scene, light_groups, band_wavelengths=wavelengths)
        loaded.append((scene, wavelengths, _photometric(root), integrator))
    start = time.perf_counter()
    with contextlib.ExitStack() as stack:
        client = None
        if args.workers is not None or args.scheduler:  # before any folder is made
            from spectrace.cluster import connect

            client = stack.enter_context(connect(args.workers, args.scheduler,
                                                 variant=args.variant))
        if args.threads is not None:
            stack.enter_context(_thread_count(args.threads))
        for paths in all_paths:  # before rendering: a bad output path costs no render time
            for p in paths.values():
                check_writable(p)
        for scene_path, (scene, wavelengths, photometric, integrator), paths in zip(
                scene_paths, loaded, all_paths, strict=True):
            settings = display_settings(args, photometric)
            code = _render_one(scene_path, scene, wavelengths, paths, params, args, client,
                               settings, integrator)
            if code:
                return code
    if len(scene_paths) > 1:
        print(f"total: {len(scene_paths)} scenes in {time.perf_counter() - start:.2f} s")
    return 0


@contextlib.contextmanager
def _thread_count(threads: int):
    """Dr.Jit's pool at ``threads`` threads while the scenes render, as it was after (a
    command called in-process leaves no pool of 1 behind). Set after the scenes load:
    Mitsuba's bundled OpenEXR reads (an ``envmap``'s image) and writes on that pool and
    hangs in a pool of one thread (``spectrace.images`` writes with at least 2)."""
    import drjit as dr

    before = dr.thread_count()
    dr.set_thread_count(threads)
    try:
        yield
    finally:
        dr.set_thread_count(before)


def _check_run_options(args) -> None:
    """--threads, --noise and --time: positive (UsageError naming the flag)."""
    import math

    if args.threads is not None and args.threads < 1:
        raise UsageError(f"-t/--threads must be a positive integer (got {args.threads})")
    if args.noise is not None and not 0 < args.noise < 1:  # NaN fails too
        raise UsageError(f"--noise must be a relative error between 0 and 1, exclusive "
                         f"(got {args.noise})")
    if args.time is not None and not (0 < args.time and math.isfinite(args.time)):
        raise UsageError(f"--time must be a positive number of seconds (got {args.time})")


def _photometric(root) -> bool:
    from spectrace.display_options import photometric_scene

    return photometric_scene(root)


def _render_one(scene_path, scene, wavelengths, paths, params, args, client, settings,
                integrator=None) -> int:
    until_clean = args.noise is not None or args.time is not None
    if until_clean:
        from spectrace.passes import UNTIL_CLEAN_MAX_SPP

        spp = args.spp or UNTIL_CLEAN_MAX_SPP
    else:
        spp = args.spp or scene_spp(scene)
    where = ""
    if client is not None:
        where = f", {len(client.scheduler_info(n_workers=-1)['workers'])} workers"
    goal = f"{spp} spp"
    if until_clean:
        stops = [f"error < {args.noise:g}"] if args.noise is not None else []
        stops += [f"{args.time:g} s"] if args.time is not None else []
        goal = f"until {' or '.join(stops)} (at most {spp} spp)"
    print(f"rendering {scene_path.name}: {goal}, {args.variant}, seed {args.seed}{where}",
          file=sys.stderr, flush=True)
    result = _render_with_progress(scene, spp, args, client, scene_path, params, integrator)
    if result.spp == 0:
        print("interrupted before the first pass finished: nothing written", file=sys.stderr)
        return EXIT_INTERRUPTED
    if result.nonfinite:
        print(f"warning: {result.nonfinite} pixel values were NaN or infinite and were set to 0",
              file=sys.stderr)
    notes = _write_outputs(result, paths, wavelengths, args, scene_path, settings, scene,
                           integrator)
    rate = result.samples_per_second
    passes = f"{result.passes} pass{'' if result.passes == 1 else 'es'}"
    print(f"{scene_path.name}: {result.spp} spp in {passes}, {result.seconds:.2f} s, "
          f"{rate / 1e6:.2f} M samples/s -> {paths['exr']}", flush=True)
    if "denoised" in paths:
        print(f"denoised (Open Image Denoise) -> {paths['denoised']}, {paths['png']}")
    if getattr(result, "noise", None) is not None:
        estimate = f"{result.noise:.4f}" if result.noise < float("inf") else "unknown (1 pass)"
        print(f"estimated relative error {estimate}, stopped by {result.stopped_by}")
    for note in notes:
        print(note)
    if result.interrupted:
        print(f"interrupted: saved {result.spp} of {spp} spp", file=sys.stderr)
        return EXIT_INTERRUPTED
    return 0


def _render_with_progress(scene, spp, args, client=None, scene_path=None, params=None,
                          integrator=None):
    from spectrace.passes import render_passes

    with progress_bar(spp, "spp", args.quiet) as on_pass:
        groups = _light_groups(args)
        if groups is None and type(scene.integrator()).__name__ == "LightGroups":
            groups = True  # the scene's own lightgroups integrator: write its layers
        until_clean = {}
        if args.noise is not None or args.time is not None:
            until_clean = {"noise": args.noise, "time_limit": args.time,
                           "on_noise": lambda e: on_pass.describe(f"error {e:.4f}")}
        if client is not None:
            from spectrace.cluster import SceneSpec, render_passes_distributed
            from spectrace.passes import scene_spp_per_pass

            bands = args.bands if args.film == "spectral" else None
            spec = SceneSpec.make(scene_path, params, args.variant, bands, groups)
            per_pass = scene_spp_per_pass(scene, spp, args.spp_per_pass)  # the local default
            result = render_passes_distributed(client, spec, spp, seed=args.seed,
                                               spp_per_pass=per_pass, on_pass=on_pass,
                                               **until_clean)
            if groups is not None:  # the names of the layers, as the workers made them
                from spectrace.lightgroups import integrator_for

                result.light_groups = list((integrator or integrator_for(scene, True)).names)
            return result
        return render_passes(scene, spp, seed=args.seed, spp_per_pass=args.spp_per_pass,
                             on_pass=on_pass, light_groups=groups, integrator=integrator,
                             **until_clean)


def _write_outputs(result, paths, wavelengths, args, scene_path, settings, scene=None,
                   integrator=None) -> tuple[str, ...]:
    """Write the EXR (and the spectral EXR, the denoised EXR, or the light-group layers),
    then the PNG through the display pipeline; returns the pipeline's notes (the exposure
    used)."""
    from spectrace.images import write_exr

    header = {
        "spp": int(result.spp),
        "variant": args.variant,
        "seed": int(args.seed),
        "scene": os.path.abspath(scene_path),
        "film": args.film,
    }
    if getattr(result, "noise", None) is not None and result.noise < float("inf"):
        header["noise"] = float(result.noise)  # the estimated relative error
    rgb = result.pixels  # a Dr.Jit tensor from the local loop: written by mi.Bitmap
    if result.light_groups is not None:
        rgb = _write_layers(result, paths, wavelengths, header, scene, integrator)
    else:
        if wavelengths is not None:
            from spectrace.spectral import write_spectral_exr
            from spectrace.spectral_film import bands_to_linear_srgb, film_to_bands

            bands = film_to_bands(result.image, wavelengths)  # radiance per nm, band-averaged
            rgb = bands_to_linear_srgb(bands, wavelengths)
            write_spectral_exr(paths["spectral"], bands, wavelengths, preview=rgb,
                               attributes=header)
        write_exr(paths["exr"], rgb, header)
    if "denoised" in paths:  # a picture: the noisy EXR above is the measurement
        import numpy as np

        from spectrace.denoise import denoise_image, render_features

        albedo, normal = render_features(scene, result.spp, seed=args.seed)
        rgb = denoise_image(np.asarray(rgb, np.float32), albedo, normal)
        write_exr(paths["denoised"], rgb, {**header, "denoiser": "Open Image Denoise RT"})
    return write_picture(paths["png"], rgb, settings, paths.get("display"))


def _write_layers(result, paths, wavelengths, header, scene, integrator):
    """The EXR with light-group layers (and with --film spectral the spectral one, whose
    bands also make the RGB beauty and layers); returns the beauty for the PNG."""
    from spectrace import lightgroups

    names = result.light_groups
    if wavelengths is None:
        rgb, layers = lightgroups.split(result.image, names)
    else:
        from spectrace.spectral_film import bands_to_linear_srgb, film_to_bands

        _, raw = lightgroups.split(result.image, names, per_layer=len(wavelengths))
        bands = {g: film_to_bands(v, wavelengths) for g, v in raw.items()}
        total = sum(bands.values())
        layers = {g: bands_to_linear_srgb(v, wavelengths) for g, v in bands.items()}
        rgb = bands_to_linear_srgb(total, wavelengths)
        spectra = lightgroups.group_spectra(scene, integrator.groups, wavelengths)
        lightgroups.write_spectral_layers_exr(paths["spectral"], total, bands, wavelengths,
                                              rgb, spectra, header)
    lightgroups.write_layers_exr(paths["exr"], rgb, layers, header)
    return rgb


def _light_groups(args):
    """``light_groups`` of :func:`spectrace.render` from --light-groups / --light-group."""
    if args.light_groups:
        return True
    return args.light_group
