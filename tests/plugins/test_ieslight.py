"""Tests of the ``ieslight`` emitter (``plugins/emitters/ieslight.py``): the photometric frame,
the profile lookup against ``Photometry.intensity``, renders against E = I cos(theta) / r^2,
an isotropic file against ``pointlight``, light tracing, the sampling of ``sample_ray``,
``luminous_flux`` and ``scale``, every variant and the load errors.

The photometric files are written by ``spectrace.photometry.generate`` into ``tmp_path``;
the oracle of the intensity is ``Photometry.intensity`` of the file read back (its own
tests check it against the analytic profiles). In RGB variants a white ``spectrum`` has
luminance Y = 1, so the light emits I_e = I_v / (683 integral V dlambda) W/sr per cd
(K_m = 683 lm/W, written here as the oracle's own constant).
"""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

#: K_m (lm/W), CIE 018:2019.
KM = 683.0
#: W/sr per cd of a white (d65) light in RGB variants: 1 / (K_m integral V dlambda), a
#: colour standing for the spectra of the same film Y (``spectrace help luminous``).
WATTS_PER_CD = 1.0 / (KM * checks.CIE_Y_INTEGRAL)
#: The profile lookup against Photometry.intensity (float32 angles from float32
#: directions), relative to the profile's peak.
RTOL_LOOKUP = 2e-5
#: Renders that must agree up to float rounding.
RTOL_SAME = 1e-5
#: Light tracing against direct lighting: relative error of 8x8-pixel block means of the
#: channel sum (noise about 1% at the spp used).
RTOL_PTRACER = 0.04
#: Sphere quadrature of the emitted intensity (midpoint rule, 64 x 128 cells) against a
#: file's flux.
RTOL_FLUX = 2e-3
#: Significance level of the chi-square test (mitsuba.chi2 applies Sidak's correction).
CHI2_SIGNIFICANCE = 0.01
#: Monte Carlo mean of the sample_ray weights against the flux (N_WEIGHTS samples; the
#: weights vary by less than a factor 2 within a cell).
N_WEIGHTS = 200_000
RTOL_WEIGHT_MEAN = 5e-3

#: Light position above the plane y = 0 of the emitter_checks scenes.
P_LIGHT = (0.3, 1.2, -0.2)
#: Irregular file angles (vertical up to 90 degrees: nothing above the horizon).
VERTICAL = [0.0, 5.0, 12.5, 30.0, 45.0, 60.0, 75.0, 85.0, 90.0]
HORIZONTAL = [0.0, 20.0, 45.0, 90.0, 135.0, 200.0, 270.0, 330.0]


# -- files ------------------------------------------------------------------------------

def write_table(path, func, vertical=VERTICAL, horizontal=HORIZONTAL, **kwargs):
    """An LM-63 file of ``func(gamma, c)`` (cd) tabulated at the given Type C angles."""
    from spectrace.photometry import generate

    table = generate.tabulate(func, vertical, horizontal)
    return str(generate.write_ies(path, vertical, horizontal, table, **kwargs))


def wall_washer_file(tmp_path):
    """An asymmetric profile (a lobe tilted 40 degrees towards C = 0 plus a little
    downlight), with symmetry 'none' on irregular angles."""
    from spectrace.photometry import generate

    return write_table(tmp_path / "washer.ies", generate.wall_washer(800.0))


#: Irregular Type B angles: V (vertical) and H (horizontal, from 0: laterally symmetric;
#: from -90: no symmetry).
TYPE_B_V = [-90.0, -60.0, -30.0, -10.0, 0.0, 5.0, 10.0, 20.0, 35.0, 50.0, 70.0, 90.0]
TYPE_B_H = {"B": [0.0, 5.0, 10.0, 20.0, 40.0, 60.0, 90.0],
            "B_full": [-90.0, -50.0, -20.0, -5.0, 0.0, 10.0, 30.0, 60.0, 90.0],
            "B_quadrant": [0.0, 5.0, 10.0, 20.0, 40.0, 60.0, 90.0]}


