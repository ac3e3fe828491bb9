"""Tests of the ``local`` integrator (plugins/integrators/local.py).

Oracles: Mitsuba's ``direct`` integrator (emitter samples only), closed-form radiance of
a diffuse surface lit by a point or directional light, the fog formulas of OpenGL
written out here, rho/pi * E for the ambient term.
"""

from __future__ import annotations

from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

SCENES = Path(__file__).resolve().parents[2] / "scenes"

#: Relative tolerance between two float32 computations of the same radiance.
RTOL = 2e-4
#: Absolute floor of the comparisons (radiance units).
ATOL = 1e-6
#: Fraction of pixels allowed to differ between local and direct: shadow-ray origins
#: differ (bias vs Mitsuba's automatic offset), which moves grazing shadow edges.
EDGE_FRACTION = 0.02
#: Relative tolerance of Monte Carlo means (area light, one emitter sample per pixel).
MC_RTOL = 0.03

RHO = 0.5  # diffuse reflectance of the test surfaces
INTENSITY = 20.0  # W/sr of the point lights
IRRADIANCE = 3.0  # W/m^2 of the directional lights


def uniform(value):
    """A spectrum of the same value at every wavelength (RGB: grey), in any variant."""
    return {"type": "uniform", "value": value}


def to_numpy(image):
    return np.array(image, dtype=np.float64)


def render(scene, integrator, seed=0, spp=None):
    integrator = mi.load_dict(integrator) if isinstance(integrator, dict) else integrator
    return to_numpy(mi.render(scene, integrator=integrator, seed=seed, spp=spp or 0))


def camera(origin, target, res, spp=1):
    return {
        "type": "perspective",
        "fov": 45,
        "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target, up=[0, 1, 0]),
        "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": spp},
    }


def spot_frame():
    return mi.ScalarTransform4f().look_at(origin=[1.5, 4.0, 2.0], target=[0, 0.5, 0], up=[0, 1, 0])


LIGHTS = {
    "point": lambda: {"type": "point", "position": [2, 4, 2], "intensity": uniform(INTENSITY)},
    "spot": lambda: {
        "type": "spot",
        "to_world": spot_frame(),
        "intensity": uniform(INTENSITY),
        "cutoff_angle": 35,
        "beam_width": 20,
    },
    "directional": lambda: {
        "type": "directional",
        "direction": [-0.4, -1, -0.3],
        "irradiance": uniform(IRRADIANCE),
    },
    "pointlight": lambda: {
        "type": "pointlight",
        "position": [2, 4, 2],
        "intensity": uniform(INTENSITY),
    },
    "spotlight": lambda: {
        "type": "spotlight",
        "to_world": spot_frame(),
        "intensity": uniform(INTENSITY),
        "umbra_angle": 35,
        "penumbra_angle": 20,
    },
}


def showcase(lights: dict, res=24):
    """Spheres (analytic and a coarse mesh with vertex normals) on a floor."""
    shiny = {"type": "phong", "diffuse_reflectance": uniform(0.4), "exponent": 20.0}
    scene = {
        "type": "scene",
        "sensor": camera([0, 3, 6], [0, 0.6, 0], res),
        "floor": {
            "type": "rectangle",
            "bsdf": {"type": "diffuse", "reflectance": uniform(RHO)},
            "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(5),
        },
        "ball": {"type": "sphere", "center": [-1.1, 1, 0], "radius": 1, "bsdf": shiny},
        "mesh": {
            "type": "obj",
            "filename": str(SCENES / "meshes" / "sphere_low.obj"),
            "to_world": mi.ScalarTransform4f().translate([1.1, 1, 0]),
            "bsdf": {"type": "roughconductor", "alpha": 0.3},
        },
    }
    scene.update(lights)
    return mi.load_dict(scene)


DIRECT = {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}


def assert_images_match(a, b):
    differs = ~np.isclose(a, b, rtol=RTOL, atol=ATOL)
    assert np.mean(np.any(differs, axis=-1)) <= EDGE_FRACTION


