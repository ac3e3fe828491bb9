"""Tests of ``ieslight``'s luminous openings (``opening``; ``plugins/emitters/ieslight.py``,
the geometry of ``plugins/emitters/opening.py``, carried by their shapes by
``plugins/emitters/sized.py``): each point of the opening emits L = I(omega) / A_proj(omega).

Oracles: the point law E = I cos(theta) / d^2 far away, Howell's configuration factors of a
uniform Lambertian disk (on its axis) and rectangle (under its corner) for a cos(gamma) file,
the file's own flux (Gauss's theorem: all of it crosses a closed surface), the file's
``Photometry.intensity`` over the projected area seen by a radiance meter, and mitsuba.chi2
for the densities of the new samplers.
"""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest
from test_opening import assert_chi2

#: Samples per point of the illuminance measurements, and the number of standard errors
#: within which a Monte Carlo estimate must meet its closed form.
SPP = 8192
N_SIGMA = 4.0
#: A far-field plane (20x the opening's size) against the point law.
RTOL_FAR = 5e-3
#: The flux through a closed box against the file's flux, Gauss-Legendre nodes per axis of
#: each face (a box opening's illuminance has kinks where a face comes into view: the
#: quadrature converges slowly, 1.2% off with 10 nodes, 0.3% with 20).
RTOL_FLUX = 5e-3
FLUX_NODES = 20
#: The radiance seen by a meter against I / A_proj (the meter's rays, float32 lookups).
RTOL_RADIANCE = 2e-3
#: The mean weight of N_RAYS rays of sample_ray against the flux.
N_RAYS = 400_000
RTOL_RAYS = 1e-2
#: A Lambertian file's on-axis intensity (cd).
I0 = 100.0
#: Variants in which the emitted luminance is checked.
COLOUR_VARIANTS = ("llvm_ad_rgb", "llvm_ad_spectral", "llvm_ad_mono")


def lambertian_file(tmp_path, opening=(0.0, 0.0, 0.0)):
    """An LM-63-2002 file of I = I0 cos(gamma) below the horizon, 0 above it, with the
    signed luminous ``opening`` (width, length, height) in metres."""
    from spectrace.photometry import generate

    return str(generate.write_ies_function(tmp_path / "lambert.ies",
                                           generate.cos_power(I0, 1.0), opening=opening))


def washer_file(tmp_path, opening=(0.0, 0.0, 0.0)):
    """An asymmetric wall-washer profile (light above the horizon too) with ``opening``."""
    from spectrace.photometry import generate

    return str(generate.write_ies_function(tmp_path / "washer.ies",
                                           generate.wall_washer(800.0), symmetry="none",
                                           opening=opening))


def lux(light: dict, points, normals, spp: int = SPP):
    """(E, stderr) in lux at ``points`` from ``light`` on its shape, alone in a scene."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    from spectrace.lighting.points import measure_points

    scene = mi.load_dict(sized.expand_dict({"type": "scene", "light": light}))
    E, err, _ = measure_points(scene, np.asarray(points, float), np.asarray(normals, float),
                               spp=spp, seed=1)
    return E, err


def assert_within_noise(E, err, expected):
    assert np.all(np.abs(E - expected) <= N_SIGMA * err + 1e-6 * np.abs(expected)), \
        (E, err, expected)


@pytest.mark.parametrize("h", [0.05, 0.2, 0.6])
def test_disk_on_its_axis(variant_rgb, tmp_path, h):
    """A disk opening of radius r with a cos(gamma) file is a uniform Lambertian disk of
    L = I0 / (pi r^2): on its axis at h, E = pi L r^2 / (r^2 + h^2) (Howell B-13), not
    the point law's I0 / h^2."""
    r = 0.15
    light = {"type": "ieslight", "filename": lambertian_file(tmp_path),
             "opening": "disk", "diameter": 2 * r}
    E, err = lux(light, [[0.0, 0.0, h]], [[0.0, 0.0, -1.0]])
    L = I0 / (np.pi * r * r)
    assert_within_noise(E, err, np.pi * L * r * r / (r * r + h * h))


