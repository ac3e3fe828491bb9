"""Tests of ``local``'s environment terms (plugins/integrators/local.py): the reflection
term rho_s L_env(r) of ``environment`` and the SH irradiance of ``ambient="environment"``.

Oracles, all computed here with numpy from the map file: the irradiance as a brute-force
integral (a midpoint grid 4 times finer than the map) of the map as Mitsuba's ``envmap``
reads it (bilinear, rows from pole to pole) times the clamped cosine; the map looked up
at the mirror direction r = 2 (n . v) n - v of an analytic sphere; and the closed form
E = pi L of a constant environment.
"""

from __future__ import annotations

from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

import spectrace
from spectrace import envmaps
from spectrace.errors import ParameterError
from spectrace.scene import load_scene

MAP = Path(__file__).resolve().parents[2] / "scenes" / "textures" / "daylight_sky.exr"

#: Relative tolerance of float32 against the float64 oracles (one radiance value).
RTOL32 = 1e-5
#: Relative tolerance of "equal up to float32 rounding" (two float32 computations).
RTOL_EXACT = 1e-6
#: Relative tolerance of the reflection term against the float64 lookup: float32 normals
#: and mirror directions move the lookup by ~1e-7 rad, in a map with large gradients.
RTOL_LOOKUP = 1e-4
#: Texel-level discrepancy allowed on top of the measured order-2 error: the projection
#: integrates the map by Gauss-Legendre quadrature (with the kinks of its bilinear
#: interpolation), the oracle by a 4x finer midpoint grid. Relative to the largest
#: irradiance of the map.
DISCRETIZATION = 1e-3
#: Brute-force grid: this many times the map's resolution in each direction.
OVERSAMPLING = 4
#: Turn of the map about +Y (degrees), so that its to_world is exercised.
MAP_ROTATION = 90.0
RHO = 0.5  # diffuse reflectance
RHO_S = 0.6  # specular reflectance of the mirror-like phong
N_NORMALS = 200
SEED = 23


def read_map():
    """The map (H, W, 3) in float64, as numpy."""
    return np.array(mi.Bitmap(str(MAP)), dtype=np.float64)[..., :3]


def rotation_y(degrees):
    """The 3x3 rotation about +Y of Mitsuba's ``rotate`` (right-handed)."""
    a = np.radians(degrees)
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def fine_grid(height, width):
    """World directions (N, 3) and solid angles (N,) of a midpoint grid over the sphere of
    OVERSAMPLING times the map's resolution (the map turned by MAP_ROTATION)."""
    rows, columns = OVERSAMPLING * height, OVERSAMPLING * width
    theta = (np.arange(rows) + 0.5) / rows * np.pi
    phi = (np.arange(columns) + 0.5) / columns * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    local = np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], axis=-1)
    solid_angle = np.sin(t) * (np.pi / rows) * (2 * np.pi / columns)
    return local.reshape(-1, 3) @ rotation_y(MAP_ROTATION).T, solid_angle.ravel()


def bilinear_lookup(image, directions):
    """The map at world ``directions`` (N, 3) as Mitsuba's ``envmap`` reads it: u =
    atan2(x, -z) / 2 pi, v = acos(y) / pi, bilinear with column j at u = (j + 1/2) / W
    (wrapping) and row i at v = i / (H - 1) (the first and last rows at the poles)."""
    local = directions @ rotation_y(MAP_ROTATION)  # inverse of the rotation
    height, width = image.shape[:2]
    u = np.mod(np.arctan2(local[:, 0], -local[:, 2]) / (2 * np.pi), 1.0)
    v = np.arccos(np.clip(local[:, 1], -1, 1)) / np.pi
    x, y = u * width - 0.5, v * (height - 1)
    x0 = np.floor(x).astype(int)
    y0 = np.minimum(np.floor(y).astype(int), height - 2)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]

    def at(i, j):
        return image[j, np.mod(i, width)]

    return ((1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0)
            + (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1))


def brute_force_irradiance(image, normals, d, solid_angle):
    """E(n) = integral L max(n . omega, 0) d omega over the grid (d, solid_angle): (N, 3)."""
    L = bilinear_lookup(image, d)
    cos = np.maximum(normals @ d.T, 0.0)
    return (cos * solid_angle) @ L