@pytest.mark.parametrize("light", sorted(LIGHTS))
def test_phong_shading_equals_direct_lighting(variant, light):
    """Without ambient and fog, local illumination with interpolated normals and shadows
    is exactly Mitsuba's direct lighting from delta lights (emitter sampling only)."""
    emitter = LIGHTS[light]()
    scene = showcase({"light": emitter})
    local = render(scene, {"type": "local", "shading": "phong", "shadows": True})
    direct = render(scene, DIRECT)
    unshadowed = render(scene, {"type": "local", "shadows": False})
    assert np.mean(local) > 0.01
    # shadows are really tested: switching them off changes many pixels
    assert np.mean(np.any(~np.isclose(local, unshadowed, rtol=RTOL, atol=ATOL), axis=-1)) > 0.03
    assert_images_match(local, direct)


def test_lights_add_up(variant):
    """The model sums the lights: local with two lights equals the sum of direct
    lighting from each light alone."""
    both = showcase({"a": LIGHTS["point"](), "b": LIGHTS["spot"]()})
    local = render(both, {"type": "local"})
    direct = render(showcase({"a": LIGHTS["point"]()}), DIRECT) + render(
        showcase({"b": LIGHTS["spot"]()}), DIRECT
    )
    assert_images_match(local, direct)


# -- direct calls of Local.sample on chosen rays -------------------------------------

WAVELENGTHS = (450.0, 520.0, 580.0, 650.0)


def cast(integrator, scene, origins, targets):
    """Radiance (numpy, rays x channels) and validity of rays from origins to targets."""
    origins, targets = np.atleast_2d(origins), np.atleast_2d(targets)
    n = max(len(origins), len(targets))
    origins = np.broadcast_to(origins, (n, 3))
    direction = targets - origins
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    ray = dr.zeros(mi.RayDifferential3f, n)
    ray.o = mi.Point3f(*(mi.Float(c) for c in origins.T.astype(np.float32)))
    ray.d = mi.Vector3f(*(mi.Float(c) for c in direction.T.astype(np.float32)))
    ray.maxt = dr.inf
    if mi.is_spectral:
        ray.wavelengths = mi.UnpolarizedSpectrum(*WAVELENGTHS)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(0, n)
    L, valid, _ = integrator.sample(scene, sampler, ray)
    L = mi.unpolarized_spectrum(L)  # the [0, 0] entry of a Mueller matrix when polarized
    return np.array(L, dtype=np.float64).T.reshape(n, -1), np.array(valid, dtype=bool)


QUAD = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float64)
QUAD_FACES = np.array([[0, 1, 2], [0, 2, 3]])
#: Vertex normals tilted away from the face normal +z, differently at each vertex.
QUAD_NORMALS = np.array([[-0.3, -0.2, 1], [0.4, -0.1, 1], [0.2, 0.35, 1], [-0.25, 0.3, 1]])
QUAD_NORMALS /= np.linalg.norm(QUAD_NORMALS, axis=1, keepdims=True)
EYE = np.array([0.2, 0.3, 3.0])