@pytest.mark.parametrize("c", [0.1, 0.5])
def test_rectangle_under_its_corner(variant_rgb, tmp_path, c):
    """A rectangle opening (length a along C0-C180, width b) with a cos(gamma) file is a
    uniform Lambertian rectangle of L = I0 / (a b): under its corner at c, E = pi L F with
    F Howell's configuration factor of a parallel rectangle (B-3)."""
    from spectrace.validation.reference import rectangle_corner_factor

    a, b = 0.6, 0.2
    light = {"type": "ieslight", "filename": lambertian_file(tmp_path, (b, a, 0.0))}
    E, err = lux(light, [[a / 2, b / 2, c]], [[0.0, 0.0, -1.0]])
    assert_within_noise(E, err, np.pi * I0 / (a * b) * rectangle_corner_factor(a, b, c))


@pytest.mark.parametrize("opening", [(-0.3, -0.3, -0.3), (0.1, 0.3, 0.0), (-0.3, -0.3, 0.0)],
                         ids=["sphere", "rectangle", "disk"])
def test_far_field_is_the_point_law(variant_rgb, tmp_path, opening):
    """20 times its size away, the file's opening lights a plane as its point version
    (opening 'point', the law I cos(theta) / d^2) to within 0.5%. (Not a box: its faces
    lie h/2 from the photometric centre, which moves its lux by about h/d, 0.9% measured
    for a 0.1 m high box at 6 m.)"""
    path = washer_file(tmp_path, opening)
    sized, point = far_field_lux(path, {}, 20 * max(abs(x) for x in opening))
    np.testing.assert_allclose(sized, point, rtol=RTOL_FAR)


def far_field_lux(path, extra: dict, d: float, spp: int = SPP):
    """The lux of the ``ieslight`` of ``path`` (with ``extra`` parameters, turned 30
    degrees about z) and of its point version on five points of a plane at the height
    ``d`` under it."""
    import mitsuba as mi

    x = np.linspace(-0.8, 0.8, 5) * d
    points = np.stack([x, 0.3 * x, np.full_like(x, d)], axis=1)
    normals = np.tile([0.0, 0.0, -1.0], (len(x), 1))
    to_world = mi.ScalarTransform4f().rotate([0, 0, 1], 30.0)
    sized, _ = lux({"type": "ieslight", "filename": path, "to_world": to_world, **extra},
                   points, normals, spp=spp)
    point, _ = lux({"type": "ieslight", "filename": path, "to_world": to_world,
                    "opening": "point"}, points, normals, spp=1)
    return sized, point


@pytest.mark.parametrize("opening", [(0.2, 0.5, 0.0), (0.2, 0.5, 0.3)],
                         ids=["rectangle", "box"])
def test_flux_through_a_closed_box(variant_rgb, tmp_path, opening):
    """All the file's flux crosses a closed box around the opening (Gauss-Legendre
    quadrature of the illuminance over its six faces), to within 0.5%: the opening emits
    the file's flux."""
    from spectrace.photometry import read_photometry

    path = washer_file(tmp_path, opening)
    flux = flux_through_closed_box({"type": "ieslight", "filename": path})
    assert flux == pytest.approx(read_photometry(path).flux, rel=RTOL_FLUX)


def flux_through_closed_box(light: dict, half: float = 0.8) -> float:
    """The flux (lm) that ``light`` sends through the closed box [-half, half]^3: the
    Gauss-Legendre quadrature (FLUX_NODES per axis) of the inward illuminance over its
    six faces."""
    from spectrace.validation.reference import gauss_legendre_grid

    points, normals, weights = [], [], []
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        a, b, w = gauss_legendre_grid(-half, half, -half, half, FLUX_NODES)
        for side in (-1.0, 1.0):
            p = np.zeros((len(a), 3))
            p[:, axis], p[:, others[0]], p[:, others[1]] = side * half, a, b
            n = np.zeros_like(p)
            n[:, axis] = -side
            points.append(p)
            normals.append(n)
            weights.append(w)
    E, _ = lux(light, np.concatenate(points), np.concatenate(normals), spp=512)
    return float(np.sum(E * np.concatenate(weights)))