def profile_file(tmp_path, kind: str) -> str:
    """An asymmetric profile written as Type C ("C": ``wall_washer_file``) or Type B ("B": the
    same wall-washer, laterally symmetric, H from 0; "B_full": the wall-washer turned towards
    C = 90, H from -90 to 90; "B_quadrant": H and V from 0, mirrored in both)."""
    from spectrace.photometry import generate

    if kind == "C":
        return wall_washer_file(tmp_path)
    washer = generate.wall_washer(800.0)
    func = washer if kind == "B" else (lambda gamma, c: washer(gamma, np.asarray(c) - 90.0))
    h = TYPE_B_H[kind]
    v = [x for x in TYPE_B_V if x >= 0] if kind == "B_quadrant" else TYPE_B_V
    table = generate.tabulate(func, v, h, photometric_type="B")
    return str(generate.write_ies(tmp_path / f"{kind}.ies", v, h, table,
                                  photometric_type="B"))


def c90_only(gamma, c):
    """Light only towards C = 90 (C within 40 degrees of it, gamma from 10 to 70)."""
    gamma, c = np.broadcast_arrays(np.asarray(gamma, float), np.asarray(c, float))
    inside = (np.abs(c - 90.0) <= 40.0) & (gamma >= 10.0) & (gamma <= 70.0)
    return np.where(inside, 1000.0, 0.0)


def isotropic_file(tmp_path, candela: float):
    from spectrace.photometry import generate

    return str(generate.write_ies_function(tmp_path / "isotropic.ies",
                                           generate.isotropic(candela)))


def read(path):
    from spectrace.photometry import read_photometry

    return read_photometry(path)


def local_angles(directions_local: np.ndarray):
    """(gamma, C) in degrees of local directions (..., 3), as the plugin page defines them:
    d = (sin gamma cos C, -sin gamma sin C, cos gamma)."""
    x, y, z = directions_local[..., 0], directions_local[..., 1], directions_local[..., 2]
    gamma = np.degrees(np.arctan2(np.hypot(x, y), z))
    return gamma, np.mod(np.degrees(np.arctan2(-y, x)), 360.0)


def direction(gamma_deg, c_deg) -> np.ndarray:
    g, c = np.radians(gamma_deg), np.radians(c_deg)
    return np.stack([np.sin(g) * np.cos(c), -np.sin(g) * np.sin(c), np.cos(g)], axis=-1)


def aimed(target, up):
    """A light at P_LIGHT aimed at ``target`` with ``up``, and its rotation matrix."""
    T = checks.transform()
    to_world = T.look_at(list(P_LIGHT), list(target), list(up))
    return to_world, np.array(to_world.matrix, dtype=np.float64)[:3, :3]


#: A spectrum of luminance Y = 1 in RGB variants (white).
WHITE = {"type": "rgb", "value": [1.0, 1.0, 1.0]}


# -- frame and lookup -------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["C", "B", "B_full", "B_quadrant"])
def test_lookup_matches_photometry_intensity(variant_rgb, tmp_path, rng, kind):
    """The emitted intensity in a direction at (gamma, C) of the local frame is WATTS_PER_CD
    W/sr per cd of ``Photometry.intensity(gamma, C)`` (bilinear on the file's irregular angles:
    (gamma, C) of a Type C file, (H, V) of a Type B one, zero outside the measured range),
    at random angles and at the file's own angles."""
    import mitsuba as mi

    path = profile_file(tmp_path, kind)
    photometry = read(path)
    light = mi.load_dict({"type": "ieslight", "filename": path})
    g_nodes, c_nodes = np.meshgrid(VERTICAL + [120.0, 180.0], HORIZONTAL + [359.0])
    gamma = np.concatenate([rng.uniform(0, 180, 4000), g_nodes.ravel()])
    c = np.concatenate([rng.uniform(0, 360, 4000), c_nodes.ravel()])
    value = checks.eval_intensity(light, direction(gamma, c))
    expected = photometry.intensity(gamma, c) * WATTS_PER_CD
    assert expected.max() > 0 and np.any(expected == 0)
    np.testing.assert_allclose(value, np.repeat(expected[:, None], 3, axis=1), rtol=0,
                               atol=RTOL_LOOKUP * expected.max())