def quad_mesh():
    """Two triangles in the plane z = 0 with tilted vertex normals, diffuse rho = RHO."""
    mesh = mi.Mesh("quad", 4, 2, has_vertex_normals=True, props=mi.Properties())
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(QUAD.astype(np.float32).ravel())
    params["vertex_normals"] = mi.Float(QUAD_NORMALS.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(QUAD_FACES.astype(np.uint32).ravel())
    params.update()
    return mesh


def quad_scene(light):
    mesh = quad_mesh()
    mesh.set_bsdf(mi.load_dict({"type": "diffuse", "reflectance": uniform(RHO)}))
    return mi.load_dict({"type": "scene", "quad": mesh, "light": light})


def random_barycentrics(rng, n):
    b = rng.dirichlet(np.ones(3), size=n)
    return np.clip(b, 0.02, None) / np.clip(b, 0.02, None).sum(axis=1, keepdims=True)


def test_gouraud_interpolates_vertex_radiance(any_variant, rng):
    """Gouraud shading: the radiance at a point of a triangle is the barycentric blend of
    the closed-form radiance rho/pi * I cos(theta_k) / r_k^2 at its three vertices, with
    the vertex normals."""
    light_position = np.array([0.7, -0.4, 1.5])
    scene = quad_scene(
        {"type": "point", "position": light_position.tolist(), "intensity": uniform(INTENSITY)}
    )
    to_light = light_position - QUAD
    r = np.linalg.norm(to_light, axis=1)
    cos = np.maximum(np.sum(QUAD_NORMALS * to_light, axis=1) / r, 0.0)
    vertex_L = RHO / np.pi * INTENSITY * cos / r**2
    assert np.ptp(vertex_L) > 0.1 * vertex_L.max()  # the blend is not trivial

    integrator = mi.load_dict({"type": "local", "shading": "gouraud"})
    for face in QUAD_FACES:
        b = random_barycentrics(rng, 64)
        points = b @ QUAD[face]
        L, valid = cast(integrator, scene, EYE, points)
        assert valid.all()
        expected = b @ vertex_L[face]
        np.testing.assert_allclose(
            L, np.repeat(expected[:, None], L.shape[1], axis=1), rtol=RTOL, atol=ATOL
        )


def test_gouraud_glossy_uses_vertex_view_directions(variant, rng):
    """Gouraud shading of a glossy BSDF: each vertex is shaded with its own normal and
    its own view direction towards the camera; the oracle evaluates Mitsuba's rough
    plastic at the vertices from a hand-built shading frame, then blends."""
    light_position = np.array([-0.5, 0.3, 1.2])
    glossy = {"type": "roughplastic", "alpha": 0.3}
    mesh = quad_mesh()
    mesh.set_bsdf(mi.load_dict(glossy))
    scene = mi.load_dict(
        {
            "type": "scene",
            "quad": mesh,
            "light": {
                "type": "point",
                "position": light_position.tolist(),
                "intensity": uniform(INTENSITY),
            },
        }
    )

    def vectors(a):
        return [mi.Float(c) for c in a.T.astype(np.float32)]

    to_light, to_eye = light_position - QUAD, EYE - QUAD
    r = np.linalg.norm(to_light, axis=1)
    si = dr.zeros(mi.SurfaceInteraction3f, len(QUAD))
    si.p = mi.Point3f(*vectors(QUAD))
    si.sh_frame = mi.Frame3f(mi.Vector3f(*vectors(QUAD_NORMALS)))
    si.wi = si.to_local(dr.normalize(mi.Vector3f(*vectors(to_eye))))
    if mi.is_spectral:
        si.wavelengths = mi.Spectrum(*WAVELENGTHS)
    wo = si.to_local(mi.Vector3f(*vectors(to_light / r[:, None])))
    f = np.array(mi.load_dict(glossy).eval(mi.BSDFContext(), si, wo), dtype=np.float64).T
    vertex_L = f * INTENSITY / r[:, None] ** 2
    assert np.ptp(vertex_L) > 0.1 * vertex_L.max()

    integrator = mi.load_dict({"type": "local", "shading": "gouraud"})
    for face in QUAD_FACES:
        b = random_barycentrics(rng, 64)
        L, valid = cast(integrator, scene, EYE, b @ QUAD[face])
        assert valid.all()
        np.testing.assert_allclose(L, b @ vertex_L[face], rtol=RTOL, atol=ATOL)


def test_flat_shading_one_value_per_face(variant, rng):
    """Flat shading under a directional light: every point of a face has the value of
    the face normal, rho/pi * E * (n_face . l), whatever the vertex normals; Phong
    shading of the same mesh varies inside each face."""
    direction = np.array([-0.3, -0.2, -1.0])
    direction /= np.linalg.norm(direction)
    scene = quad_scene(
        {"type": "directional", "direction": direction.tolist(), "irradiance": uniform(IRRADIANCE)}
    )
    expected = RHO / np.pi * IRRADIANCE * float(-direction[2])  # face normal +z
    flat = mi.load_dict({"type": "local", "shading": "flat"})
    phong = mi.load_dict({"type": "local", "shading": "phong"})
    for face in QUAD_FACES:
        points = random_barycentrics(rng, 64) @ QUAD[face]
        L_flat, valid = cast(flat, scene, EYE, points)
        assert valid.all()
        np.testing.assert_allclose(L_flat, expected, rtol=RTOL)
        L_phong, _ = cast(phong, scene, EYE, points)
        assert np.ptp(L_phong) > 0.05 * expected


def test_gouraud_on_analytic_shape_falls_back_to_phong(variant):
    """A sphere shape has no vertices: Gouraud shading renders it like Phong shading."""
    scene = mi.load_dict(
        {
            "type": "scene",
            "sensor": camera([0, 0, 4], [0, 0, 0], 16),
            "ball": {"type": "sphere", "bsdf": {"type": "roughplastic"}},
            "light": LIGHTS["point"](),
        }
    )
    gouraud = render(scene, {"type": "local", "shading": "gouraud"})
    phong = render(scene, {"type": "local", "shading": "phong"})
    assert np.mean(phong) > 0.01
    np.testing.assert_allclose(gouraud, phong, rtol=RTOL, atol=ATOL)


# -- many lights: one symbolic loop -----------------------------------------------------


def ring_of_lights(n, res=8):
    """A mesh on a floor under ``n`` point lights on a ring (total intensity INTENSITY)."""
    lights = {}
    for k in range(n):
        angle = 2 * np.pi * k / n
        lights[f"light{k}"] = {"type": "pointlight", "intensity": uniform(INTENSITY / n),
                               "position": [3 * np.cos(angle), 3, 3 * np.sin(angle)]}
    return showcase(lights, res=res)


def largest_kernel_size(scene, integrator):
    """Operation count of the largest kernel that rendering ``scene`` launches."""
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    try:
        dr.kernel_history()  # clear
        dr.eval(mi.render(scene, integrator=mi.load_dict(integrator), seed=0))
        kernels = [k for k in dr.kernel_history() if k["type"] == dr.KernelType.JIT]
    finally:
        dr.set_flag(dr.JitFlag.KernelHistory, False)
    return max(k["operation_count"] for k in kernels)


@pytest.mark.parametrize("shading", ["phong", "gouraud"])
def test_kernel_size_does_not_depend_on_the_number_of_lights(variant_rgb, shading):
    """``local`` loops over the emitters symbolically: 2 and 7 lights give kernels of the
    same size (an unrolled Python loop grows the kernel with every light)."""
    integrator = {"type": "local", "shading": shading}
    sizes = [largest_kernel_size(ring_of_lights(n), integrator) for n in (2, 7)]
    assert sizes[0] == sizes[1]


class _Warnings(mi.Appender):
    """Collects the text of Mitsuba's log messages."""

    def __init__(self):
        super().__init__()
        self.lines = []

    def append(self, level, text):
        self.lines.append(text)

    def log_progress(self, *args):
        pass


def test_gouraud_fallback_warned_once_per_scene(variant_rgb):
    """Rendering the same scene in several passes logs the Gouraud fallback once; a second
    scene logs it again."""
    logger = mi.logger()
    appender = _Warnings()
    logger.add_appender(appender)
    try:
        integrator = mi.load_dict({"type": "local", "shading": "gouraud"})
        scene = ring_of_lights(1)
        for seed in range(3):
            mi.render(scene, integrator=integrator, seed=seed)
        mi.render(ring_of_lights(1), integrator=integrator, seed=0)
    finally:
        logger.remove_appender(appender)
    warnings = [line for line in appender.lines if "gouraud' needs triangle meshes" in line]
    assert len(warnings) == 2


# -- ambient and fog -------------------------------------------------------------------

PLANE_DISTANCE = 4.0  # camera height above the plane z = 0


def plane_scene(lights: dict):
    return mi.load_dict(
        {
            "type": "scene",
            "plane": {
                "type": "rectangle",
                "to_world": mi.ScalarTransform4f().scale(100),
                "bsdf": {"type": "diffuse", "reflectance": uniform(RHO)},
            },
            **lights,
        }
    )


def test_ambient_term_is_rho_over_pi_times_irradiance(variant, rng):
    """The ambient term of a diffuse surface is rho/pi * E_ambient (no lights here)."""
    E = 2.5
    scene = plane_scene({})
    integrator = mi.load_dict({"type": "local", "ambient": uniform(E)})
    points = np.c_[rng.uniform(-5, 5, (32, 2)), np.zeros(32)]
    L, valid = cast(integrator, scene, [0, 0, PLANE_DISTANCE], points)
    assert valid.all()
    np.testing.assert_allclose(L, RHO / np.pi * E, rtol=RTOL)


@pytest.mark.parametrize("shading", ["flat", "phong"])
def test_closed_form_in_every_variant(any_variant, rng, shading):
    """In every variant (RGB, mono, spectral, polarized), flat and Phong shading (Gouraud:
    test_gouraud_interpolates_vertex_radiance): a diffuse plane under a point
    light of intensity I at height h, with ambient E and exponential fog, shows
    L = f(d) rho/pi (I cos / r^2 + E) + (1 - f(d)) C with f(d) = exp(-density d)."""
    E, density, color, height = 0.4, 0.05, 0.3, 2.0
    light = {"type": "pointlight", "position": [0, 0, height], "intensity": uniform(INTENSITY)}
    scene = plane_scene({"light": light})
    integrator = mi.load_dict({"type": "local", "shading": shading, "ambient": uniform(E),
                               "fog": "exponential", "fog_density": density,
                               "fog_color": uniform(color)})
    eye = np.array([0.0, 0.0, PLANE_DISTANCE])
    points = np.c_[rng.uniform(-3, 3, (32, 2)), np.zeros(32)]
    L, valid = cast(integrator, scene, eye, points)
    assert valid.all()
    r2 = np.sum(points[:, :2] ** 2, axis=1) + height**2
    irradiance = INTENSITY * height / np.sqrt(r2) / r2
    f = np.exp(-density * np.linalg.norm(points - eye, axis=1))
    expected = f * RHO / np.pi * (irradiance + E) + (1 - f) * color
    np.testing.assert_allclose(L, np.broadcast_to(expected[:, None], L.shape), rtol=RTOL,
                               atol=ATOL)


FOG_FORMULAS = {
    "linear": lambda d, start, end, density: np.clip((end - d) / (end - start), 0.0, 1.0),
    "exponential": lambda d, start, end, density: np.exp(-density * d),
    "exponential_squared": lambda d, start, end, density: np.exp(-((density * d) ** 2)),
}


@pytest.mark.parametrize("law", sorted(FOG_FORMULAS))
def test_fog_law(variant, rng, law):
    """Fog blends the surface radiance with the fog colour by the law's f(d) of the
    camera distance d, L = f L_surface + (1 - f) C; rays that leave the scene get C."""
    start, end, density, color = 5.0, 25.0, 0.08, 0.7
    scene = plane_scene(
        {"sun": {"type": "directional", "direction": [0, 0, -1], "irradiance": uniform(IRRADIANCE)}}
    )
    integrator = mi.load_dict(
        {
            "type": "local",
            "fog": law,
            "fog_start": start,
            "fog_end": end,
            "fog_density": density,
            "fog_color": uniform(color),
        }
    )
    eye = np.array([0.0, 0.0, PLANE_DISTANCE])
    points = np.c_[rng.uniform(-30, 30, (64, 2)), np.zeros(64)]
    d = np.linalg.norm(points - eye, axis=1)
    assert d.min() < start + 3 and d.max() > end  # every regime of the linear law
    L, valid = cast(integrator, scene, eye, points)
    assert valid.all()
    f = FOG_FORMULAS[law](d, start, end, density)[:, None]
    surface = RHO / np.pi * IRRADIANCE
    expected = np.broadcast_to(f * surface + (1 - f) * color, L.shape)
    np.testing.assert_allclose(L, expected, rtol=RTOL, atol=ATOL)

    L_sky, valid_sky = cast(integrator, scene, eye, eye + [0.1, 0.2, 1.0])
    assert valid_sky.all()
    np.testing.assert_allclose(L_sky, color, rtol=RTOL)


# -- shadows ----------------------------------------------------------------------------


def far_plane_scene(offset):
    o = np.array([offset] * 3, dtype=float)
    return mi.load_dict(
        {
            "type": "scene",
            "sensor": camera((o + [0, 4, 4]).tolist(), o.tolist(), 32),
            "floor": {
                "type": "rectangle",
                "bsdf": {"type": "diffuse"},
                "to_world": mi.ScalarTransform4f()
                .translate(o.tolist())
                .rotate([1, 0, 0], -83)
                .scale(10),
            },
            "light": {
                "type": "point",
                "position": (o + [2, 5, 1]).tolist(),
                "intensity": uniform(INTENSITY),
            },
        }
    )


def test_shadow_acne_without_bias_and_gone_with_bias(variant):
    """On an unoccluded plane far from the origin (float32 rounding of the hit point),
    shadow rays started exactly at the hit point hit the plane itself for a large share of
    pixels (shadow acne); a small bias along the normal removes every false shadow."""
    scene = far_plane_scene(1000.0)
    lit = render(scene, {"type": "local", "shadows": False})
    acne = render(scene, {"type": "local", "shadow_bias": 0.0})
    clean = render(scene, {"type": "local", "shadow_bias": 0.01})
    assert np.mean(np.all(acne == 0, axis=-1)) > 0.2
    np.testing.assert_allclose(clean, lit, rtol=RTOL, atol=ATOL)


def test_area_light_one_sample_estimate(variant_rgb):
    """An area light gets one emitter sample per pixel sample: the image converges to
    Mitsuba's direct lighting, and the light itself is seen with its radiance."""
    radiance = 4.0
    scene = mi.load_dict(
        {
            "type": "scene",
            "sensor": camera([0, 3, 5], [0, 0.5, 0], 16),
            "floor": {
                "type": "rectangle",
                "bsdf": {"type": "diffuse", "reflectance": uniform(RHO)},
                "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(5),
            },
            "lamp": {
                "type": "rectangle",
                "emitter": {"type": "area", "radiance": uniform(radiance)},
                "to_world": mi.ScalarTransform4f()
                .translate([0, 3, 0])
                .rotate([1, 0, 0], 90)
                .scale(0.5),
            },
            "ball": {
                "type": "sphere",
                "center": [0, 0.6, 0],
                "radius": 0.6,
                "bsdf": {"type": "diffuse"},
            },
        }
    )
    local = render(scene, {"type": "local"}, spp=128)
    direct = render(scene, DIRECT, spp=128)
    assert np.mean(local) == pytest.approx(np.mean(direct), rel=MC_RTOL)
    L, _ = cast(mi.load_dict({"type": "local"}), scene, [0.1, 2.0, 0.1], [0.1, 3.0, 0.1])
    np.testing.assert_allclose(L, radiance, rtol=RTOL)


# -- shadow samples ---------------------------------------------------------------------

#: Noise of N shadow samples against 1: 1/sqrt(N) within this factor.
NOISE_RATIO_SLACK = 1.3


def soft_shadow_scene(radius: float):
    """A floor seen from above, a ball between it and a sphere light of ``radius``
    (carried by its shape, outside the view): the floor holds the ball's umbra and
    penumbra, which vary slowly across a pixel (little noise from the pixel samples)."""
    from spectrace.plugins.emitters import sized

    T = mi.ScalarTransform4f()
    return mi.load_dict(sized.expand_dict({
        "type": "scene",
        "sensor": {**camera([0, 1.6, 0.01], [0, 0, 0], 24), "fov": 60},  # below the light
        "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(5),
                  "bsdf": {"type": "diffuse", "reflectance": uniform(RHO)}},
        "ball": {"type": "sphere", "center": [0, 0.8, 0], "radius": 0.4},
        "bulb": {"type": "pointlight", "position": [0.5, 3.0, 0.0],
                 "intensity": uniform(INTENSITY), "source_radius": radius},
    }))