@pytest.mark.parametrize("variant_name", COLOUR_VARIANTS)
@pytest.mark.parametrize("opening", [(0.2, 0.5, 0.3), (0.2, 0.5, 0.0), (0.3, 0.0, 0.3)],
                         ids=["box", "rectangle", "sphere"])
def test_meter_sees_intensity_over_projected_area(tmp_path, variant_name, opening):
    """A radiance meter looking at the opening (on its shape) sees the luminance
    L = I(omega) / A_proj(omega) of the file's intensity in the meter's direction omega
    (L_v = K_m integral V L_e, from the film's Y), in RGB, spectral and mono."""
    from spectrace.photometry import read_photometry
    from spectrace.plugins.emitters import sized

    import spectrace

    spectrace.set_variant(variant_name)
    sphere = opening[1] == 0.0
    if sphere:  # an LM-63-2002 sphere: every dimension -diameter
        opening = (-opening[0], -opening[0], -opening[2])
    path = washer_file(tmp_path, opening)
    w, length, h = (abs(x) for x in opening)
    gamma, c = np.radians(35.0), np.radians(20.0)
    omega = np.array([np.sin(gamma) * np.cos(c), -np.sin(gamma) * np.sin(c), np.cos(gamma)])
    if sphere:
        area = np.pi * w * w / 4
    else:
        area = length * w * abs(omega[2]) + (w * h * abs(omega[0]) + length * h * abs(omega[1]))
    expected = read_photometry(path).intensity(np.degrees(gamma), np.degrees(c)) / area
    scene = sized.expand_dict({"type": "scene", "light": {"type": "ieslight",
                                                          "filename": path}})
    assert meter_luminance(scene, omega, 1024) == pytest.approx(float(expected),
                                                             rel=RTOL_RADIANCE)


def meter_luminance(scene: dict, omega, spp: int) -> float:
    """The luminance (cd/m^2, K_m integral V L_e from the film's Y) that a radiance meter
    3 m away along ``omega``, looking back at the origin, sees in ``scene`` (a dict)."""
    import mitsuba as mi

    scene = {**scene, "integrator": {"type": "path", "max_depth": 1}}
    scene["sensor"] = {
        "type": "radiancemeter", "origin": list(3.0 * omega), "direction": list(-omega),
        "film": {"type": "hdrfilm", "width": 1, "height": 1, "pixel_format": "luminance",
                 "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": spp},
    }
    Y = float(np.array(mi.render(mi.load_dict(scene)), dtype=np.float64).ravel()[0])
    return checks.KM * checks.CIE_Y_INTEGRAL * Y


REF = (0.1, -0.2, 0.3)


@pytest.mark.parametrize("opening", ["box", "rectangle", "disk", "sphere", "cylinder"])
def test_sample_direction_chi2(variant_rgb, tmp_path, opening):
    """The directions that ``sample_direction`` draws towards an opening follow the
    density that ``pdf_direction`` reports for the hit the integrators build (mitsuba.chi2;
    the flat openings seen from behind, their back face)."""
    import drjit as dr
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    sizes = {"box": {"width": 0.3, "length": 0.5, "height": 0.2},
             "rectangle": {"width": 0.3, "length": 0.5}, "disk": {"diameter": 0.5},
             "sphere": {"diameter": 0.4},
             "cylinder": {"diameter": 0.3, "height": 0.4}}[opening]
    to_world = mi.ScalarTransform4f().translate([0.2, 0.1, 0.0]).rotate([0.6, 0.8, 0], 20.0)
    light = {"type": "ieslight", "filename": washer_file(tmp_path), "opening": opening,
             "to_world": to_world, **sizes}
    scene = mi.load_dict(sized.expand_dict({"type": "scene", "light": light}))
    emitter = scene.emitters()[0]

    def interaction(n):
        it = dr.zeros(mi.Interaction3f, n)
        it.p = mi.Point3f(*REF)
        return it

    def sample(s):
        ds, _ = emitter.sample_direction(interaction(dr.width(s)), s)
        return ds.d

    def pdf(d):
        it = interaction(dr.width(d))
        si = scene.ray_intersect(mi.Ray3f(it.p, d))
        ds = mi.DirectionSample3f(scene, si, it)
        return dr.select(si.is_valid(), emitter.pdf_direction(it, ds, si.is_valid()), 0.0)

    assert_chi2(sample, pdf, ires=64)