def test_frame_c90_is_local_minus_y(variant_rgb, tmp_path):
    """C = 90 is local -Y: aimed straight down with lookat ``up`` = world +Z, a profile that
    emits only towards C = 90 lights the floor on the world -Z side only (local +Y is the
    ``up`` vector); with ``up`` = world +X it lights the -X side."""
    p = checks.positions()
    path = write_table(tmp_path / "c90.ies", c90_only, vertical=np.arange(0, 91, 5.0),
                       horizontal=np.arange(0, 360, 5.0))
    for up, axis in (([0, 0, 1], 2), ([1, 0, 0], 0)):
        to_world, _ = aimed([P_LIGHT[0], 0, P_LIGHT[2]], up)
        image = checks.render({"type": "ieslight", "filename": path, "to_world": to_world})
        lum = image.sum(-1)
        side = p[..., axis] - P_LIGHT[axis]
        assert lum[side < -0.1].sum() > 0
        assert lum[side > 0.0].sum() == 0.0, up


@pytest.mark.parametrize(("angle", "world_axis"), [("V", 0), ("H", 2)])
def test_type_b_frame(variant_rgb, tmp_path, angle, world_axis):
    """A Type B file's aiming axis (H = V = 0) is local +Z; its V > 0 half is local +X
    (C = 0, ``up`` x aim with lookat); H > 0 is C = 270, local +Y (the lookat ``up`` side
    when aimed down: LM-63 measures Type B horizontal angles clockwise seen from above the
    floodlight). A floodlight that emits only for that angle in [10, 60] degrees (the other
    within 30 degrees of 0), aimed down with ``up`` = world +Z, lights the floor on the
    world +X side (V) or the world +Z side (H) only."""
    from spectrace.photometry import generate

    h = np.arange(-90.0, 90.1, 5.0)[:, None]
    v = np.arange(-90.0, 90.1, 5.0)[None, :]
    lit, other = (v, h) if angle == "V" else (h, v)
    table = np.where((lit >= 10) & (lit <= 60) & (np.abs(other) <= 30), 500.0, 0.0)
    path = str(generate.write_ies(tmp_path / "flood.ies", v.ravel(), h.ravel(), table,
                                  photometric_type="B"))
    p = checks.positions()
    to_world, _ = aimed([P_LIGHT[0], 0, P_LIGHT[2]], [0, 0, 1])
    lum = checks.render({"type": "ieslight", "filename": path, "to_world": to_world}).sum(-1)
    side = p[..., world_axis] - P_LIGHT[world_axis]
    assert lum[side > 0.1].sum() > 0
    assert lum[side < 0.0].sum() == 0.0


def test_light_from_an_in_memory_photometry(variant_rgb, tmp_path, rng):
    """``from_photometry`` builds the light from a ``Photometry`` object: the one read from
    a file emits what the file's plugin emits; its candela table doubled in memory emits
    twice that; a table written in memory (isotropic 100 cd) emits 100 cd everywhere."""
    import mitsuba as mi
    from spectrace.photometry import Photometry
    from spectrace.plugins.emitters import ieslight

    path = profile_file(tmp_path, "B_full")
    photometry = read(path)
    d = direction(rng.uniform(0, 180, 500), rng.uniform(0, 360, 500))
    from_file = checks.eval_intensity(mi.load_dict({"type": "ieslight", "filename": path}), d)
    same = checks.eval_intensity(ieslight.from_photometry(photometry), d)
    np.testing.assert_array_equal(same, from_file)
    doubled = ieslight.from_photometry(photometry.replace(candela=2 * photometry.candela),
                                       {"spectrum": WHITE})
    np.testing.assert_allclose(checks.eval_intensity(doubled, d), 2 * from_file, rtol=1e-6)
    table = Photometry(path="memory", format="LM-63-2002", photometric_type="C",
                       vertical_angles=[0.0, 90.0, 180.0], horizontal_angles=[0.0],
                       candela=[[100.0, 100.0, 100.0]], symmetry="rotational")
    value = checks.eval_intensity(ieslight.from_photometry(table, {"scale": 0.5}), d)
    np.testing.assert_allclose(value, 50.0 * WATTS_PER_CD, rtol=RTOL_SAME)
    with pytest.raises(ValueError, match="'filename' does not apply"):
        ieslight.from_photometry(table, {"filename": path})