def test_shadow_samples_change_nothing_for_point_lights(variant):
    """With delta lights only, ``shadow_samples`` 4 gives the image of 1, bit for bit."""
    scene = showcase({"p": LIGHTS["pointlight"](), "s": LIGHTS["spotlight"]()})
    np.testing.assert_array_equal(render(scene, {"type": "local", "shadow_samples": 4}),
                                  render(scene, {"type": "local"}))


def test_shadow_samples_average_the_penumbra(variant_rgb):
    """N shadow rays per sized light average N estimates: the same mean, and the noise
    falls as 1/sqrt(N) (N = 1, 16, against 256) on a floor with a soft shadow."""
    scene = soft_shadow_scene(0.5)
    # The same seed: the same pixel positions (the sampler's first dimensions), so the
    # difference from 256 samples is the light samples' noise alone.
    images = {n: render(scene, {"type": "local", "shadow_samples": n}) for n in (1, 16, 256)}
    noise = {n: np.std(images[n] - images[256]) for n in (1, 16)}
    assert np.mean(images[16]) == pytest.approx(np.mean(images[1]), rel=MC_RTOL)
    ratio = noise[16] / noise[1]  # 1/4, and 1/16 of the reference's own noise
    assert 0.25 / NOISE_RATIO_SLACK < ratio < 0.25 * NOISE_RATIO_SLACK, ratio