def test_point_keeps_the_delta_light(variant_rgb, tmp_path):
    """``opening`` 'point' on a file with an opening emits exactly what the same file
    without an opening emits (the delta light, bit for bit)."""
    import mitsuba as mi

    directions, _ = checks.sphere_quadrature(8, 8)
    (tmp_path / "sized").mkdir()
    sized_file = washer_file(tmp_path / "sized", (0.2, 0.5, 0.1))
    plain = washer_file(tmp_path)
    a = checks.eval_intensity(mi.load_dict({"type": "ieslight", "filename": sized_file,
                                            "opening": "point"}), directions)
    b = checks.eval_intensity(mi.load_dict({"type": "ieslight", "filename": plain}),
                              directions)
    np.testing.assert_array_equal(a, b)
    light = mi.load_dict({"type": "ieslight", "filename": plain})
    assert mi.has_flag(light.flags(), mi.EmitterFlags.DeltaPosition)


@pytest.mark.parametrize(("params", "expected"), [
    ({"opening": "ellipse"}, "'opening'"),
    ({"opening": "disk", "diameter": -0.1}, "'diameter'"),
    ({"opening": "rectangle", "width": float("nan"), "length": 0.2}, "'width'"),
    ({"opening": "rectangle", "width": 0.0, "length": 0.2}, "'width'"),
    ({"opening": "rectangle", "width": 0.1}, "'length'"),
    ({"opening": "file", "width": 0.1}, "'width'"),
    ({"opening": "point", "diameter": 0.1}, "'diameter'"),
    ({"opening": "disk", "diameter": 0.1, "height": 0.1}, "'height'"),
    ({"opening": "cylinder", "diameter": 0.1}, "'height'"),
    ({"opening": "cylinder", "diameter": 0.1, "height": 0.0}, "'height'"),
])
def test_bad_openings_fail_with_one_line(variant_rgb, tmp_path, params, expected):
    """An unknown opening, a negative, NaN or zero size, a missing size or a size that the
    opening does not take fail at load with one line naming the parameter."""
    import mitsuba as mi

    with pytest.raises(RuntimeError, match=expected) as error:
        mi.load_dict({"type": "ieslight", "filename": lambertian_file(tmp_path), **params})
    assert "ieslight" in str(error.value)


