"""Tests of the ``illuminance`` integrator (``plugins/integrators/illuminance.py``): lux of
delta lights against the inverse-square cosine law pixel by pixel, every light summed,
shadows, area lights and an environment against their closed-form illuminance,
interreflections in an integrating sphere, RGB against spectral, the work plane, the
reference page and the one-line errors.

Oracles: closed forms written here; the points seen through the pixels come from
Mitsuba's ``aov`` integrator; the integral of V from colour-science.
"""

from __future__ import annotations

import emitter_checks as checks
import numpy as np
import pytest

#: A float32 render against a float64 formula (RGB, mono: every sample exact).
RTOL_EXACT = 2e-4
#: Delta lights at one sample per pixel in every variant (the exact direct path: no
#: wavelength sampling) against their closed forms.
RTOL_DIRECT = 1e-5
#: Spectral variants with flat spectra: every sample exact up to Mitsuba's tabulated V
#: (its trapezoidal integral against colour-science's 1 nm sum).
RTOL_FLAT_SPECTRAL = 1e-3
#: Monte Carlo estimates of area lights and environments from AREA_SPP samples (measured
#: error 0.2 %).
RTOL_AREA = 1e-2
AREA_SPP = 4096
#: The uniform sky without MIS (``shadows`` off): uniform sphere sampling, relative spread
#: 1.3 per sample, measured 0.6 % over seeds at SKY_SPP: five times that.
SKY_SPP = 65536
RTOL_SKY_PLAIN = 3e-2
#: A sphere of albedo RHO_SPHERE with no bounce limit (Russian roulette; measured 0.1 %).
RTOL_ROULETTE = 2e-2
#: Lux of a light of a non-flat spectrum in spectral variants, AGREE_SPP samples of four
#: wavelengths drawn from V (measured spread 0.1 %), against RGB.
RTOL_AGREE = 5e-3
AGREE_SPP = 1024
#: Pixels this close (m) to a shadow or occluder edge are left out of exact comparisons.
EDGE_MARGIN = 0.08
KM = 683.0
RES = 16
HEIGHT = 1.0
RHO_SPHERE = 0.5


def v_integral() -> float:
    """integral V(lambda) dlambda (nm) over 360-830 nm, from colour-science: the
    photometric integral of the flat spectrum 1 in spectral variants and of the grey 1 in
    RGB and mono variants (a colour stands for the spectra of the same film Y)."""
    import colour

    V = colour.colorimetry.SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    return float(np.sum(V[np.arange(360.0, 831.0)]))


def flat(value: float = 1.0) -> dict:
    return {"type": "uniform", "value": value}


def floor_scene(lights: dict, integrator: dict | None = None, res: int = RES,
                spp: int = 1) -> dict:
    """A floor y = 0 (10 m square) seen straight from above by an orthographic camera over
    2 HALF_WIDTH metres, one sample at each pixel centre (spp 1)."""
    scene = checks.plane_scene({"type": "point", "position": [0, 1, 0]},
                               integrator or {"type": "illuminance"}, spp=spp, res=res)
    del scene["light"]
    scene.update(lights)
    return scene


def render(scene: dict, seed: int = 0) -> np.ndarray:
    import mitsuba as mi

    return np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)


def lux_of(image: np.ndarray) -> np.ndarray:
    """The AOV channels (lux, measured) are the film's last two."""
    return image[..., -2]


def floor_points(res: int = RES) -> np.ndarray:
    """World positions at the pixel centres, (H, W, 3), from Mitsuba's ``aov``."""
    return checks.positions(res=res)


def point_law(p: np.ndarray, light, intensity: float, normal=(0.0, 1.0, 0.0)) -> np.ndarray:
    """I cos(theta) / r^2 at the points p (..., 3) on a surface of ``normal``."""
    v = np.asarray(light, dtype=np.float64) - p
    r = np.linalg.norm(v, axis=-1)
    return intensity * np.maximum(v @ np.asarray(normal), 0.0) / r**3