def test_render_turned_profile_against_closed_form(variant_rgb, tmp_path):
    """The asymmetric profile, aimed obliquely by ``to_world``, gives a diffuse plane the
    radiance rho/pi * E with E = I(gamma, C) cos(theta) / r^2 at every pixel, (gamma, C)
    the angles of the direction to the pixel's point in the light's frame."""
    path = wall_washer_file(tmp_path)
    photometry = read(path)
    to_world, R = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    image = checks.render({"type": "ieslight", "filename": path, "to_world": to_world})
    p = checks.positions()

    def directional(d, r):
        gamma, c = local_angles(d @ R)  # R^T d: world to local
        return photometry.intensity(gamma, c) * WATTS_PER_CD / r**2

    expected = checks.closed_form(p, P_LIGHT, directional)
    assert expected.max() > 0 and np.count_nonzero(expected) > expected.size // 4
    checks.assert_image_close(image, expected)


def test_spectral_render_is_profile_times_pointlight(variant_spectral, tmp_path):
    """In spectral variants the light of spectrum s renders, at every pixel, like a
    ``pointlight`` of 1 cd of the same spectrum times I(gamma, C) (same seed: same
    wavelengths), so the luminous scale of the profile is the one of the candela."""
    path = wall_washer_file(tmp_path)
    photometry = read(path)
    spd = {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}
    to_world, R = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    image = checks.render({"type": "ieslight", "filename": path, "to_world": to_world,
                           "spectrum": spd}, seed=5)
    point = checks.render({"type": "pointlight", "position": list(P_LIGHT),
                           "luminous_intensity": 1.0, "spectrum": spd}, seed=5)
    p = checks.positions()
    gamma, c = local_angles((p - np.array(P_LIGHT)) @ R)
    expected = point * photometry.intensity(gamma, c)[..., None]
    checks.assert_image_close(image, expected)


def test_eulumdat_file_emits_like_ies_file(variant_rgb, tmp_path):
    """A ``.ldt`` file and an ``.ies`` file of the same distribution (a cos^8 downlight,
    tabulated at the same angles) give the same emitted intensity in every direction.
    The point law: ``opening`` 'point', as the ``.ldt`` file has a luminous area (the
    generator writes a 0.1 m disk)."""
    import mitsuba as mi
    from spectrace.photometry import generate

    func = generate.cos_power(1200.0, 8.0)
    gamma = np.arange(0.0, 180.1, 5.0)
    ies = generate.write_ies_function(tmp_path / "down.ies", func, vertical_angles=gamma)
    ldt = generate.write_ldt(tmp_path / "down.ldt", func, isym=1, gamma_angles=gamma)
    directions, _ = checks.sphere_quadrature(16, 16)
    values = [checks.eval_intensity(mi.load_dict({"type": "ieslight", "filename": str(p),
                                                  "opening": "point"}),
                                    directions) for p in (ies, ldt)]
    assert values[0].max() > 0
    np.testing.assert_allclose(values[1], values[0], rtol=1e-5, atol=1e-7 * values[0].max())


def test_emitter_interface(variant, tmp_path):
    """The delta-position interface: flags, sample_direction towards the light (sets
    ds.emitter, pdf 1, delta), pdf_direction 0, eval 0, sample_position and bbox at the
    light (the translation of ``to_world``)."""
    import drjit as dr
    import mitsuba as mi

    to_world, _ = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    light = mi.load_dict({"type": "ieslight", "filename": wall_washer_file(tmp_path),
                          "to_world": to_world})
    assert light.flags() == int(mi.EmitterFlags.DeltaPosition)
    it = dr.zeros(mi.Interaction3f, 3)
    it.p = mi.Point3f([0.0, 1.0, -1.0], [0.0, 0.0, 0.5], [0.0, 2.0, 0.0])
    it.wavelengths = checks.wavelength_grid(3).wavelengths
    ds, value = light.sample_direction(it, mi.Point2f(0.3, 0.7))
    v = np.array(P_LIGHT)[:, None] - np.array(it.p)
    np.testing.assert_allclose(np.array(ds.d), v / np.linalg.norm(v, axis=0), rtol=1e-5,
                               atol=1e-6)
    np.testing.assert_allclose(np.array(ds.dist), np.linalg.norm(v, axis=0), rtol=1e-6)
    assert np.all(np.array(ds.pdf) == 1.0) and np.all(np.array(ds.delta))
    assert dr.all(ds.emitter == mi.EmitterPtr(light), axis=None)
    assert dr.all(light.pdf_direction(it, ds) == 0.0)
    np.testing.assert_allclose(np.array(light.eval_direction(it, ds)), np.array(value),
                               rtol=1e-5, atol=1e-12)
    assert dr.all(light.eval(dr.zeros(mi.SurfaceInteraction3f)) == 0.0, axis=None)
    ps, weight = light.sample_position(0.0, mi.Point2f(0.5))
    np.testing.assert_allclose(np.array(ps.p).ravel(), P_LIGHT, rtol=1e-6)
    assert bool(ps.delta[0]) and float(weight[0]) == 1.0
    np.testing.assert_allclose(list(light.bbox().min), P_LIGHT, rtol=1e-6)