def test_cli_bad_opening_exits_2(variant_rgb, tmp_path):
    """``spectrace render`` of a scene with a bad opening prints one error line naming the
    parameter and exits 2, writing nothing."""
    import subprocess
    import sys
    from pathlib import Path

    lambertian_file(tmp_path)
    scene = tmp_path / "scene.xml"
    scene.write_text(
        '<scene version="3.0.0"><integrator type="direct"/><sensor type="perspective">'
        '<film type="hdrfilm"><integer name="width" value="8"/>'
        '<integer name="height" value="8"/></film></sensor>'
        '<emitter type="ieslight"><string name="filename" value="lambert.ies"/>'
        '<string name="opening" value="disk"/><float name="diameter" value="-1"/>'
        "</emitter></scene>")
    spectrace = Path(sys.executable).parent / "spectrace"
    out = tmp_path / "out.exr"
    run = subprocess.run([str(spectrace), "render", str(scene), "-o", str(out)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "'diameter'" in lines[0], run.stderr
    assert not out.exists()


@pytest.mark.parametrize("extra", [{}, {"opening": "cylinder", "diameter": 0.3, "height": 0.4}],
                         ids=["box", "cylinder"])
def test_sample_ray_weights_average_to_the_flux(variant_rgb, tmp_path, extra):
    """The rays that ``sample_ray`` draws from a box or cylinder opening (uniform on its
    surface, cosine about the normal) carry on average the file's flux: mean weight = Phi_e =
    Phi_v / (K_m integral V) for a white light (N_RAYS rays)."""
    import mitsuba as mi
    from spectrace.photometry import read_photometry

    path = washer_file(tmp_path, (0.2, 0.5, 0.3))
    light = mi.load_dict({"type": "ieslight", "filename": path, **extra})
    rng = np.random.default_rng(3)
    u = rng.random((5, N_RAYS))
    _, weight = light.sample_ray(0.0, mi.Float(u[0]), mi.Point2f(u[1], u[2]),
                                 mi.Point2f(u[3], u[4]))
    mean = float(np.mean(np.array(weight)[0]))
    flux = read_photometry(path).flux
    assert mean * checks.KM * checks.CIE_Y_INTEGRAL == pytest.approx(flux, rel=RTOL_RAYS)


def test_scene_loader_puts_the_opening_on_its_shape(variant_rgb, tmp_path):
    """One ``<emitter type="ieslight">`` of a file with an opening becomes, at scene load,
    a shape carrying the light (so that it is visible and hit by BSDF rays); with
    ``opening`` 'point' it stays a delta light without a shape."""
    from spectrace.lighting.glare import has_visible_lights
    from spectrace.scene import load_scene

    washer_file(tmp_path, (0.2, 0.5, 0.0))
    for opening, shapes in (("file", 1), ("point", 0)):
        scene_path = tmp_path / f"{opening}.xml"
        scene_path.write_text(
            '<scene version="3.0.0"><integrator type="direct"/><sensor type="perspective"/>'
            '<emitter type="ieslight"><string name="filename" value="washer.ies"/>'
            f'<string name="opening" value="{opening}"/></emitter></scene>')
        scene = load_scene(scene_path)
        assert len(scene.shapes()) == shapes
        assert (scene.emitters()[0].get_shape() is not None) == bool(shapes)
        assert has_visible_lights(scene) == bool(shapes)
    import mitsuba as mi

    unshaped = mi.load_dict({"type": "scene", "light": {  # no loader: lights, is not seen
        "type": "ieslight", "filename": str(tmp_path / "washer.ies")}})
    assert not has_visible_lights(unshaped)


def test_luminaires_scene_has_visible_luminaires(variant_rgb):
    """scenes/luminaires.xml: each of its four luminaires is its file's opening, on a
    shape (visible, so that a glare rating can be computed from the view)."""
    from pathlib import Path

    from spectrace.lighting.glare import has_visible_lights
    from spectrace.scene import load_scene

    scene = load_scene(Path(__file__).parents[2] / "scenes" / "luminaires.xml",
                       {"res": "16", "spp": "1"})
    lights = [e for e in scene.emitters() if "IESLight" in str(e)]
    assert len(lights) == 4 and all(e.get_shape() is not None for e in lights)
    assert has_visible_lights(scene)


#: Light tracing against path tracing: relative error of 8x8-pixel block means.
RTOL_PTRACER = 0.05


def test_ptracer_agrees_with_path(variant, tmp_path):
    """Light tracing (``ptracer``: rays from the opening's surface, the visible opening
    connected to the camera) converges to ``path``'s image of a plane 0.4 m under a
    tilted box opening and of the box itself (its luminance), in RGB and spectral."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    to_world = mi.ScalarTransform4f().look_at([0.2, 0.4, 0.0], [0.5, 0.0, 0.3], [0, 0, 1])
    light = {"type": "ieslight", "filename": washer_file(tmp_path, (0.3, 0.5, 0.2)),
             "to_world": to_world}
    images = []
    for integrator, spp, seed in (({"type": "path", "max_depth": 2}, 64, 0),
                                  ({"type": "ptracer", "max_depth": 2}, 256, 3)):
        scene = sized.expand_dict(checks.plane_scene(light, integrator, spp=spp,
                                                     sensor="perspective", res=32))
        images.append(np.array(mi.render(mi.load_dict(scene), seed=seed),
                               dtype=np.float64)[..., :3])
    path, traced = (block_means(image) for image in images)
    np.testing.assert_allclose(traced, path, rtol=RTOL_PTRACER,
                               atol=RTOL_PTRACER * path.max())


def block_means(image, block: int = 8):
    h, w, c = image.shape
    return image.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3)).sum(-1)


def test_lux_rates_the_glare_of_the_visible_luminaires(tmp_path):
    """``spectrace lux scenes/luminaires.xml --ugr``: the luminaires are seen (their
    openings), so the view has glare sources and a unified glare rating."""
    import re
    import subprocess
    import sys
    from pathlib import Path

    scene = Path(__file__).parents[2] / "scenes" / "luminaires.xml"
    spectrace = Path(sys.executable).parent / "spectrace"
    run = subprocess.run([str(spectrace), "lux", str(scene), "--ugr", "-D", "res=48",
                          "-o", str(tmp_path / "lux.exr")], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    match = re.search(r"UGR (-?[\d.]+) .*: (\d+) source pixels", run.stdout)
    assert match and int(match.group(2)) > 0, run.stdout


def test_a_file_shape_it_does_not_render_is_refused(variant_rgb, tmp_path):
    """A file whose opening is an ellipse (LM-63-2002: width and length negative and
    unequal) fails at load with ``opening`` 'file', one line naming the parameter and
    the shape; ``opening`` 'point' or an explicit shape loads it."""
    import mitsuba as mi

    path = lambertian_file(tmp_path, (-0.2, -0.4, 0.0))
    with pytest.raises(RuntimeError, match="'opening'.*ellipse") as error:
        mi.load_dict({"type": "ieslight", "filename": path})
    assert "ieslight" in str(error.value)
    from spectrace.errors import ParameterError
    from spectrace.scene import load_scene

    scene = tmp_path / "scene.xml"
    scene.write_text('<scene version="3.0.0"><integrator type="direct"/>'
                     '<sensor type="perspective"/><emitter type="ieslight">'
                     '<string name="filename" value="lambert.ies"/></emitter></scene>')
    with pytest.raises(ParameterError) as error:
        load_scene(scene)
    assert "\n" not in str(error.value) and "'opening'" in str(error.value)
    for params in ({"opening": "point"}, {"opening": "disk", "diameter": 0.3}):
        mi.load_dict({"type": "ieslight", "filename": path, **params})


# -- the cylinder opening (a closed mesh made at load) ------------------------------------------

CYLINDER = {"opening": "cylinder", "diameter": 0.3, "height": 0.4}


def test_cylinder_far_field_is_the_point_law(variant_rgb, tmp_path):
    """Far away (400 times its size: its caps lie h/2 from the photometric centre, a
    first-order error h/d like the box's) a closed cylinder opening lights a plane as its
    point version to within 0.5%."""
    # Area sampling: the weights vary with the cosine on the side, hence more samples.
    sized, point = far_field_lux(washer_file(tmp_path), CYLINDER, 400 * 0.4, spp=2**17)
    np.testing.assert_allclose(sized, point, rtol=RTOL_FAR)


def test_cylinder_flux_through_a_closed_box(variant_rgb, tmp_path):
    """All the file's flux leaves the closed cylinder (its side and both caps, one mesh)
    through a closed box around it (Gauss-Legendre quadrature over the box's faces), to
    within 0.5%."""
    from spectrace.photometry import read_photometry

    path = washer_file(tmp_path)
    flux = flux_through_closed_box({"type": "ieslight", "filename": path, **CYLINDER})
    assert flux == pytest.approx(read_photometry(path).flux, rel=RTOL_FLUX)


def test_cylinder_is_one_mesh_seen_with_its_luminance(variant_rgb, tmp_path):
    """The cylinder is carried by ONE closed mesh whose area is the cylinder's (to 1e-3,
    256 sides), and a radiance meter looking at its side at gamma = 60 degrees sees
    L = I(omega) / (2 r h sin(gamma) + pi r^2 |cos(gamma)|)."""
    import mitsuba as mi
    from spectrace.photometry import read_photometry
    from spectrace.plugins.emitters import sized

    path = washer_file(tmp_path)
    r, h = 0.15, 0.4
    scene = sized.expand_dict({"type": "scene", "light": {"type": "ieslight",
                                                          "filename": path, **CYLINDER}})
    (shape,) = [v for v in scene.values() if isinstance(v, mi.Mesh)]
    assert float(shape.surface_area()[0]) == pytest.approx(2 * np.pi * r * (h + r), rel=1e-3)
    gamma, c = np.radians(60.0), np.radians(20.0)
    omega = np.array([np.sin(gamma) * np.cos(c), -np.sin(gamma) * np.sin(c), np.cos(gamma)])
    area = 2 * r * h * np.sin(gamma) + np.pi * r * r * abs(np.cos(gamma))
    expected = read_photometry(path).intensity(np.degrees(gamma), np.degrees(c)) / area
    assert meter_luminance(scene, omega, 64) == pytest.approx(float(expected),
                                                             rel=RTOL_RADIANCE)


def test_file_vertical_cylinder_is_the_cylinder_opening(variant_rgb, tmp_path):
    """An LM-63-2002 file whose opening is a vertical cylinder (width = length < 0,
    height > 0) renders it with ``opening`` 'file': its A_proj seen along gamma = 90
    degrees is the side's 2 r h, along gamma = 0 the cap's pi r^2."""
    import mitsuba as mi

    light = mi.load_dict({"type": "ieslight",
                          "filename": lambertian_file(tmp_path, (-0.3, -0.3, 0.2))})
    side = light.projected_area(mi.Vector3f(1.0, 0.0, 0.0))
    cap = light.projected_area(mi.Vector3f(0.0, 0.0, 1.0))
    assert float(side[0]) == pytest.approx(0.3 * 0.2, rel=1e-6)
    assert float(cap[0]) == pytest.approx(np.pi * 0.15**2, rel=1e-6)


def test_xml_cylinder_is_a_visible_luminaire(variant_rgb, tmp_path, monkeypatch):
    """In an XML scene a cylinder opening is carried by the closed unit-cylinder mesh (a
    PLY file written once to the user's cache folder) scaled to its size: one shape, the
    light attached to it, a visible luminaire of the cylinder's area."""
    from spectrace.lighting.glare import has_visible_lights
    from spectrace.scene import load_scene

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    washer_file(tmp_path)
    scene_path = tmp_path / "cylinder.xml"
    scene_path.write_text(
        '<scene version="3.0.0"><integrator type="direct"/><sensor type="perspective"/>'
        '<emitter type="ieslight"><string name="filename" value="washer.ies"/>'
        '<string name="opening" value="cylinder"/><float name="diameter" value="0.3"/>'
        '<float name="height" value="0.4"/></emitter></scene>')
    scene = load_scene(scene_path)
    (shape,) = scene.shapes()
    assert scene.emitters()[0].get_shape() is not None and has_visible_lights(scene)
    r, h = 0.15, 0.4
    assert float(shape.surface_area()[0]) == pytest.approx(2 * np.pi * r * (h + r), rel=1e-3)
    assert len(list((tmp_path / "cache" / "spectrace").glob("unit_cylinder_*.ply"))) == 1
