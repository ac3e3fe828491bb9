"""The daylight factor: indoor illuminance as a share of the unobstructed sky's.

DF = E_in / E_out x 100 %, with E_in the illuminance at a point inside and E_out the
horizontal illuminance that the same sky gives on an unobstructed horizontal plane, the
direct sun excluded (CIE S 017:2020, ILV 17-29-190 "daylight factor"). E_out is not
rendered: the scene's ``ciesky`` knows it analytically (7 pi L_z / 9 for the CIE overcast
sky, the sky for which the daylight factor is defined; pi L_z for the uniform sky; a
numerical integral of the standard's formula for the 15 general skies).

EN 17037:2018+A1:2021 (Daylight in buildings, clause 5.1 and annex A, tables A.1 and A.3)
asks of a room lit through vertical or inclined openings that a target illuminance E_T be
exceeded on 50 % of the reference plane and a minimum target E_TM on 95 % of it, for half
of the daylight hours; with daylight factors the targets are D = E / E_v,d,med x 100 %,
E_v,d,med the median external diffuse horizontal illuminance of the site (table A.3, e.g.
about 15 000 lx in much of central Europe):

=========  ======================  ======================
level      E_T on 50 % of plane    E_TM on 95 % of plane
=========  ======================  ======================
minimum    300 lx                  100 lx
medium     500 lx                  300 lx
high       750 lx                  500 lx
=========  ======================  ======================

Sources: CEN (2018), EN 17037:2018+A1:2021 *Daylight in buildings*; CIE (2020), CIE S
017:2020 *ILV*; Moon, Spencer (1942) (the overcast sky); Tregenza, Wilson (2011),
*Daylighting*, ch. 8.
"""

from __future__ import annotations

import numpy as np

from spectrace.errors import ParameterError

#: EN 17037 table A.1: level -> (E_T on 50 % of the plane, E_TM on 95 % of it), in lux.
EN17037_LEVELS = {"minimum": (300.0, 100.0), "medium": (500.0, 300.0), "high": (750.0, 500.0)}
#: Shares of the reference plane that must exceed E_T and E_TM.
EN17037_SHARES = (0.50, 0.95)


def sky_horizontal_illuminance(scene) -> float:
    """E_out (lux): the diffuse horizontal illuminance of the scene's ``ciesky``, from its
    analytic distribution (no rendering). Raises ``ParameterError`` when the scene has none."""
    return float(find_sky(scene).horizontal_illuminance)


def find_sky(scene):
    """The scene's ``ciesky`` emitter (the Python object), or ``ParameterError``."""
    for emitter in scene.emitters():
        if type(emitter).__name__ == "CIESky":
            return emitter
    raise ParameterError("the scene has no ciesky emitter: a daylight factor needs the sky's "
                         "unobstructed horizontal illuminance")


def sky_component(scene, points, normal=(0.0, 1.0, 0.0), spp: int = 256, seed: int = 0):
    """Illuminance (lux) that the scene's ``ciesky`` gives straight through the openings
    at ``points`` (N, 3) on surfaces of unit ``normal``: the sky component of the daylight
    factor (no light reflected by the scene), and its standard error, two (N,) arrays.

    Monte Carlo with ``spp`` directions per point drawn by the sky's own importance
    sampling and Mitsuba's shadow rays (``scene.ray_test``). The luminous conversion is
    spectrace's (``spectrace help luminous``): K_m integral V E dlambda over wavelengths
    drawn uniformly in spectral variants, K_m Y(E) integral V in RGB and mono ones.
    """
    import drjit as dr
    import mitsuba as mi

    from spectrace.plugins.arrays import host_array
    from spectrace.plugins.emitters import luminous

    if spp < 2:
        raise ParameterError(f"spp must be >= 2 (got {spp})")
    sky = find_sky(scene)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n_points = points.shape[0]
    n = n_points * spp
    rng = np.random.default_rng(seed)
    it = dr.zeros(mi.SurfaceInteraction3f, n)
    p = np.repeat(points, spp, axis=0).astype(np.float32)
    it.p = mi.Point3f(*(mi.Float(p[:, i]) for i in range(3)))
    normal = np.asarray(normal, dtype=np.float64) / np.linalg.norm(normal)
    it.n = mi.Normal3f(*(float(c) for c in normal))
    it.sh_frame = mi.Frame3f(it.n)
    weight = None
    if mi.is_spectral:
        low, high = luminous.GRID_NM
        u = rng.random((len(it.wavelengths), n)).astype(np.float32)
        it.wavelengths = mi.UnpolarizedSpectrum(*(low + (high - low)
                                                  * mi.Float(host_array(row)) for row in u))
        V = luminous.photopic_spectrum().eval(it)
        weight = mi.unpolarized_spectrum(V) * (high - low)
    u = rng.random((n, 2)).astype(np.float32)
    ds, value = sky.sample_direction(it, mi.Point2f(mi.Float(u[:, 0]), mi.Float(u[:, 1])))
    cos = dr.dot(ds.d, it.n)
    visible = (cos > 0.0) & ~scene.ray_test(it.spawn_ray_to(ds.p))
    E = dr.select(visible, mi.unpolarized_spectrum(value) * cos, 0.0)
    lux = np.array(luminous.illuminance_lux(E, weight), dtype=np.float64).reshape(n_points, spp)
    return lux.mean(axis=1), lux.std(axis=1, ddof=1) / np.sqrt(spp)


