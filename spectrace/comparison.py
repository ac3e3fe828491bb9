"""Comparing two linear-sRGB images: CIEDE2000 per pixel, statistics and a figure.

Colour differences are CIEDE2000 on the sRGB-encoded images clipped to [0, 1] (what is
displayed), computed by :func:`spectrace.spectral.delta_e_2000`. Used by ``spectrace
compare`` and the notebooks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError
from spectrace.spectral import srgb

#: Rec. 709 / sRGB luminance weights of linear R, G, B (one source: spectral.srgb).
LUMINANCE_WEIGHTS = np.array(srgb.LUMINANCE_WEIGHTS)


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
        raise ParameterError(f"image sizes differ: {a.shape[1]}x{a.shape[0]} and "
                             f"{b.shape[1]}x{b.shape[0]}")
    if not (np.isfinite(a).all() and np.isfinite(b).all()):
        raise ParameterError("an image holds NaN or infinite values")
    display = [encode_srgb(np.clip(x, 0.0, 1.0)) for x in (a, b)]
    return Comparison(a, b, np.asarray(delta_e_2000(*display)))


def write_figure(path, comparison: Comparison, label_a: str, label_b: str) -> None:
    """A | B | CIEDE2000 heat map with a colour bar, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spectrace.images import atomic_path
    from spectrace.spectral import encode_srgb

    stats = comparison.stats
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), constrained_layout=True)
    for ax, img, label in zip(axes, (comparison.a, comparison.b), (label_a, label_b), strict=False):
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