# -- parameters -----------------------------------------------------------------------

BAD_PARAMETERS = [
    ("shading", {"shading": "smooth"}),
    ("fog", {"fog": "haze"}),
    ("shadow_bias", {"shadow_bias": -0.1}),
    ("fog_density", {"fog_density": -1.0}),
    ("fog_end", {"fog": "linear", "fog_start": 10.0, "fog_end": 10.0}),
    ("fog_start", {"fog_start": -1.0}),
    ("ambient", {"ambient": -0.5}),
    ("fog_color", {"fog_color": -0.2}),
    ("ambient", {"ambient": {"type": "rgb", "value": [0.5, -0.1, 0.2]}}),
    ("shadow_samples", {"shadow_samples": 0}),
    ("ambient", {"ambient": "environmnt"}),
    ("environment", {"environment": {"type": "point"}}),
]


@pytest.mark.parametrize("name, params", BAD_PARAMETERS, ids=[name for name, _ in BAD_PARAMETERS])
def test_bad_parameters_fail_at_load(variant, name, params):
    """Invalid values are refused when the scene is loaded, naming the parameter."""
    with pytest.raises(Exception, match=f"local: parameter '{name}'"):
        mi.load_dict({"type": "local", **params})


def test_black_spectra_are_accepted(variant):
    """Zero ambient and fog colour are valid (black), also in spectral variants."""
    integrator = mi.load_dict(
        {"type": "local", "ambient": 0.0, "fog": "exponential", "fog_color": 0}
    )
    scene = plane_scene({})
    L, valid = cast(integrator, scene, [0, 0, PLANE_DISTANCE], [0.5, 0.5, 0.0])
    assert valid.all()
    np.testing.assert_array_equal(L, 0.0)