def meter(objects: dict, integrator: dict, spp: int, point=(0.0, 0.0), seed: int = 1) -> float:
    """Lux at the floor point (x, z) seen by a radiancemeter looking straight down."""
    import mitsuba as mi

    scene = floor_scene(objects, integrator)
    scene["sensor"] = {
        "type": "radiancemeter", "origin": [point[0], 0.5, point[1]], "direction": [0, -1, 0],
        "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": spp},
    }
    image = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)
    return float(lux_of(image).ravel()[0])


# -- delta lights -----------------------------------------------------------------------------

def test_every_delta_light_follows_the_inverse_square_cosine_law(any_variant):
    """Scene units are metres: a 100 cd ``pointlight`` h = 1 m above the floor gives
    100 h / r^3 lux at every pixel, and Mitsuba's ``point`` of radiant intensity I_e beside
    it adds K_m integral(V) I_e h' / r'^3 (a flat spectrum): the two are summed, never
    sampled one at a time (every sample exact), in every variant."""

    second, I_e = [0.6, 2.0, -0.4], 0.2
    lights = {
        "light": {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
                  "luminous_intensity": 100.0, "spectrum": flat()},
        "other": {"type": "point", "position": second, "intensity": flat(I_e)},
    }
    lux = lux_of(render(floor_scene(lights)))
    p = floor_points()
    expected = point_law(p, [0.0, HEIGHT, 0.0], 100.0) + \
        point_law(p, second, KM * v_integral() * I_e)
    np.testing.assert_allclose(lux, expected, rtol=RTOL_DIRECT)
    centre = np.argmin(np.linalg.norm(p[..., [0, 2]], axis=-1))
    assert expected.ravel()[centre] > 90.0  # the pixels reach the foot of the light