# -- against pointlight, light tracing ----------------------------------------------------

@pytest.mark.parametrize("integrator", ["path", "direct", "prb", "local"])
def test_isotropic_file_matches_pointlight(variant, tmp_path, integrator):
    """A file of 250 cd in every direction renders exactly like ``pointlight`` with
    ``luminous_intensity`` 250 and the same spectrum (same seed), with shadows and
    interreflections (a sphere on the plane)."""
    import mitsuba as mi

    path = isotropic_file(tmp_path, 250.0)
    spectrum = {"type": "d65"} if mi.is_spectral else {"type": "rgb", "value": [1.0, 0.8, 0.5]}
    images = []
    for light in ({"type": "pointlight", "position": list(P_LIGHT),
                   "luminous_intensity": 250.0, "spectrum": spectrum},
                  {"type": "ieslight", "filename": path, "spectrum": spectrum,
                   "to_world": checks.transform().translate(list(P_LIGHT))}):
        scene = checks.plane_scene(light, integrator, spp=4, sensor="perspective", res=16)
        scene["sphere"] = {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5}
        images.append(np.array(mi.render(mi.load_dict(scene), seed=7)))
    reference, image = images
    assert reference.max() > 0.0
    np.testing.assert_allclose(image, reference, rtol=RTOL_SAME, atol=RTOL_SAME * reference.max())


def block_means(image: np.ndarray, block: int = 8) -> np.ndarray:
    h, w, c = image.shape
    return image.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3)).sum(-1)


def test_ptracer_agrees_with_direct(variant, tmp_path):
    """Light tracing (``ptracer``: directions from sample_ray's distribution, weighted by
    I / pdf) converges to the direct-lighting image of the turned asymmetric profile."""
    path = wall_washer_file(tmp_path)
    to_world, _ = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    light = {"type": "ieslight", "filename": path, "to_world": to_world}
    direct = checks.render(light, "direct", spp=16, sensor="perspective")
    traced = checks.render(light, {"type": "ptracer", "max_depth": 2}, spp=256,
                           sensor="perspective", seed=3)
    np.testing.assert_allclose(block_means(traced), block_means(direct), rtol=RTOL_PTRACER,
                               atol=RTOL_PTRACER * block_means(direct).max())


# -- sampling ---------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["C", "B_full", "B_quadrant"])
def test_sample_ray_chi2_and_weights(variant_rgb, tmp_path, rng, kind):
    """``sample_ray`` draws world directions with the density ``ray_direction_pdf``
    (Pearson's chi-square test, mitsuba.chi2; the density integrates to 1), and each ray's
    weight times that density is the emitted intensity I_v(gamma, C) / 683 of the file
    (``Photometry.intensity``): together, the rays carry exactly the intensity profile.
    The mean weight is then the radiant flux, the file's flux / 683. For a Type C file
    and Type B ones (one mirrored in H and V)."""
    import mitsuba as mi
    from mitsuba import chi2

    path = profile_file(tmp_path, kind)
    photometry = read(path)
    to_world, R = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    light = mi.load_dict({"type": "ieslight", "filename": path, "to_world": to_world,
                          "spectrum": WHITE})
    to_local = mi.Transform4f(to_world.inverse())

    def sample(s):
        ray, _ = light.sample_ray(0.0, 0.5, s, mi.Point2f(0.5))
        return ray.d

    def pdf(v):
        return light.ray_direction_pdf(to_local @ mi.Vector3f(v))

    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample, pdf_func=pdf,
                              sample_dim=2, sample_count=400_000, res=101, ires=16)
    assert test.run(CHI2_SIGNIFICANCE), test.messages

    u = rng.random((2, N_WEIGHTS)).astype(np.float32)
    ray, weight = light.sample_ray(0.0, 0.5, mi.Point2f(u[0], u[1]), mi.Point2f(0.5))
    d = np.array(ray.d, dtype=np.float64).T
    np.testing.assert_allclose(np.array(ray.o, dtype=np.float64).T[0], P_LIGHT, rtol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0, rtol=1e-5)
    gamma, c = local_angles(d @ R)
    intensity = photometry.intensity(gamma, c) * WATTS_PER_CD
    density = np.array(pdf(mi.Vector3f(np.array(ray.d))), dtype=np.float64)
    weight = np.array(weight, dtype=np.float64)[0]
    assert np.all(intensity > 0)
    np.testing.assert_allclose(weight * density, intensity, rtol=1e-3,
                               atol=RTOL_LOOKUP * intensity.max())
    np.testing.assert_allclose(weight.mean(), photometry.flux * WATTS_PER_CD, rtol=RTOL_WEIGHT_MEAN)


