"""Discomfort glare: the unified glare rating UGR of CIE 117-1995 from a luminance image.

::

    UGR = 8 log10( 0.25 / L_b  sum_i L_i^2 omega_i / P_i^2 )

(CIE 117-1995 *Discomfort Glare in Interior Lighting*, eq. 1) with L_i the luminance
(cd/m^2) of glare source i, omega_i its solid angle (sr) seen from the eye, P_i Guth's
position index and L_b the background luminance (cd/m^2). As evalglare computes it from
an image (Wienold and Christoffersen 2006, *Energy and Buildings* 38(7); its default
detection): the glare sources are the pixels brighter than :data:`SOURCE_FACTOR` times
the image's mean luminance (solid-angle weighted), or than a luminance ``threshold``
given in cd/m^2; L_b is the solid-angle-weighted mean of the other pixels. The sum runs
over the source pixels, each with its own L, omega and P (for a small uniform source
this is its L^2 omega / P^2; evalglare merges the pixels into sources first and takes
one P per source at its centroid, which differs by the variation of P across a source).

Position index: the closed-form fit of Guth's index (used by evalglare and the
Radiance tools; after Luckiesh and Guth 1949), **not** CIE 117's table (the two differ by
up to about 0.8 UGR away from the vertical plane of the line of sight)::

    P = exp[ (35.2 - 0.31889 tau - 1.22 e^(-2 tau / 9)) 1e-3 sigma
             + (21 + 0.26667 tau - 0.002963 tau^2) 1e-5 sigma^2 ]

with sigma the angle (degrees) between the line of sight and the direction of the source
and tau the angle (degrees) between the vertical plane through the line of sight and
the plane through the line of sight and the source (0 straight above the line of sight,
90 beside it). The line of sight is the ray through the image's centre, the vertical the
scene's +Y (DESIGN.md). Pixels below the horizontal plane of the line of sight, or
90 degrees or more from it, are neither sources nor background (the fit is for sources
above the line of sight, where luminaires are).

The image comes from :func:`spectrace.lighting.luminance.luminance_image` (its pixel
directions and exact solid angles). Luminaires need a size to be seen: Mitsuba ``area``
emitters work; spectrace's point-like lights (``pointlight``, ``spotlight``, ``ieslight``)
have no luminance to see until lights with size exist (DESIGN.md, "Lights with size").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError

__all__ = ["GlareResult", "SOURCE_FACTOR", "guth_position_index", "position_angles", "ugr"]

#: Pixels brighter than this times the image's mean luminance are glare sources
#: (evalglare's default).
SOURCE_FACTOR = 5.0
#: What a UGR of a scene without visible lights means.
NO_SIZE_NOTE = ("the scene's lights have no size (point-like lights are not seen), so the UGR "
                "counts only bright surfaces; give luminaires a size (Mitsuba area emitters)")
#: The scene's up axis.
UP = np.array([0.0, 1.0, 0.0])


def guth_position_index(sigma, tau):
    """Guth's position index P (closed-form fit, see the module docstring) for the
    angles ``sigma`` and ``tau`` in degrees; P = 1 on the line of sight."""
    sigma = np.asarray(sigma, dtype=np.float64)
    tau = np.asarray(tau, dtype=np.float64)
    a = (35.2 - 0.31889 * tau - 1.22 * np.exp(-2.0 * tau / 9.0)) * 1e-3
    b = (21.0 + 0.26667 * tau - 0.002963 * tau**2) * 1e-5
    return np.exp(a * sigma + b * sigma**2)


def check_line_of_sight(forward, up=UP) -> None:
    """ParameterError when the line of sight ``forward`` is vertical."""
    position_angles(np.zeros((1, 3)), forward, up)


def position_angles(directions, forward, up=UP):
    """(sigma, tau, above) of unit ``directions`` (..., 3) for the line of sight
    ``forward``: angles in degrees, and whether each is above its horizontal plane and
    less than 90 degrees from it. ParameterError for a vertical line of sight."""
    s = np.asarray(forward, dtype=np.float64)
    s = s / np.linalg.norm(s)
    right = np.cross(s, up)
    if not np.linalg.norm(right) > 1e-6:
        raise ParameterError("glare: the line of sight is vertical (no vertical plane "
                             "through it to measure the position index from)")
    right /= np.linalg.norm(right)
    up_s = np.cross(right, s)
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d @ right, d @ up_s, d @ s
    sigma = np.degrees(np.arccos(np.clip(z, -1.0, 1.0)))
    tau = np.degrees(np.arctan2(np.abs(x), np.maximum(y, 0.0)))
    return sigma, tau, (y >= 0.0) & (z > 0.0)


@dataclass
class GlareResult:
    """UGR (None without a glare source), the background luminance, the threshold used
    and the sources' total solid angle and mean luminance."""

    UGR: float | None
    L_b: float
    threshold: float
    source_pixels: int
    source_solid_angle: float
    source_luminance: float

    def summary(self) -> str:
        if self.UGR is None:
            return (f"UGR: no glare source (no pixel above {self.threshold:.4g} cd/m^2); "
                    f"L_b {self.L_b:.4g} cd/m^2")
        return (f"UGR {self.UGR:.1f} (CIE 117, Guth index fit): {self.source_pixels} source "
                f"pixels, {self.source_solid_angle:.3g} sr, mean {self.source_luminance:.4g} "
                f"cd/m^2; L_b {self.L_b:.4g} cd/m^2")


