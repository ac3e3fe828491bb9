"""``spectrace compare``: CIEDE2000 between two images, two scenes, or one scene in two variants.

Inputs are EXR (linear sRGB) or PNG/JPEG (sRGB-encoded) images, or Mitsuba XML scenes,
which are rendered first. Colour differences are CIEDE2000 on the sRGB-encoded images
clipped to [0, 1] (what is displayed), computed by :func:`spectrace.spectral.delta_e_2000`.
Writes a side-by-side PNG (A, B, a CIEDE2000 heat map with its colour bar) and prints the
mean, 95th percentile and maximum CIEDE2000 and the relative difference of mean luminance.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from spectrace import DEFAULT_VARIANT
from spectrace.errors import UserError

#: Rec. 709 / sRGB luminance weights of linear R, G, B (IEC 61966-2-1, Y row of the matrix).
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])
SCENE_SUFFIXES = (".xml",)


@dataclass
class Comparison:
    a: np.ndarray  # (H, W, 3) linear sRGB
    b: np.ndarray
    delta_e: np.ndarray  # (H, W) CIEDE2000

    @property
    def stats(self) -> dict[str, float]:
        ya = float((self.a @ LUMINANCE_WEIGHTS).mean())
        yb = float((self.b @ LUMINANCE_WEIGHTS).mean())
        return {
            "mean": float(self.delta_e.mean()),
            "p95": float(np.percentile(self.delta_e, 95)),
            "max": float(self.delta_e.max()),
            "luminance_rel": (yb - ya) / ya if ya > 0 else float("nan"),
        }


def compare_images(a: np.ndarray, b: np.ndarray) -> Comparison:
    """CIEDE2000 per pixel between two linear-sRGB images of the same size."""
    from spectrace.spectral import delta_e_2000, encode_srgb

    a = np.asarray(a, dtype=np.float64)[..., :3]
    b = np.asarray(b, dtype=np.float64)[..., :3]
    if a.shape != b.shape:
        raise UserError(f"image sizes differ: {a.shape[1]}x{a.shape[0]} and "
                        f"{b.shape[1]}x{b.shape[0]}")
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        raise UserError("an image holds NaN or infinite values")
    display = [encode_srgb(np.clip(x, 0.0, 1.0)) for x in (a, b)]
    return Comparison(a, b, np.asarray(delta_e_2000(*display)))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("a", help="image (EXR/PNG) or scene (XML)")
    parser.add_argument("b", nargs="?", help="image or scene; omit with --variants")
    parser.add_argument("--variants", help="render one scene under two variants, e.g. "
                        "llvm_ad_rgb,llvm_ad_spectral")
    parser.add_argument("--variant", default=DEFAULT_VARIANT,
                        help=f"variant for rendering scenes (default {DEFAULT_VARIANT})")
    parser.add_argument("--spp", type=int, help="samples per pixel for scenes")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", default="out/compare.png",
                        help="side-by-side PNG (default out/compare.png)")


def _render_scene(path: Path, variant: str, args) -> np.ndarray:
    import spectrace
    from spectrace.render import scene_spp
    from spectrace.scene import load_scene, parse_defines, read_scene_xml

    read_scene_xml(path)
    spectrace.set_variant(variant)
    scene = load_scene(path, parse_defines(args.defines))
    result = spectrace.render(scene, spp=args.spp or scene_spp(scene), seed=args.seed)
    return result.image[..., :3]


def _load(path: str, variant: str, args) -> np.ndarray:
    from spectrace.images import read_image

    p = Path(path)
    if p.suffix.lower() in SCENE_SUFFIXES:
        return _render_scene(p, variant, args)
    return read_image(p)


def inputs(args) -> tuple[np.ndarray, np.ndarray, str, str]:
    """The two images to compare and their labels."""
    if args.variants:
        names = [v.strip() for v in args.variants.split(",") if v.strip()]
        if len(names) != 2 or args.b is not None:
            raise UserError("--variants takes exactly two variants and one scene")
        if Path(args.a).suffix.lower() not in SCENE_SUFFIXES:
            raise UserError(f"--variants needs a scene (.xml), got {args.a}")
        return (_render_scene(Path(args.a), names[0], args),
                _render_scene(Path(args.a), names[1], args), names[0], names[1])
    if args.b is None:
        raise UserError("give two images or scenes, or one scene with --variants")
    return (_load(args.a, args.variant, args), _load(args.b, args.variant, args),
            Path(args.a).name, Path(args.b).name)


def write_figure(path, comparison: Comparison, label_a: str, label_b: str) -> None:
    """A | B | CIEDE2000 heat map with a colour bar, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spectrace.images import atomic_path
    from spectrace.spectral import encode_srgb

    stats = comparison.stats
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), constrained_layout=True)
    for ax, img, label in zip(axes, (comparison.a, comparison.b), (label_a, label_b)):
        ax.imshow(encode_srgb(np.clip(img, 0, 1)))
        ax.set_title(label)
        ax.axis("off")
    vmax = max(stats["p95"], 1e-3)
    heat = axes[2].imshow(comparison.delta_e, cmap="magma", vmin=0, vmax=vmax)
    axes[2].set_title(f"CIEDE2000 (mean {stats['mean']:.2f}, max {stats['max']:.1f})")
    axes[2].axis("off")
    fig.colorbar(heat, ax=axes[2], label="ΔE₀₀ (clipped at the 95th percentile)")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)


def run(args) -> int:
    from spectrace.images import check_writable
    from spectrace.render import DEFAULT_SPP_PER_PASS, check_sample_counts

    check_sample_counts(args.spp, DEFAULT_SPP_PER_PASS)
    out = Path(args.output)
    if out.suffix.lower() != ".png":
        raise UserError(f"output {out}: must end in .png")
    check_writable(out)
    a, b, label_a, label_b = inputs(args)
    comparison = compare_images(a, b)
    write_figure(out, comparison, label_a, label_b)
    s = comparison.stats
    print(f"CIEDE2000 {label_a} vs {label_b}: mean {s['mean']:.3f}, 95th percentile "
          f"{s['p95']:.3f}, max {s['max']:.3f}")
    print(f"relative difference of mean luminance (B - A) / A: {s['luminance_rel']:+.4f}")
    print(f"wrote {out}")
    return 0