# -- photometric scale ------------------------------------------------------------------

def emitted_flux(light) -> float:
    """K_m times the emitted radiant intensity integrated over the sphere (lm, RGB
    variants with a white spectrum): midpoint quadrature of eval_direction."""
    directions, weights = checks.sphere_quadrature(64, 128)
    return float((weights @ checks.eval_intensity(light, directions)[:, 1]) / WATTS_PER_CD)


def test_luminous_flux_and_scale(variant_rgb, tmp_path):
    """Without ``luminous_flux`` the light emits the file's flux (a cos^4 downlight of
    I0 = 900 cd: 2 pi I0 / 5 lm); ``luminous_flux`` rescales the profile to that many
    lumens, ``scale`` multiplies the result; the profile's shape is kept."""
    import mitsuba as mi
    from spectrace.photometry import generate

    i0 = 900.0
    path = str(generate.write_ies_function(tmp_path / "cos4.ies", generate.cos_power(i0, 4.0),
                                           vertical_angles=np.arange(0, 90.1, 2.5)))
    base = {"type": "ieslight", "filename": path, "spectrum": WHITE}
    file_flux = 2 * np.pi * i0 / 5
    assert emitted_flux(mi.load_dict(base)) == pytest.approx(file_flux, rel=RTOL_FLUX)
    rescaled = mi.load_dict({**base, "luminous_flux": 1500.0})
    assert emitted_flux(rescaled) == pytest.approx(1500.0, rel=RTOL_FLUX)
    scaled = mi.load_dict({**base, "luminous_flux": 1500.0, "scale": 0.4})
    assert emitted_flux(scaled) == pytest.approx(600.0, rel=RTOL_FLUX)
    axis = np.array([[0.0, 0.0, 1.0]])
    on_axis = checks.eval_intensity(rescaled, axis)[0, 1] / WATTS_PER_CD
    assert on_axis == pytest.approx(i0 * 1500.0 / read(path).flux, rel=1e-5)


def test_traverse_scale_and_spectrum(variant_rgb, tmp_path):
    """``scale``, ``luminous_flux`` and ``spectrum`` are exposed and differentiable; a new
    ``scale`` through mi.traverse changes the emission in proportion."""
    import drjit as dr
    import mitsuba as mi

    light = mi.load_dict({"type": "ieslight", "filename": isotropic_file(tmp_path, 100.0),
                          "luminous_flux": 1000.0, "spectrum": WHITE})
    params = mi.traverse(light)
    for key in ("scale", "luminous_flux", "spectrum.value", "to_world"):
        assert key in params, key
    for key in ("scale", "luminous_flux", "spectrum.value"):
        assert params.flags(key) & int(mi.ParamFlags.NonDifferentiable) == 0, key
    axis = np.array([[0.0, 0.0, 1.0]])
    before = checks.eval_intensity(light, axis)[0, 1]
    params["scale"] = 2.5
    params.update()
    assert checks.eval_intensity(light, axis)[0, 1] == pytest.approx(2.5 * before, rel=1e-6)
    dr.enable_grad(params["scale"])
    params.update()
    it = dr.zeros(mi.Interaction3f)
    it.p = mi.Point3f(0, 0, 2)
    _, value = light.sample_direction(it, mi.Point2f(0.5))
    dr.backward(value[1])
    assert dr.grad(params["scale"])[0] == pytest.approx(1000.0 / (4 * np.pi) * WATTS_PER_CD / 4,
                                                        rel=1e-4)
    with pytest.raises(ValueError, match="'scale'"):
        params["scale"] = -1.0
        params.update()


