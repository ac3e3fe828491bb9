"""``spectrace compare``: CIEDE2000 between two images, two scenes, one scene in two variants,
or one scene under two settings.

``spectrace compare SCENE.xml -D a=1 --against -D a=2`` renders the scene twice: ``-D``
options before ``--against`` set side A, those after it side B (B starts from A's settings
and overrides them). Comparing a scene with itself under the same settings and variant is
refused: it would report 0 whatever the renderer does.

Inputs are EXR (linear sRGB) or PNG/JPEG (sRGB-encoded) images, or Mitsuba XML scenes,
which are rendered first. Colour differences are CIEDE2000 on the sRGB-encoded images
clipped to [0, 1] (what is displayed), computed by :func:`spectrace.spectral.delta_e_2000`.
Writes a side-by-side PNG (A, B, a CIEDE2000 heat map with its colour bar) and prints the
mean, 95th percentile and maximum CIEDE2000 and the relative difference of mean luminance.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from spectrace import DEFAULT_VARIANT
from spectrace.commands import (
    add_display_options,
    add_verbose,
    display_settings,
    parse_defines,
)
from spectrace.errors import UsageError

SCENE_SUFFIXES = (".xml",)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("a", help="image (EXR/PNG) or scene (XML)")
    parser.add_argument("b", nargs="?", help="image or scene; omit with --variants")
    parser.add_argument("--variants", help="render one scene under two variants, e.g. "
                        "llvm_ad_rgb,llvm_ad_spectral")
    parser.add_argument("--variant", default=DEFAULT_VARIANT,
                        help=f"variant for rendering scenes (default {DEFAULT_VARIANT})")
    parser.add_argument("--spp", type=int, help="samples per pixel for scenes")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-D", dest="defines", action=_SideDefine, default=[], metavar="NAME=VALUE",
                        help="scene parameter; after --against it sets side B only")
    parser.add_argument("--against", action="store_true",
                        help="the -D options that follow set the second side (B) of one scene")
    parser.add_argument("-o", "--output", default="out/compare.png",
                        help="side-by-side PNG (default out/compare.png)")
    add_verbose(parser)
    add_display_options(parser, views=False)
    parser.add_argument("--view", default="standard", choices=("standard", "aces", "neutral"),
                        help="view transform of both sides before the comparison (default "
                        "standard: the clip)")


class _SideDefine(argparse.Action):
    """``-D``: appended to side A's list, or to side B's once ``--against`` was given
    (argparse runs actions in command-line order)."""

    def __call__(self, parser, namespace, values, option_string=None):
        name = "defines_b" if getattr(namespace, "against", False) else self.dest
        setattr(namespace, name, [*(getattr(namespace, name, None) or []), values])


def _render_scene(path: Path, variant: str, args, defines=None) -> np.ndarray:
    import spectrace
    from spectrace.passes import scene_spp
    from spectrace.scene import load_scene, read_scene_xml

    read_scene_xml(path)
    spectrace.set_variant(variant)
    params = parse_defines(args.defines if defines is None else defines)
    scene = load_scene(path, params)
    result = spectrace.render(scene, spp=args.spp or scene_spp(scene), seed=args.seed)
    from spectrace.images import as_rgb

    return as_rgb(result.image)  # a mono film's luminance as grey


def _load(path: str, variant: str, args) -> np.ndarray:
    from spectrace.images import read_image

    p = Path(path)
    if p.suffix.lower() in SCENE_SUFFIXES:
        return _render_scene(p, variant, args)
    return read_image(p)


def inputs(args) -> tuple[np.ndarray, np.ndarray, str, str]:
    """The two images to compare and their labels."""

    if args.against:
        if args.variants or args.b is not None:
            raise UsageError("--against compares two settings of one scene: give one scene, "
                             "no second input and no --variants")
        if Path(args.a).suffix.lower() not in SCENE_SUFFIXES:
            raise UsageError(f"--against needs a scene (.xml), got {args.a}")
        side_a = parse_defines(args.defines)
        side_b = {**side_a, **parse_defines(getattr(args, "defines_b", None))}
        if side_a == side_b:
            raise UsageError("--against: side B sets nothing new (give -D name=value after "
                             "--against): nothing to compare")
        label = Path(args.a).name
        changed = " ".join(f"{k}={v}" for k, v in side_b.items() if side_a.get(k) != v)
        before = " ".join(f"{k}={side_a[k]}" for k in side_b if k in side_a and
                          side_a[k] != side_b[k])
        return (_render_scene(Path(args.a), args.variant, args, args.defines),
                _render_scene(Path(args.a), args.variant, args,
                              [f"{k}={v}" for k, v in side_b.items()]),
                f"{label} {before}".strip(), f"{label} {changed}")
    if args.variants:
        names = [v.strip() for v in args.variants.split(",") if v.strip()]
        if len(names) != 2 or args.b is not None:
            raise UsageError("--variants takes exactly two variants and one scene")
        if names[0] == names[1]:
            raise UsageError(f"--variants: both sides are {names[0]}: nothing to compare")
        if Path(args.a).suffix.lower() not in SCENE_SUFFIXES:
            raise UsageError(f"--variants needs a scene (.xml), got {args.a}")
        return (_render_scene(Path(args.a), names[0], args),
                _render_scene(Path(args.a), names[1], args), names[0], names[1])
    if args.b is None:
        raise UsageError("give two images or scenes, one scene with --variants, or one scene "
                         "with -D ... --against -D ...")
    if (Path(args.a).suffix.lower() in SCENE_SUFFIXES and Path(args.a).resolve() ==
            Path(args.b).resolve()):
        raise UsageError(f"{args.a} against itself with the same settings and variant: nothing "
                         "to compare (use -D ... --against -D ..., or --variants)")
    return (_load(args.a, args.variant, args), _load(args.b, args.variant, args),
            Path(args.a).name, Path(args.b).name)


def run(args) -> int:
    from spectrace.images import check_writable
    from spectrace.passes import check_sample_counts

    check_sample_counts(args.spp, None, names=("--spp", "--spp-per-pass"))
    out = Path(args.output)
    if out.suffix.lower() != ".png":
        raise UsageError(f"output {out}: must end in .png")
    settings = display_settings(args)
    check_writable(out)
    a, b, label_a, label_b = inputs(args)
    from spectrace.comparison import compare_images, write_figure

    if not settings.is_default:  # exposure, white balance, view: the same for both sides
        from spectrace.display import develop_pair

        a, b, notes = develop_pair(a, b, settings)
        for note in notes:
            print(note)

    comparison = compare_images(a, b)
    write_figure(out, comparison, label_a, label_b)
    s = comparison.stats
    print(f"CIEDE2000 {label_a} vs {label_b}: mean {s['mean']:.3f}, 95th percentile "
          f"{s['p95']:.3f}, max {s['max']:.3f}")
    print(f"relative difference of mean luminance (B - A) / A: {s['luminance_rel']:+.4f}")
    print(f"wrote {out}")
    return 0