# -- the lecture's scenes ---------------------------------------------------------------

SCENE_RENDERS = [
    ("shading_models.xml", {"shading": "flat"}),
    ("shading_models.xml", {"shading": "gouraud"}),
    ("shading_models.xml", {"shading": "phong"}),
    ("shadow_acne.xml", {"shadow_bias": "0"}),
    ("shadow_acne.xml", {"shadow_bias": "0.01"}),
    ("fog.xml", {"fog": "none"}),
    ("fog.xml", {"fog": "linear"}),
    ("fog.xml", {"fog": "exponential"}),
    ("fog.xml", {"fog": "exponential_squared"}),
    ("fog_volpath.xml", {}),
]


@pytest.mark.parametrize(
    "name, params",
    SCENE_RENDERS,
    ids=[f"{n}-{'-'.join(p.values()) or 'default'}" for n, p in SCENE_RENDERS],
)
def test_scene_renders(variant_rgb, name, params):
    """Each scene of the lecture's comparisons loads and renders a finite, non-black image."""
    scene = mi.load_file(str(SCENES / name), res=16, spp=1, **params)
    image = to_numpy(mi.render(scene))
    assert np.isfinite(image).all() and image.mean() > 0.0


def test_coarse_gouraud_loses_the_highlight(variant_rgb):
    """The lecture's point: on the coarse sphere the highlight falls inside a facet,
    between the vertices, so Gouraud shading loses it while Phong shading keeps it."""
    images = {
        s: to_numpy(
            mi.render(mi.load_file(str(SCENES / "shading_models.xml"), res=64, spp=4, shading=s))
        )
        for s in ("gouraud", "phong")
    }
    coarse = slice(0, 32)  # left half: the coarse sphere
    assert images["gouraud"][:, coarse].max() < 0.5 * images["phong"][:, coarse].max()