# -- variants, integrators, errors ------------------------------------------------------

def test_every_variant_and_integrator(any_variant, tmp_path):
    """In every variant (RGB, mono, spectral, polarized) the light loads, returns a
    ``mi.Spectrum`` (a depolarizing Mueller matrix in polarized variants) and lights the
    plane with ``direct``, ``ptracer`` and ``local``: finite, positive images that agree
    (channel sums of the block means, ptracer within its noise)."""
    import drjit as dr
    import mitsuba as mi

    path = wall_washer_file(tmp_path)
    to_world, _ = aimed([0.9, 0.0, 0.1], [1, 0, 1])
    light = {"type": "ieslight", "filename": path, "to_world": to_world,
             "spectrum": {"type": "spectrum", "value": [(400.0, 1.0), (700.0, 2.0)]}}
    emitter = mi.load_dict(light)
    it = dr.zeros(mi.Interaction3f, 2)
    it.p = mi.Point3f([0.0, 1.0], [0.0, 0.0], [0.0, 0.0])
    _, value = emitter.sample_direction(it, mi.Point2f(0.5))
    assert type(value) is mi.Spectrum
    _, weight = emitter.sample_ray(0.0, 0.5, mi.Point2f(0.3, 0.6), mi.Point2f(0.5))
    assert type(weight) is mi.Spectrum
    images = {name: checks.render(light, integrator, spp=spp, res=16, sensor="perspective")
              for name, integrator, spp in (("direct", "direct", 16),
                                            ("local", "local", 16),
                                            ("ptracer", {"type": "ptracer", "max_depth": 2},
                                             256))}
    for name, image in images.items():
        assert np.all(np.isfinite(image)) and image.max() > 0, name
    reference = block_means(images["direct"])
    np.testing.assert_allclose(block_means(images["local"]), reference, rtol=RTOL_PTRACER,
                               atol=RTOL_PTRACER * reference.max())
    np.testing.assert_allclose(block_means(images["ptracer"]), reference, rtol=2 * RTOL_PTRACER,
                               atol=2 * RTOL_PTRACER * reference.max())


def test_bad_files_fail_at_load_with_one_line(variant_rgb, tmp_path):
    """A truncated file, a missing file and misused parameters fail when the scene loads,
    with one line that names the file (and the field) or the parameter."""
    import mitsuba as mi

    from spectrace.errors import FileFormatError
    from spectrace.scene import load_scene

    good = isotropic_file(tmp_path, 100.0)
    text = open(good, encoding="latin-1").read()
    truncated = tmp_path / "truncated.ies"
    truncated.write_text(text[: len(text) // 2], encoding="latin-1")
    scene = tmp_path / "scene.xml"
    scene.write_text(
        '<scene version="3.0.0"><integrator type="direct"/><sensor type="perspective"/>'
        '<emitter type="ieslight"><string name="filename" value="truncated.ies"/></emitter>'
        "</scene>")
    with pytest.raises(FileFormatError) as error:
        load_scene(scene)
    message = str(error.value)
    assert "\n" not in message and "truncated.ies" in message and "ieslight" in message
    cases = {
        "no such file": {"filename": str(tmp_path / "missing.ies")},
        "'filename'": {},
        "'intensity'": {"filename": good, "intensity": 2.0},
        "'scale'": {"filename": good, "scale": -1.0},
        "'luminous_flux'": {"filename": good, "luminous_flux": -5.0},
    }
    for expected, params in cases.items():
        with pytest.raises(RuntimeError, match=expected):
            mi.load_dict({"type": "ieslight", **params})


def test_reference_page(variant_rgb, tmp_path):
    """The module docstring follows the one reference-page format, and its |exposed| /
    |differentiable| marks agree with what mi.traverse reports."""
    import mitsuba as mi
    from spectrace.plugins.emitters import ieslight

    table = checks.parse_reference_page(ieslight.__doc__, "ieslight")
    assert {"filename", "to_world", "spectrum", "scale", "luminous_flux", "falloff"} <= set(table)
    assert table["luminous_flux"]["unit"] == "lm"
    light = mi.load_dict({"type": "ieslight", "filename": isotropic_file(tmp_path, 10.0),
                          "luminous_flux": 100.0})
    checks.check_marks_against_traverse(table, light)