def ugr(Y, directions, solid_angle, forward, *, threshold: float | None = None,
        up=UP) -> GlareResult:
    """The UGR of the luminance image ``Y`` (H, W) cd/m^2 whose pixels look along
    ``directions`` (H, W, 3) and subtend ``solid_angle`` (H, W) sr, for the line of sight
    ``forward`` (see the module docstring)."""
    Y = np.asarray(Y, dtype=np.float64)
    omega = np.asarray(solid_angle, dtype=np.float64)
    if threshold is not None and not (np.isfinite(threshold) and threshold > 0.0):
        raise ParameterError(f"glare threshold must be > 0 cd/m^2 (got {threshold!r})")
    sigma, tau, usable = position_angles(directions, forward, up)
    total = omega[usable].sum()
    if not total > 0.0:
        raise ParameterError("glare: no pixel of the image is above the line of sight")
    mean = float((Y * omega)[usable].sum() / total)
    limit = SOURCE_FACTOR * mean if threshold is None else float(threshold)
    source = usable & (Y > limit)
    background = usable & ~source
    w_b = omega[background].sum()
    L_b = float((Y * omega)[background].sum() / w_b) if w_b > 0.0 else 0.0
    if not source.any() or not L_b > 0.0:
        return GlareResult(None, L_b, limit, int(source.sum()), float(omega[source].sum()),
                           0.0)
    P = guth_position_index(sigma[source], tau[source])
    total_glare = float(np.sum(Y[source] ** 2 * omega[source] / P**2))
    value = 8.0 * np.log10(0.25 / L_b * total_glare)
    w_s = float(omega[source].sum())
    return GlareResult(float(value), L_b, limit, int(source.sum()), w_s,
                       float((Y * omega)[source].sum() / w_s))


def has_visible_lights(scene) -> bool:
    """Whether some light of ``scene`` can be seen: not a delta light, and on a shape
    (an area emitter, spectrace's sized lights and ``ieslight`` openings once the scene
    loader has put them on their shapes) or infinitely far (an environment)."""
    import mitsuba as mi

    return any(not mi.has_flag(e.flags(), mi.EmitterFlags.Delta)
               and (e.get_shape() is not None or mi.has_flag(e.flags(), mi.EmitterFlags.Infinite))
               for e in scene.emitters())