D65 = {"type": "d65"}
TABULATED = {"type": "spectrum", "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}


@pytest.mark.parametrize("spectrum", [TABULATED, D65], ids=["tabulated", "d65"])
def test_delta_lights_are_exact_at_one_sample(any_variant, spectrum):
    """The illuminance of delta lights has no random part: at one sample per pixel, in
    every variant, a 100 cd ``pointlight`` of a non-flat spectrum 1 m above the floor
    gives 100 h / r^3 (100.00 lx at its foot), a 100 cd ``spotlight`` beside it its
    on-axis 100 cd inside the penumbra, and Mitsuba's ``spot`` (I_e inside its beam
    width) and ``directional`` (irradiance E_e normal to it at 60 degrees from the
    vertical) K_m integral(V) I_e h / r^3 and K_m integral(V) E_e cos 60 (flat spectra),
    all summed."""
    T = checks.transform()
    spot_at, I_e, E_e = [0.5, 1.5, -0.3], 0.1, 0.05
    d = np.array([np.sin(np.pi / 3), -np.cos(np.pi / 3), 0.0])
    lights = {
        "light": {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
                  "luminous_intensity": 100.0, "spectrum": spectrum},
        "spotlight": {"type": "spotlight", "luminous_intensity": 100.0, "spectrum": spectrum,
                      "umbra_angle": 80.0, "penumbra_angle": 75.0,
                      "to_world": T.look_at([-0.4, 2.0, 0.2], [-0.4, 0.0, 0.2], [0, 0, 1])},
        "spot": {"type": "spot", "intensity": flat(I_e), "cutoff_angle": 85.0,
                 "beam_width": 80.0,
                 "to_world": T.look_at(spot_at, [spot_at[0], 0.0, spot_at[2]], [0, 0, 1])},
        "sun": {"type": "directional", "direction": d.tolist(), "irradiance": flat(E_e)},
    }
    lux = lux_of(render(floor_scene(lights)))
    p = floor_points()
    scale = KM * v_integral()
    expected = (point_law(p, [0.0, HEIGHT, 0.0], 100.0) + point_law(p, [-0.4, 2.0, 0.2], 100.0)
                + point_law(p, spot_at, scale * I_e) + scale * E_e * 0.5)
    np.testing.assert_allclose(lux, expected, rtol=RTOL_DIRECT)


def test_hundred_candela_at_one_metre_read_100_lux_at_every_pixel(any_variant):
    """The issue's case: 100 cd of a non-flat spectrum at the centre of a sphere of radius
    1 m, seen from its centre at one sample per pixel (a jittered sampler: random
    wavelengths in spectral variants), reads 100.00 lx at every pixel: min = max = 100
    to RTOL_DIRECT, U0 = 1."""
    T = checks.transform()
    scene = {
        "type": "scene", "integrator": {"type": "illuminance"},
        "sensor": {"type": "perspective", "fov": 90,
                   "to_world": T.look_at([0, 0, 0], [0, 0, 1], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 16, "height": 16,
                            "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": 1}},
        "sphere": {"type": "sphere", "radius": 1.0, "flip_normals": True},
        "light": {"type": "pointlight", "position": [0, 0, 0], "luminous_intensity": 100.0,
                  "spectrum": TABULATED},
    }
    lux = lux_of(render(scene, seed=7))
    np.testing.assert_allclose([lux.min(), lux.max()], 100.0, rtol=RTOL_DIRECT)


def test_ieslight_is_exact_at_one_sample(tmp_path):
    """A real-looking luminaire file (scenes/luminaires/wallwasher.ies, asymmetric), 2 m
    above the floor, at one sample per pixel: the spectral variant's lux equal the RGB
    variant's (where every sample is exact) to RTOL_DIRECT, and both the file's
    I(gamma, C) cos / r^2. The point law: ``opening`` 'point' (the file's 0.1 x 0.3 m
    opening would be sampled, not exact)."""
    from spectrace.photometry import read_photometry
    from spectrace.scenes import FOLDER

    import spectrace

    filename = str(FOLDER / "luminaires" / "wallwasher.ies")
    lux = {}
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        spectrace.set_variant(variant)
        T = checks.transform()
        light = {"light": {"type": "ieslight", "filename": filename, "spectrum": TABULATED,
                           "opening": "point",
                           "to_world": T.look_at([0, 2, 0], [0, 0, 0], [0, 0, 1])}}
        lux[variant] = lux_of(render(floor_scene(light)))
    np.testing.assert_allclose(lux["llvm_ad_spectral"], lux["llvm_ad_rgb"], rtol=RTOL_DIRECT,
                               atol=RTOL_DIRECT * lux["llvm_ad_rgb"].max())
    # the light frame: local x = world x, local y = world z, local z = world -y
    p = floor_points()
    v = p - np.array([0.0, 2.0, 0.0])
    r = np.linalg.norm(v, axis=-1)
    d = v / r[..., None]
    gamma = np.degrees(np.arccos(np.clip(-d[..., 1], -1, 1)))
    c = np.degrees(np.arctan2(-d[..., 2], d[..., 0])) % 360.0
    expected = read_photometry(filename).intensity(gamma, c) * (-d[..., 1]) / r**2
    np.testing.assert_allclose(lux["llvm_ad_rgb"], expected, rtol=RTOL_EXACT,
                               atol=RTOL_EXACT * expected.max())
    assert expected.max() > 10.0


def test_shadows(variant_rgb):
    """A square occluder halfway between a light and the floor casts its shadow: the floor
    points whose segment to the light crosses it get 0 lux, the others I h / r^3; with
    ``shadows`` false every point gets I h / r^3."""
    half = 0.3
    lights = {
        "light": {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
                  "luminous_intensity": 100.0},
        "occluder": {"type": "rectangle", "to_world": checks.transform().translate(
            [0.5, 0.5, 0.0]).rotate([1, 0, 0], 90).scale(half)},
    }
    p = floor_points()
    # where the segment from p to the light crosses y = 0.5; the occluder's square there
    q = p + (0.5 - p[..., 1:2]) / (HEIGHT - p[..., 1:2]) * (np.array([0.0, HEIGHT, 0.0]) - p)
    distance = np.maximum(np.abs(q[..., 0] - 0.5), np.abs(q[..., 2])) - half
    # the occluder hides a part of the floor from the camera too
    seen = (np.abs(p[..., 0] - 0.5) > half + EDGE_MARGIN) | (np.abs(p[..., 2]) > half +
                                                              EDGE_MARGIN)
    clear = (np.abs(distance) > EDGE_MARGIN) & seen
    law = point_law(p, [0.0, HEIGHT, 0.0], 100.0)
    expected = np.where(distance < 0, 0.0, law)
    lux = lux_of(render(floor_scene(lights)))
    assert (distance[clear] < 0).sum() > 4 and (distance[clear] > 0).sum() > 4
    np.testing.assert_allclose(lux[clear], expected[clear], rtol=RTOL_EXACT)
    lux = lux_of(render(floor_scene(lights, {"type": "illuminance", "shadows": False})))
    np.testing.assert_allclose(lux[seen], law[seen], rtol=RTOL_EXACT)


# -- area lights and environments -----------------------------------------------------------

def disk_on_axis(L, R, h):
    """Lambertian disk of radiance L and radius R, at height h above a parallel surface:
    E = pi L R^2 / (h^2 + R^2) on its axis."""
    return np.pi * L * R**2 / (h**2 + R**2)


def rectangle_corner(L, a, b, h):
    """Lambertian rectangle a x b of radiance L parallel to the surface at height h, the
    point under a corner: E = pi L F with the view factor
    F = (1 / 2 pi) [A / sqrt(1 + A^2) atan(B / sqrt(1 + A^2)) + (A <-> B)], A = a/h, B = b/h
    (Howell, A Catalog of Radiation Heat Transfer Configuration Factors, B-3)."""
    A, B = a / h, b / h
    F = (A / np.sqrt(1 + A**2) * np.arctan(B / np.sqrt(1 + A**2))
         + B / np.sqrt(1 + B**2) * np.arctan(A / np.sqrt(1 + B**2))) / (2 * np.pi)
    return np.pi * L * F


@pytest.mark.parametrize("shadows", [True, False])
def test_area_lights_and_environment_match_closed_forms(variant, shadows):
    """Emitter sampling with multiple importance sampling (``shadows`` on) or alone
    (``shadows`` off) gives the closed-form illuminance of a downward Lambertian disk on
    its axis, of a rectangle above its corner, and pi L of a uniform sky above an open
    floor, in lux: K_m integral(V) E for a flat radiance spectrum."""
    T = checks.transform()
    L, R, h = 0.5, 0.5, 1.0
    a, b, h_rect = 0.8, 0.4, 0.7
    integrator = {"type": "illuminance", "shadows": shadows}
    scale = KM * v_integral()
    down = T.rotate([1, 0, 0], 90)  # a disk's or rectangle's normal +z -> -y
    disk = {"disk": {"type": "disk", "to_world": T.translate([0, h, 0]) @ down.scale(R),
                     "emitter": {"type": "area", "radiance": flat(L)}}}
    np.testing.assert_allclose(meter(disk, integrator, AREA_SPP),
                               scale * disk_on_axis(L, R, h), rtol=RTOL_AREA)
    # rectangle [0, a] x [0, b] in (x, z) at height h_rect: the point (0, 0) under a corner
    rectangle = {"rect": {"type": "rectangle", "to_world": T.translate([a / 2, h_rect, b / 2])
                          @ down.scale([a / 2, b / 2, 1]),
                          "emitter": {"type": "area", "radiance": flat(L)}}}
    np.testing.assert_allclose(meter(rectangle, integrator, AREA_SPP),
                               scale * rectangle_corner(L, a, b, h_rect), rtol=RTOL_AREA)
    sky = {"sky": {"type": "constant", "radiance": flat(L)}}
    np.testing.assert_allclose(meter(sky, integrator, SKY_SPP), scale * np.pi * L,
                               rtol=RTOL_AREA if shadows else RTOL_SKY_PLAIN)


def test_interreflections_in_an_integrating_sphere(variant):
    """Inside a diffuse sphere of radius R and albedo rho, with a light of flux Phi at its
    centre, every wall point receives E_0 = Phi / (4 pi R^2) directly and, since any point
    sees every area element of the sphere alike, rho^k E_0 after k reflections: E =
    E_0 (1 + rho + ... + rho^(K-1)) with ``max_depth`` K, E_0 / (1 - rho) without limit
    (integrating-sphere theory; Goebel 1967, J. Opt. Soc. Am. 57)."""
    T = checks.transform()
    R, flux = 1.5, 2000.0
    E0 = flux / (4 * np.pi * R**2)
    scene = {
        "type": "scene",
        "sensor": {"type": "perspective", "fov": 60,
                   "to_world": T.look_at([0, 0, 0], [0, 0, 1], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 4, "height": 4,
                            "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": 64}},
        "sphere": {"type": "sphere", "radius": R, "flip_normals": True,
                   "bsdf": {"type": "diffuse", "reflectance": flat(RHO_SPHERE)}},
        "light": {"type": "pointlight", "position": [0, 0, 0], "luminous_flux": flux,
                  "spectrum": flat()},
    }
    for K in (1, 2, 4):
        scene["integrator"] = {"type": "illuminance", "max_depth": K}
        expected = E0 * sum(RHO_SPHERE**k for k in range(K))
        np.testing.assert_allclose(lux_of(render(scene)), expected, rtol=RTOL_FLAT_SPECTRAL,
                                   err_msg=f"max_depth {K}")
    scene["integrator"] = {"type": "illuminance", "max_depth": -1}
    np.testing.assert_allclose(lux_of(render(scene)).mean(), E0 / (1 - RHO_SPHERE),
                               rtol=RTOL_ROULETTE)


# -- variants -------------------------------------------------------------------------------

def test_rgb_and_spectral_variants_agree():
    """The same photometric scale in every variant: a 100 cd pointlight of a tabulated,
    non-flat spectrum and a D65 spotlight of 100 cd measured in llvm_ad_rgb (K_m Y(E)) and
    llvm_ad_spectral (K_m integral V E, wavelengths drawn from V) give the same lux, the
    expected 100 h / r^3 + 100 at a point beside the foot of the pointlight."""
    import spectrace

    x, z = 0.4, 0.3
    r = np.sqrt(x**2 + z**2 + HEIGHT**2)
    lux = {}
    for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
        spectrace.set_variant(variant)
        T = checks.transform()
        lights = {
            "light": {"type": "pointlight", "position": [0.0, HEIGHT, 0.0],
                      "luminous_intensity": 100.0,
                      "spectrum": {"type": "spectrum",
                                   "value": [(400.0, 1.0), (550.0, 3.0), (700.0, 2.0)]}},
            "spot": {"type": "spotlight", "luminous_intensity": 100.0,
                     "to_world": T.look_at([x, HEIGHT, z], [x, 0.0, z], [0, 0, 1])},
        }
        lux[variant] = meter(lights, {"type": "illuminance"}, AGREE_SPP, point=(x, z))
    np.testing.assert_allclose(lux["llvm_ad_rgb"], 100.0 * HEIGHT / r**3 + 100.0,
                               rtol=RTOL_EXACT)
    np.testing.assert_allclose(lux["llvm_ad_spectral"], lux["llvm_ad_rgb"], rtol=RTOL_AGREE)


# -- the work plane -------------------------------------------------------------------------

def test_work_plane(variant_rgb):
    """With ``plane_point`` (0, 0.5, 0) and ``plane_normal`` (0, 1, 0) each camera ray
    measures where it crosses the plane y = 0.5: I h / r^3 with h = 0.5, the points of the
    floor seen from above lifted to the plane. A square occluder above the plane hides it
    from the camera there (``measured`` 0, no lux) and shadows the plane points whose
    segment to the light crosses it."""
    y_plane, y_occluder, half = 0.5, 0.75, 0.3
    light = [0.0, HEIGHT, 0.0]
    lights = {
        "light": {"type": "pointlight", "position": light, "luminous_intensity": 100.0},
        "occluder": {"type": "rectangle", "to_world": checks.transform().translate(
            [0.5, y_occluder, 0.0]).rotate([1, 0, 0], 90).scale(half)},
    }
    integrator = {"type": "illuminance", "plane_point": [0.0, y_plane, 0.0],
                  "plane_normal": [0.0, 2.0, 0.0]}  # any length
    image = render(floor_scene(lights, integrator))
    p = floor_points()
    p[..., 1] = y_plane
    hidden_distance = np.maximum(np.abs(p[..., 0] - 0.5), np.abs(p[..., 2])) - half
    s = (y_occluder - y_plane) / (HEIGHT - y_plane)
    q = p + s * (np.array(light) - p)
    shadow_distance = np.maximum(np.abs(q[..., 0] - 0.5), np.abs(q[..., 2])) - half
    hidden = hidden_distance < 0
    sure = np.abs(hidden_distance) > EDGE_MARGIN  # surely hidden or surely seen
    lit = ~hidden & sure & (np.abs(shadow_distance) > EDGE_MARGIN)
    shadowed = shadow_distance < 0
    assert (hidden & sure).sum() >= 4 and (shadowed & lit).sum() >= 4 and (~shadowed & lit).any()
    measured = image[..., -1]
    np.testing.assert_array_equal(measured[sure], np.where(hidden, 0.0, 1.0)[sure])
    assert np.all(lux_of(image)[hidden & sure] == 0.0)
    expected = np.where(shadowed, 0.0, point_law(p, light, 100.0))
    np.testing.assert_allclose(lux_of(image)[lit], expected[lit], rtol=RTOL_EXACT)


def test_rays_that_hit_nothing_measure_nothing(variant_rgb):
    """Rays that hit nothing give 0 lux and ``measured`` 0, also under a sky; rays that
    miss a work plane (crossing it behind the camera) too."""
    lights = {"sky": {"type": "constant", "radiance": 1.0}}
    scene = floor_scene(lights)
    del scene["plane"]
    image = render(scene)
    assert np.all(image[..., -2:] == 0.0)
    scene = floor_scene({"light": {"type": "pointlight", "position": [0, 1, 0]}},
                        {"type": "illuminance", "plane_point": [0.0, 9.0, 0.0],
                         "plane_normal": [0.0, 1.0, 0.0]})  # above the camera at y = 8
    image = render(scene)
    assert np.all(image[..., -2:] == 0.0)


# -- reference page and errors ----------------------------------------------------------------

def test_reference_page(variant_rgb):
    """The module docstring follows the one reference-page format."""
    from spectrace.plugins.integrators import illuminance

    table = checks.parse_reference_page(illuminance.__doc__, "illuminance")
    assert table["max_depth"]["default"] == "1" and table["shadows"]["default"] == "true"
    assert table["plane_point"]["unit"] == "m"


INVALID = [
    ({"max_depth": 0}, "'max_depth' must be >= 1, or -1"),
    ({"max_depth": -2}, "'max_depth' must be >= -1"),
    ({"max_depth": 2.0}, "'max_depth' must be an integer"),
    ({"shadows": "no"}, "'shadows' must be a boolean"),
    ({"plane_point": [0, 1, 0]}, "'plane_point' needs parameter 'plane_normal'"),
    ({"plane_normal": [0, 1, 0]}, "'plane_normal' needs parameter 'plane_point'"),
    ({"plane_point": [0, 1, 0], "plane_normal": [0, 0, 0]},
     "'plane_normal' must be a non-zero vector"),
]


@pytest.mark.parametrize(("params", "message"), INVALID)
def test_invalid_parameters_fail_in_one_line(variant_rgb, params, message):
    """Bad parameters fail at load with one line naming the plugin and the parameter."""
    import mitsuba as mi

    spec = {"type": "illuminance"}
    for name, value in params.items():
        spec[name] = mi.ScalarPoint3f(value) if isinstance(value, list) else value
    with pytest.raises(Exception) as info:
        mi.load_dict(spec)
    line = next(l for l in str(info.value).splitlines() if "illuminance: " in l)
    assert message in line, line