def map_scene(integrator, bsdf, environment=True):
    """A unit sphere at the origin with ``bsdf``, under the rotated map (id ``sky``)."""
    scene = {"type": "scene", "integrator": integrator,
             "sphere": {"type": "sphere", "bsdf": bsdf}}
    if environment:
        scene["sky"] = {"type": "envmap", "filename": str(MAP),
                        "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], MAP_ROTATION)}
    return mi.load_dict(scene)


def shade(scene, origins, directions, wavelengths=None):
    """The integrator's radiance (N, C) along the given rays (numpy in and out)."""
    n = len(origins)
    ray = mi.Ray3f(mi.Point3f(*origins.T), mi.Vector3f(*directions.T))
    if wavelengths is not None:
        ray.wavelengths = type(ray.wavelengths)(*wavelengths)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(SEED, n)
    L, valid, _ = scene.integrator().sample(scene, sampler, ray)
    assert bool(dr.all(valid))
    return np.array(mi.unpolarized_spectrum(L), dtype=np.float64).reshape(-1, n).T


def random_normals(n):
    v = np.random.default_rng(SEED).normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_sh_irradiance_matches_the_brute_force_integral(variant_rgb):
    """A diffuse sphere lit by ambient="environment" reflects rho/pi E_SH(n), with E_SH
    within the order-2 truncation error (measured on this map) of the brute-force
    irradiance integral of the map, for normals in every direction."""
    image = read_map()
    normals = random_normals(N_NORMALS)
    d, solid_angle = fine_grid(*image.shape[:2])
    E = brute_force_irradiance(image, normals, d, solid_angle)
    # The order-2 truncation error of this map, measured in float64 on the same grid.
    coefficients = envmaps.sh_project_samples(bilinear_lookup(image, d), solid_angle, d)
    order2_error = np.abs(envmaps.sh_irradiance(coefficients, normals) - E).max()
    assert order2_error > 0

    scene = map_scene({"type": "local", "ambient": "environment"},
                      {"type": "diffuse", "reflectance": RHO})
    L = shade(scene, 3.0 * normals, -normals)
    tolerance = order2_error + DISCRETIZATION * E.max()
    np.testing.assert_allclose(L * np.pi / RHO, E, rtol=0, atol=tolerance)
    # ... and the truncation is a small error on this smooth sky.
    assert tolerance < 0.1 * E.max()


def eval_emitter(emitter, directions, wavelengths=None):
    """The emitter's own radiance (N, C) arriving from world ``directions`` (N, 3)."""
    si = dr.zeros(mi.SurfaceInteraction3f, len(directions))
    si.wi = -mi.Vector3f(*np.ascontiguousarray(directions.T))
    if wavelengths is not None:
        si.wavelengths = type(si.wavelengths)(*wavelengths)
    L = np.array(mi.unpolarized_spectrum(emitter.eval(si)), dtype=np.float64)
    return L.reshape(-1, len(directions)).T


#: Wavelengths (nm) of the spectral checks, on and between the 5 nm nodes of the table.
WAVELENGTHS = (405.0, 512.5, 600.0, 777.0)
#: Environments whose SH irradiance is checked against a brute-force integral of their
#: own eval: (variant, emitter).
EMITTERS = {
    "envmap-spectral": ("llvm_ad_spectral", {
        "type": "envmap", "filename": str(MAP), "to_world": "rotated"}),
    "ciesky-overcast-rgb": ("llvm_ad_rgb", {
        "type": "ciesky", "sky_type": "cie_overcast", "zenith_luminance": 5000.0}),
    "ciesky-12-spectral": ("llvm_ad_spectral", {
        "type": "ciesky", "sky_type": 12, "zenith_luminance": 5000.0,
        "sun_elevation": 30.0, "sun_azimuth": 150.0, "ground_reflectance": 0.2}),
}


@pytest.mark.parametrize("case", sorted(EMITTERS))
def test_sh_irradiance_of_any_environment_matches_its_brute_force_integral(case):
    """For an envmap in a spectral variant (the SH table interpolated between its 5 nm
    nodes) and for `ciesky` skies, rho/pi E_SH(n) is within the order-2 error of the
    brute-force irradiance integral of the emitter's own radiance; the brute force itself
    gives the CIE overcast sky's closed form E_h = 7 pi L_z / 9."""
    variant, emitter = EMITTERS[case]
    spectrace.set_variant(variant)
    if "to_world" in emitter:
        emitter = {**emitter, "to_world": mi.ScalarTransform4f().rotate([0, 1, 0],
                                                                        MAP_ROTATION)}
    scene = mi.load_dict({"type": "scene",
                          "integrator": {"type": "local", "ambient": "environment"},
                          "sky": mi.load_dict(emitter),
                          "sphere": {"type": "sphere",
                                     "bsdf": {"type": "diffuse", "reflectance": RHO}}})
    wavelengths = WAVELENGTHS if mi.is_spectral else None
    normals = np.vstack([[0.0, 1.0, 0.0], random_normals(N_NORMALS)])
    d, solid_angle = fine_grid(64, 128)
    L_grid = eval_emitter(scene.environment(), d, wavelengths)
    E = (np.maximum(normals @ d.T, 0.0) * solid_angle) @ L_grid
    if case.startswith("ciesky-overcast"):
        L_zenith = eval_emitter(scene.environment(), np.array([[0.0, 1.0, 0.0]]))[0]
        np.testing.assert_allclose(E[0], 7 * np.pi / 9 * L_zenith, rtol=1e-4)
    coefficients = envmaps.sh_project_samples(L_grid, solid_angle, d)
    order2_error = np.abs(np.maximum(envmaps.sh_irradiance(coefficients, normals), 0) - E).max()
    L = shade(scene, 3.0 * normals, -normals, wavelengths)
    np.testing.assert_allclose(L * np.pi / RHO, E, rtol=0,
                               atol=order2_error + DISCRETIZATION * E.max())


def test_reflection_term_is_the_map_at_the_mirror_direction(variant_rgb):
    """A mirror-like phong sphere (diffuse 0, exponent 1000) seen by orthographic rays
    reflects rho_s L_env(r), the map looked up at r = 2 (n . v) n - v."""
    rng = np.random.default_rng(SEED)
    xy = rng.uniform(-0.9, 0.9, size=(4 * N_NORMALS, 2))
    xy = xy[np.hypot(xy[:, 0], xy[:, 1]) < 0.95][:N_NORMALS]
    n = np.column_stack([xy, np.sqrt(1 - (xy ** 2).sum(axis=1))])
    v = np.array([0.0, 0.0, 1.0])
    r = 2 * (n @ v)[:, None] * n - v
    origins = np.column_stack([xy, np.full(len(xy), 5.0)])
    directions = np.broadcast_to(-v, origins.shape)

    scene = map_scene({"type": "local", "environment": {"type": "ref", "id": "sky"}},
                      {"type": "phong", "diffuse_reflectance": 0.0,
                       "specular_reflectance": RHO_S, "exponent": 1000.0})
    L = shade(scene, origins, np.ascontiguousarray(directions))
    expected = RHO_S * bilinear_lookup(read_map(), r)
    np.testing.assert_allclose(L, expected, rtol=RTOL_LOOKUP, atol=1e-6)


def test_other_bsdfs_reflect_no_environment(variant_rgb):
    """A BSDF without a specular_reflectance attribute (diffuse) gets no reflection term:
    with `environment` alone and the environment left out of the light sum, black."""
    scene = map_scene({"type": "local", "environment": {"type": "ref", "id": "sky"}},
                      {"type": "diffuse", "reflectance": RHO})
    normals = random_normals(16)
    assert np.all(shade(scene, 3.0 * normals, -normals) == 0.0)


def test_constant_environment_irradiance_is_pi_L(variant):
    """ambient="environment" under a `constant` environment of radiance L gives exactly
    what ambient = pi L gives (the irradiance of a uniform sphere of radiance L is pi L),
    in RGB and spectral variants."""
    L_sky = 0.7
    normals = random_normals(64)
    wavelengths = (405.0, 512.5, 600.0, 777.0)

    def radiance(integrator, with_sky):
        scene = {"type": "scene", "integrator": integrator,
                 "sphere": {"type": "sphere", "bsdf": {"type": "diffuse", "reflectance": RHO}}}
        if with_sky:
            scene["sky"] = {"type": "constant",
                            "radiance": {"type": "uniform", "value": L_sky}}
        return shade(mi.load_dict(scene), 3.0 * normals, -normals,
                     wavelengths if mi.is_spectral else None)

    from_environment = radiance({"type": "local", "ambient": "environment"}, True)
    from_constant = radiance(
        {"type": "local", "ambient": {"type": "uniform", "value": np.pi * L_sky}}, False)
    np.testing.assert_allclose(from_environment, from_constant, rtol=RTOL_EXACT)
    np.testing.assert_allclose(from_environment, RHO * L_sky, rtol=RTOL32)


@pytest.mark.parametrize("shading", ["flat", "gouraud", "phong"])
def test_constant_environment_in_every_shading_and_variant(any_variant, shading):
    """Under a constant environment of radiance L a phong mesh sphere (rho, rho_s) with
    both terms reflects rho L + rho_s L at every front-facing hit, whatever the normal
    (flat, per vertex or interpolated), in every variant (mono, polarized too)."""
    L_sky = 0.7
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "local", "shading": shading, "ambient": "environment",
                       "environment": {"type": "ref", "id": "sky"}},
        "sky": {"type": "constant", "radiance": {"type": "uniform", "value": L_sky}},
        "sphere": {"type": "obj", "filename": str(MAP.parents[1] / "meshes" / "sphere_low.obj"),
                   "bsdf": {"type": "phong", "diffuse_reflectance": RHO,
                            "specular_reflectance": RHO_S}},
    })
    normals = random_normals(64)
    L = shade(scene, 3.0 * normals, -normals,
              (405.0, 512.5, 600.0, 777.0) if mi.is_spectral else None)
    np.testing.assert_allclose(L, (RHO + RHO_S) * L_sky, rtol=RTOL32)