def fisheye_luminance(sky, size: int = 129):
    """Luminance (cd/m^2) of a ``ciesky`` emitter as an equidistant fisheye image (size x
    size) seen from below: the zenith at the centre, the horizon on the circle, north at
    the top and east on the left; NaN outside the circle. Evaluated by the emitter itself."""
    import drjit as dr
    import mitsuba as mi

    from spectrace.plugins.arrays import host_array

    c = (np.arange(size) + 0.5) / size * 2 - 1
    s, t = np.meshgrid(c, -c)
    r = np.hypot(s, t)
    zenith = np.clip(r, 0.0, 1.0) * np.pi / 2
    azimuth = np.arctan2(-s, t)
    east, north, up = (np.array(dr.slice(v), dtype=np.float64) for v in
                       (sky.east, sky.north, sky.up))
    d = (np.sin(zenith)[..., None] * (np.sin(azimuth)[..., None] * east
                                      + np.cos(azimuth)[..., None] * north)
         + np.cos(zenith)[..., None] * up).reshape(-1, 3).astype(np.float32)
    value = sky.relative_luminance(mi.Vector3f(*(mi.Float(host_array(d[:, i]))
                                                 for i in range(3))))
    L = sky.zenith_luminance * np.array(value, dtype=np.float64).reshape(size, size)
    return np.where(r <= 1.0, L, np.nan)


def daylight_factor(E_inside, E_outside: float):
    """DF in percent: 100 E_inside / E_outside (any array shape)."""
    if not E_outside > 0:
        raise ParameterError(f"E_outside must be > 0 lux (got {E_outside:g})")
    return 100.0 * np.asarray(E_inside, dtype=np.float64) / E_outside


def en17037_targets(median_external_illuminance: float) -> dict[str, tuple[float, float]]:
    """Daylight-factor targets (D_T, D_TM) in percent per EN 17037 level for a site of
    median external diffuse illuminance E_v,d,med (lux): D = E / E_v,d,med x 100."""
    if not median_external_illuminance > 0:
        raise ParameterError("median_external_illuminance must be > 0 lux "
                             f"(got {median_external_illuminance:g})")
    return {level: (100.0 * e_t / median_external_illuminance,
                    100.0 * e_tm / median_external_illuminance)
            for level, (e_t, e_tm) in EN17037_LEVELS.items()}


def statistics(df, targets=(), median_external_illuminance: float | None = None) -> dict:
    """Mean, median, minimum and maximum of the daylight factors ``df`` (percent; NaNs are
    points outside the plane and ignored), the uniformity DF_min / DF_mean, the share of
    points at or above each DF in ``targets`` and, given E_v,d,med, which EN 17037 levels
    the plane meets (D_T on 50 % and D_TM on 95 % of the points)."""
    values = np.asarray(df, dtype=np.float64).ravel()
    values = values[np.isfinite(values)]
    if values.size == 0:
        raise ParameterError("df holds no finite daylight factor")
    mean = float(np.mean(values))
    result = {"mean": mean, "median": float(np.median(values)), "min": float(values.min()),
              "max": float(values.max()), "uniformity": float(values.min()) / mean if mean
              else float("nan"), "points": int(values.size),
              "share_above": {float(t): float(np.mean(values >= t)) for t in targets}}
    if median_external_illuminance is not None:
        levels = {}
        for level, (d_t, d_tm) in en17037_targets(median_external_illuminance).items():
            share_t, share_tm = np.mean(values >= d_t), np.mean(values >= d_tm)
            levels[level] = {"D_T": d_t, "D_TM": d_tm, "share_D_T": float(share_t),
                             "share_D_TM": float(share_tm),
                             "met": bool(share_t >= EN17037_SHARES[0]
                                         and share_tm >= EN17037_SHARES[1])}
        result["en17037"] = levels
    return result


def report_lines(scene, lux, median_external_illuminance: float | None = None) -> list[str]:
    """Lines of text on the daylight factors of illuminances ``lux`` (an array; NaNs
    ignored) under the scene's ``ciesky``: E_out, DF mean/median/min/max, the shares of the
    points above 1, 2 and 5 %, and EN 17037's levels given E_v,d,med."""
    E_out = sky_horizontal_illuminance(scene)
    stats = statistics(daylight_factor(lux, E_out), targets=(1.0, 2.0, 5.0),
                       median_external_illuminance=median_external_illuminance)
    lines = [f"daylight factor (E_out {E_out:.6g} lx, the sky's unobstructed horizontal "
             f"illuminance): DF_mean {stats['mean']:.3g} %, DF_median {stats['median']:.3g} %, "
             f"DF_min {stats['min']:.3g} %, DF_max {stats['max']:.3g} %",
             "share of the points at or above " + ", ".join(
                 f"{target:g} %: {share:.0%}" for target, share in stats["share_above"].items())]
    for level, verdict in stats.get("en17037", {}).items():
        lines.append(f"EN 17037 {level}: DF >= {verdict['D_T']:.3g} % on "
                     f"{verdict['share_D_T']:.0%} (50 % asked), >= {verdict['D_TM']:.3g} % on "
                     f"{verdict['share_D_TM']:.0%} (95 % asked): "
                     f"{'met' if verdict['met'] else 'not met'}")
    return lines
