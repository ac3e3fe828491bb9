"""White-furnace measurement: directional albedo of a BSDF against the incident angle.

The directional albedo of a BSDF for light arriving from wi is

    a(wi) = integral over the sphere of f(wi, wo) |cos(theta_o)| dwo,

the fraction of the energy arriving from wi that the surface scatters (what a white
furnace, a uniform environment of radiance 1, shows as the surface's brightness). An
energy-conserving BSDF has a(wi) <= 1 everywhere. :func:`directional_albedo` estimates
it as the mean of the BSDF's sample weights f |cos(theta_o)| / pdf, which also counts
delta components (``plastic``'s mirror coat); the standard error comes with it.

In RGB variants the albedo is given per channel (R, G, B); in spectral variants the
wavelengths are drawn uniformly in [360, 830] nm and the albedo is their mean (one
channel). The BSDF comes as a Mitsuba dict, an XML string (``<bsdf type=...>``) or an
XML file, under the active variant.

Command line: ``spectrace furnace BSDF [-p name=value ...] [--angles 0,30,60]``, where
BSDF is a plugin name (parameters from ``-p``), an XML string or an XML file, e.g.
``spectrace furnace phong -p exponent=2 -p specular_reflectance=1
-p diffuse_reflectance=0`` shows the classic Phong lobe reflecting pi/2 at normal
incidence.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from spectrace.errors import ParameterError, SpectraceError

#: Incident angles (degrees from the normal) tabulated by default.
DEFAULT_ANGLES = (0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 80.0, 85.0, 89.0)
#: Samples per angle by default (standard error ~ 1e-3 for the lobes of interest).
DEFAULT_SAMPLES = 1 << 18
#: Wavelength range sampled in spectral variants (nm).
WAVELENGTH_RANGE = (360.0, 830.0)
#: An albedo counts as "> 1" in the table when it exceeds 1 by this many standard errors.
SIGMAS = 4.0


@dataclass
class FurnaceResult:
    """Directional albedo per incident angle: ``albedo[i, c]`` for ``angles[i]`` (degrees)."""

    angles: np.ndarray
    albedo: np.ndarray
    stderr: np.ndarray
    channels: tuple[str, ...]

    def exceeds_one(self) -> np.ndarray:
        """Per angle: whether some channel's albedo is above 1 beyond SIGMAS standard errors."""
        return np.any(self.albedo - SIGMAS * self.stderr > 1.0, axis=1)

    def table(self) -> str:
        head = ["angle"] + [f"albedo {c}" for c in self.channels] + ["std.err", ""]
        rows = [head]
        for i, angle in enumerate(self.angles):
            rows.append(
                [f"{angle:g}"]
                + [f"{a:.4f}" for a in self.albedo[i]]
                + [f"{self.stderr[i].max():.1e}",
                   "> 1 (gains energy)" if self.exceeds_one()[i] else ""]
            )
        widths = [max(len(r[j]) for r in rows) for j in range(len(head))]
        return "\n".join("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)).rstrip()
                         for r in rows)


def load_bsdf(spec):
    """A BSDF from a Mitsuba dict, an XML string or an XML file (active variant).

    Raises :class:`~spectrace.errors.ParameterError` (a bad parameter) or
    :class:`~spectrace.errors.FileFormatError` (Mitsuba's own error) in one line.
    """
    import mitsuba as mi

    try:
        if isinstance(spec, dict):
            bsdf = mi.load_dict(spec)
        elif isinstance(spec, str) and spec.lstrip().startswith("<"):
            xml = spec if "version=" in spec else spec.replace("<bsdf", '<bsdf version="3.0.0"', 1)
            bsdf = mi.load_string(xml)
        elif isinstance(spec, (str, Path)) and Path(spec).is_file():
            bsdf = mi.load_file(str(spec))
        else:
            raise ParameterError(f"not a BSDF dict, XML string or XML file: {spec!r}")
    except SpectraceError:
        raise
    except Exception as e:
        from spectrace.scene import load_error

        raise load_error(e) from None
    if not isinstance(bsdf, mi.BSDF):
        raise ParameterError(f"{spec!r} does not describe a BSDF (got {type(bsdf).__name__})")
    return bsdf


def directional_albedo(bsdf, angles=DEFAULT_ANGLES, samples: int = DEFAULT_SAMPLES,
                       seed: int = 0) -> FurnaceResult:
    """Estimate the directional albedo of ``bsdf`` (a BSDF object, dict, XML string or file).

    ``angles``: incident angles in degrees from the normal; ``samples`` per angle.
    """
    import drjit as dr
    import mitsuba as mi

    if not isinstance(bsdf, mi.BSDF):
        bsdf = load_bsdf(bsdf)
    angles = np.asarray(angles, dtype=float).ravel()
    if angles.size == 0 or np.any((angles < 0) | (angles > 90)) or samples < 1:
        raise ParameterError("angles must lie in [0, 90] degrees and samples must be >= 1")
    from spectrace.memory import check_furnace

    check_furnace(int(samples), angles.size)
    n = angles.size * samples
    theta = np.repeat(np.radians(angles), samples)

    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(np.sin(theta), np.zeros(n), np.cos(theta))
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(0.5, 0.5)
    rng = mi.PCG32(size=n, initstate=mi.UInt64(seed) + 0x853C49E6748FEA9B)
    spectral = mi.is_spectral
    if spectral:
        lo, hi = WAVELENGTH_RANGE
        si.wavelengths = lo + (hi - lo) * mi.sample_shifted(rng.next_float32())
    bs, weight = bsdf.sample(mi.BSDFContext(), si, rng.next_float32(),
                             mi.Point2f(rng.next_float32(), rng.next_float32()))
    w = np.array(mi.unpolarized_spectrum(weight), dtype=np.float64)  # (channels, n)
    if spectral:
        w = w.mean(axis=0, keepdims=True)
        channels = ("mean 360-830 nm",)
    else:
        channels = ("R", "G", "B")[: w.shape[0]] if w.shape[0] > 1 else ("mono",)
    w = w.T.reshape(angles.size, samples, -1)
    albedo = w.mean(axis=1)
    stderr = w.std(axis=1, ddof=1) / np.sqrt(samples) if samples > 1 else np.zeros_like(albedo)
    return FurnaceResult(angles, albedo, stderr, channels)