def write_scene(tmp_path, integrator, emitter=""):
    path = tmp_path / "scene.xml"
    path.write_text(f"""<scene version="3.0.0">
    <integrator type="local">{integrator}</integrator>
    <sensor type="orthographic"><film type="hdrfilm">
        <integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    {emitter}
    <shape type="sphere"/>
</scene>""")
    return path


def test_ambient_environment_without_environment_is_refused(tmp_path, variant_rgb):
    """ambient="environment" in a scene without an environment emitter: one line naming the
    scene and the parameter, at load."""
    path = write_scene(tmp_path, '<string name="ambient" value="environment"/>',
                       '<emitter type="point"><point name="position" x="0" y="2" z="0"/>'
                       '</emitter>')
    with pytest.raises(ParameterError, match="local: parameter 'ambient'") as error:
        load_scene(path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)


#: More bad input in tests/plugins/test_local.py (BAD_PARAMETERS).
BAD_PARAMETERS = [
    ("environment", {"environment": {"type": "directional"}}),
    ("environment", {"environment": {"type": "diffuse"}}),
    ("environment", {"environment": "sky"}),
]


@pytest.mark.parametrize("name, params", BAD_PARAMETERS,
                         ids=[f"{name}-{i}" for i, (name, _) in enumerate(BAD_PARAMETERS)])
def test_bad_environment_parameters_fail_at_load(variant_rgb, name, params):
    """An unknown ambient string, or an environment that is no environment emitter, is
    refused at load, naming the parameter."""
    with pytest.raises(Exception, match=f"local: parameter '{name}'"):
        mi.load_dict({"type": "local", **params})


def test_bad_ambient_string_in_a_scene_file_is_one_line(tmp_path, variant_rgb):
    """Through spectrace's scene loader the unknown ambient string is one ParameterError
    line naming the scene and the parameter."""
    path = write_scene(tmp_path, '<string name="ambient" value="sky"/>')
    with pytest.raises(ParameterError, match="local: parameter 'ambient'") as error:
        load_scene(path)
    assert str(path) in str(error.value) and "\n" not in str(error.value)
