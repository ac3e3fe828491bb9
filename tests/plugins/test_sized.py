"""Tests of the lights with a size (``plugins/emitters/sized.py``: ``source_radius`` of
``pointlight`` and ``spotlight``, their expansion into shapes): far field, near field
against closed forms (Howell's sphere, the disk on its axis), the penumbra of a straight
edge under a sphere and a disk, the luminance seen by a camera, light tracing, variants
and bad input."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import emitter_checks as checks
import numpy as np
import pytest

#: Far field: a light at 20 times its size lights a plane like its point version within.
RTOL_FAR_FIELD = 5e-3
#: Monte Carlo estimates of the irradiance from 2^20 light samples against closed forms.
RTOL_MC = 1e-2
MC_SAMPLES = 2**20
#: Penumbra of a straight edge: its 10/50/90 % points where the quadrature puts them.
PENUMBRA_PIXELS = 2.0
#: Block means of ptracer against path (about 1 % noise per block).
RTOL_PTRACER = 0.04
#: A camera pixel entirely on the source against L = I / A_proj (float rounding).
RTOL_LUMINANCE = 1e-4
INTENSITY = 2.0


def sphere_light(position=(0.3, 1.0, 0.0), radius=0.1, **extra) -> dict:
    return {"type": "pointlight", "position": list(position), "intensity": INTENSITY,
            "source_radius": radius, **extra}


def disk_light(origin=(0.3, 1.5, 0.0), target=(0.0, 0.0, 0.2), radius=0.1, **extra) -> dict:
    T = checks.transform()
    light = {"type": "spotlight", "to_world": T.look_at(list(origin), list(target), [0, 0, 1]),
             "intensity": INTENSITY, "umbra_angle": 40.0, "penumbra_angle": 20.0,
             "source_radius": radius}
    return {**light, **extra}


def render_expanded(light: dict, integrator="direct", seed=0, **kwargs) -> np.ndarray:
    """The plane under ``light`` carried by its shape (sized.expand_dict)."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    scene = sized.expand_dict(checks.plane_scene(light, integrator, **kwargs))
    return np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)[..., :3]


def irradiance_mc(light: dict, point, normal, seed: int = 0) -> float:
    """Mean of the light samples' weight times cos(theta) at ``point`` (normal ``normal``):
    the irradiance estimate of next-event estimation (channel 0)."""
    import drjit as dr
    import mitsuba as mi

    emitter = mi.load_dict(light)
    rng = np.random.default_rng(seed)
    u = rng.random((2, MC_SAMPLES)).astype(np.float32)
    it = dr.zeros(mi.Interaction3f, MC_SAMPLES)
    it.p = mi.Point3f(*(float(c) for c in point))
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[0], u[1]))
    n = np.asarray(normal, dtype=np.float64) / np.linalg.norm(normal)
    cos = np.maximum(np.array(ds.d, dtype=np.float64).T @ n, 0.0)
    w = np.array(mi.unpolarized_spectrum(weight), dtype=np.float64)
    w = np.broadcast_to(w.reshape(w.shape[0], -1)[0], cos.shape)
    return float(np.mean(w * cos))


def howell_sphere_factor(H: float, phi: float) -> float:
    """Configuration factor from a plane element to a sphere of radius 1 at distance H
    from it, the element's normal at the angle phi from the direction of the centre
    (Howell, *A Catalog of Radiation Heat Transfer Configuration Factors*, "differential
    planar element to sphere", the case partly below the horizon when phi >
    arccos(1/H))."""
    if phi <= np.arccos(1.0 / H):
        return np.cos(phi) / H**2
    s = np.sqrt(H**2 - 1.0)
    return (0.5 - np.arcsin(s / (H * np.sin(phi))) / np.pi
            + (np.cos(phi) * np.arccos(-s / np.tan(phi))
               - s * np.sqrt(1.0 - H**2 * np.cos(phi)**2)) / (np.pi * H**2))


# -- far field and variants -----------------------------------------------------------------


@pytest.mark.parametrize("kind", ["sphere", "disk"])
def test_far_field_is_the_point_light(any_variant, kind):
    """A light at 20 times its size (diameter 0.1 m, 2 m and more from the plane) gives
    the plane the image of its point version within 0.5 % in every variant (the sphere
    exactly up to noise: wholly above the horizon E = I cos(theta) / d^2; the disk where
    the whole disk is inside the spot's full-intensity cone, since in the penumbra the
    spot's profile varies across the disk's 1.5 degrees)."""
    if kind == "sphere":
        light = sphere_light(position=(0.3, 2.0, 0.0), radius=0.05)
    else:
        light = disk_light(origin=(0.3, 2.0, 0.0), radius=0.05)
    sized = render_expanded(light, spp=64)
    point = checks.render({**light, "source_radius": 0.0}, spp=64)
    p = checks.positions()
    beside = np.hypot(p[..., 0] - 0.3, p[..., 2]) > 0.1  # not under the source itself
    # Inside the spot's full-intensity cone (penumbra 20 degrees less the disk's 1.5).
    axis = np.array([-0.3, -2.0, 0.2]) / np.linalg.norm([-0.3, -2.0, 0.2])
    v = p - np.array([0.3, 2.0, 0.0])
    inside = (v @ axis) / np.linalg.norm(v, axis=-1) > np.cos(np.radians(18.5))
    lit = (point > 0.2 * point.max()) & (beside & (inside | (kind == "sphere")))[..., None]
    np.testing.assert_allclose(sized[lit], point[lit], rtol=RTOL_FAR_FIELD)


def test_source_radius_zero_is_the_delta_light_bit_for_bit(variant):
    """``source_radius`` 0 is today's delta light: the same image, bit for bit, and the
    scene loader leaves it alone."""
    from spectrace.plugins.emitters import sized

    for light in (sphere_light(radius=0.0), disk_light(radius=0.0)):
        plain = {k: v for k, v in light.items() if k != "source_radius"}
        np.testing.assert_array_equal(render_expanded(light), checks.render(plain))
    root = ET.fromstring('<scene><emitter type="pointlight">'
                         '<float name="source_radius" value="0"/></emitter></scene>')
    assert not sized.expand_tree(root)


# -- near field against closed forms --------------------------------------------------------


@pytest.mark.parametrize("method", ["solid_angle", "area"])
@pytest.mark.parametrize(("H", "phi"), [(1.5, 0.6), (1.5, 1.5), (1.5, 1.8), (3.0, 1.5)])
def test_sphere_irradiance_matches_howell(variant_rgb, method, H, phi):
    """A Lambertian sphere (L = I / (pi r^2)) at a plane element, partly below its horizon
    or not: E = L pi F = I F / r^2 with Howell's configuration factor F, for both sampling
    methods (next-event estimates of 2^20 samples)."""
    radius = 0.2
    normal = (np.sin(phi), np.cos(phi), 0.0)  # the centre lies along +y from the point
    light = sphere_light(position=(0.0, H * radius, 0.0), radius=radius,
                         source_sampling=method)
    expected = INTENSITY * howell_sphere_factor(H, phi) / radius**2
    assert irradiance_mc(light, (0.0, 0.0, 0.0), normal) == pytest.approx(expected,
                                                                           rel=RTOL_MC)


@pytest.mark.parametrize("h", [0.05, 0.2, 1.0])
def test_disk_on_its_axis(variant_rgb, h):
    """A disk spot with the quadratic cone law, umbra 90 and penumbra 0.01 degrees has
    I(alpha) = I0 cos^2(alpha), so L = I0 cos(gamma) / (pi r^2); on its axis at height h
    E = integral L cos dw = 2 I0 (1 - cos^3 theta_m) / (3 r^2), cos theta_m = h /
    sqrt(h^2 + r^2) (tends to I0 / h^2 far away)."""
    radius = 0.1
    T = checks.transform()
    light = {"type": "spotlight", "to_world": T.look_at([0, h, 0], [0, 0, 0], [0, 0, 1]),
             "intensity": INTENSITY, "umbra_angle": 90.0, "penumbra_angle": 0.01,
             "source_radius": radius}
    cos_m = h / np.hypot(h, radius)
    expected = 2.0 * INTENSITY * (1.0 - cos_m**3) / (3.0 * radius**2)
    assert irradiance_mc(light, (0.0, 0.0, 0.0), (0, 1, 0)) == pytest.approx(expected,
                                                                            rel=RTOL_MC)


#: The straight-edge scenes: the light's and the edge's heights, the light's radius (m).
EDGE_HEIGHT_LIGHT, EDGE_HEIGHT, EDGE_RADIUS = 2.0, 1.0, 0.2


def render_edge_profile(light: dict, res: int = 64, half: float = 0.5):
    """The floor's rendered radiance across the shadow of a half-plane (x < 0, height
    EDGE_HEIGHT) under ``light``, seen by an orthographic camera below the edge: (x, profile)."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    T = checks.transform()
    scene = checks.plane_scene(light, "direct", res=res)
    scene["sensor"]["to_world"] = T.look_at([0, 0.05, 0], [0, 0, 0], [0, 0, 1]).scale(
        [half, half, 1])
    scene["sensor"]["sampler"] = {"type": "independent", "sample_count": 64}
    scene["edge"] = {"type": "rectangle", "to_world": T.translate([-5, EDGE_HEIGHT, 0])
                     @ T.rotate([1, 0, 0], 90).scale(5),
                     "bsdf": {"type": "diffuse", "reflectance": 0.0}}
    image = np.array(mi.render(mi.load_dict(sized.expand_dict(scene)), seed=1))[..., 0]
    # The film's x runs along world -x (camera up +z, looking down): flip to world x.
    x = (np.arange(res) + 0.5) / res * 2 * half - half
    return x, image.mean(axis=0)[::-1]


def check_penumbra(x, profile, free, shadowed):
    """The rendered fractions 10/50/90 % where the oracle's ``shadowed`` / ``free`` puts
    them (within PENUMBRA_PIXELS), dark before the similar-triangle umbra edge x = -r h_e /
    (h_l - h_e), fully lit after x = +r h_e / (h_l - h_e)."""
    free, shadowed = np.asarray(free), np.asarray(shadowed)
    fraction_oracle = shadowed / free
    scale = profile[-8:].mean() / free[-8:].mean()
    fraction = profile / (scale * free)
    pixel = x[1] - x[0]
    for level in (0.1, 0.5, 0.9):
        at = np.interp(level, fraction, x)
        expected = np.interp(level, fraction_oracle, x)
        assert abs(at - expected) <= PENUMBRA_PIXELS * pixel, (level, at, expected)
    end = EDGE_RADIUS * EDGE_HEIGHT / (EDGE_HEIGHT_LIGHT - EDGE_HEIGHT)
    assert np.all(fraction[x < -end - pixel] < 0.02)
    assert np.all(fraction[x > end + pixel] > 0.97)


def test_penumbra_of_a_straight_edge(variant_rgb):
    """The shadow on the floor of a half-plane (x < 0, height 1) under a sphere light
    (radius 0.2, height 2): the fractions 10/50/90 % of the unshadowed irradiance fall
    where a quadrature of the visible part of the sphere puts them (within 2 pixels);
    dark before the similar-triangle umbra edge x = -0.2, fully lit after x = +0.2."""
    light = sphere_light(position=(0.0, EDGE_HEIGHT_LIGHT, 0.0), radius=EDGE_RADIUS)
    x, profile = render_edge_profile(light)

    # Oracle: the cone of the sphere from each floor point, midpoint rule, numpy only.
    n = 400
    u = (np.arange(n) + 0.5) / n
    free, shadowed = [], []
    for xi in x:
        c = np.array([-xi, EDGE_HEIGHT_LIGHT, 0.0])
        dist = np.linalg.norm(c)
        cos_m = np.sqrt(1 - (EDGE_RADIUS / dist) ** 2)
        cos_t = 1 - u[:, None] * (1 - cos_m)
        sin_t = np.sqrt(1 - cos_t**2)
        phi = 2 * np.pi * u[None, :]
        axis = c / dist
        e1 = np.cross(axis, [0.0, 0.0, 1.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(axis, e1)
        d = (sin_t * np.cos(phi))[..., None] * e1 + (sin_t * np.sin(phi))[..., None] * e2 \
            + cos_t[..., None] * axis
        cos_floor = d[..., 1]
        x_edge = xi + d[..., 0] * EDGE_HEIGHT / d[..., 1]
        free.append(np.sum(cos_floor))
        shadowed.append(np.sum(cos_floor * (x_edge >= 0)))
    check_penumbra(x, profile, free, shadowed)


def test_penumbra_of_a_straight_edge_under_a_disk(variant_rgb):
    """The same edge under a disk spot facing down (radius 0.2, height 2; quadratic cone,
    umbra 90 degrees: I = I0 cos^2, so L = I0 cos(gamma) / (pi r^2)): the 10/50/90 %
    points where a quadrature over the disk's area of L cos^2 / t^2 (cos(gamma) =
    h / t on both the disk and the floor) puts them, dark before x = -0.2 and fully lit
    after x = +0.2 (similar triangles)."""
    T = checks.transform()
    light = {"type": "spotlight", "intensity": INTENSITY, "umbra_angle": 90.0,
             "penumbra_angle": 0.01, "source_radius": EDGE_RADIUS,
             "to_world": T.look_at([0, EDGE_HEIGHT_LIGHT, 0], [0, 0, 0], [0, 0, 1])}
    x, profile = render_edge_profile(light)

    # Oracle: the disk's area in polar cells (equal areas in rho^2), numpy only.
    n = 400
    u = (np.arange(n) + 0.5) / n
    rho = EDGE_RADIUS * np.sqrt(u)[:, None]
    phi = 2 * np.pi * u[None, :]
    qx = rho * np.cos(phi)
    qz = rho * np.sin(phi)
    free, shadowed = [], []
    for xi in x:
        t2 = (qx - xi) ** 2 + EDGE_HEIGHT_LIGHT**2 + qz**2
        weight = EDGE_HEIGHT_LIGHT**3 / t2**2.5  # cos(gamma) L cos cos / t^2, constants off
        x_edge = xi + (qx - xi) * EDGE_HEIGHT / EDGE_HEIGHT_LIGHT
        free.append(np.sum(weight))
        shadowed.append(np.sum(weight * (x_edge >= 0)))
    check_penumbra(x, profile, free, shadowed)


# -- seen by the camera ------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["sphere", "disk"])
def test_camera_sees_luminance_over_projected_area(variant, kind):
    """Camera rays (a pixel of 0.05 degrees aimed at the centre) that hit the source see
    L = I(omega) / A_proj(omega): I / (pi r^2) on the sphere, I(gamma) / (pi r^2 cos
    gamma) on the disk seen at gamma = 30 degrees from its axis (quadratic cone, penumbra
    40: full intensity there), as Mitsuba's ``area`` emitter of that radiance shows it."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    T = checks.transform()
    radius, gamma = 0.5, np.radians(30.0)
    if kind == "sphere":
        light, cos_gamma = sphere_light(position=(0, 0, 0), radius=radius), 1.0
    else:
        light = {"type": "spotlight", "to_world": T.look_at([0, 0, 0], [0, 0, 1], [0, 1, 0]),
                 "intensity": INTENSITY, "umbra_angle": 50.0, "penumbra_angle": 40.0,
                 "source_radius": radius}
        cos_gamma = np.cos(gamma)
    light["intensity"] = checks.uniform(INTENSITY)
    eye = [0, 3 * np.sin(gamma), 3 * np.cos(gamma)]
    scene = {"type": "scene", "integrator": {"type": "path"}, "light": light,
             "sensor": {"type": "perspective", "fov": 0.05,
                        "to_world": T.look_at(eye, [0, 0, 0], [0, 1, 0]),
                        "film": {"type": "hdrfilm", "width": 1, "height": 1,
                                 "rfilter": {"type": "box"}},
                        "sampler": {"type": "independent", "sample_count": 16}}}
    expanded = sized.expand_dict(scene)
    image = np.array(mi.render(mi.load_dict(expanded)), dtype=np.float64)
    # Oracle: Mitsuba's own area emitter of radiance I / A_proj on the same shape, the
    # same samples (so the same wavelengths in spectral variants).
    radiance = INTENSITY / (np.pi * radius**2 * cos_gamma)
    expanded["light"]["emitter"] = {"type": "area", "radiance": checks.uniform(radiance)}
    expected = np.array(mi.render(mi.load_dict(expanded)), dtype=np.float64)
    assert np.all(expected > 0.5 * radiance)
    np.testing.assert_allclose(image, expected, rtol=RTOL_LUMINANCE)


@pytest.mark.parametrize("kind", ["sphere", "disk"])
def test_ptracer_sees_the_source_as_path_does(variant_rgb, kind):
    """``ptracer`` connects points of the light's surface to the camera (sample_position,
    sample_wavelengths towards the camera): the source seen directly has the luminance
    path tracing gives it, the disk's directional one included (image sums within
    noise), and a disk seen from behind is black for both."""
    import mitsuba as mi
    from spectrace.plugins.emitters import sized

    T = checks.transform()
    if kind == "sphere":
        light = sphere_light(position=(0, 0, 0), radius=0.5)
    else:
        light = {"type": "spotlight", "to_world": T.look_at([0, 0, 0], [0, 0, 1], [0, 1, 0]),
                 "intensity": INTENSITY, "umbra_angle": 60.0, "penumbra_angle": 40.0,
                 "source_radius": 0.5}
    for eye in ([0, 1.5, 2.6], [0, 1.5, -2.6]):
        scene = {"type": "scene", "light": light,
                 "sensor": {"type": "perspective", "fov": 30,
                            "to_world": T.look_at(eye, [0, 0, 0], [0, 1, 0]),
                            "film": {"type": "hdrfilm", "width": 16, "height": 16,
                                     "rfilter": {"type": "box"}},
                            "sampler": {"type": "independent", "sample_count": 256}}}
        sums = []
        for integrator in ("path", "ptracer"):
            scene["integrator"] = {"type": integrator}
            sums.append(np.array(mi.render(mi.load_dict(sized.expand_dict(scene)),
                                           seed=4)).sum())
        if kind == "disk" and eye[2] < 0:
            assert sums == [0.0, 0.0]
        else:
            assert sums[1] == pytest.approx(sums[0], rel=RTOL_PTRACER)


def block_means(image: np.ndarray, block: int = 8) -> np.ndarray:
    h, w, c = image.shape
    return image.reshape(h // block, block, w // block, block, c).mean(axis=(1, 3))


@pytest.mark.parametrize("kind", ["sphere", "disk"])
def test_ptracer_equals_path(variant_rgb, kind):
    """Light tracing from the sized light (sample_ray, and its visible surface splatted to
    the camera) converges to path tracing with MIS (block means of the channel sums)."""
    light = sphere_light(radius=0.2) if kind == "sphere" else disk_light(radius=0.2)
    path = render_expanded(light, {"type": "path", "max_depth": 2}, spp=64,
                           sensor="perspective")
    traced = render_expanded(light, {"type": "ptracer", "max_depth": 2}, spp=256,
                             sensor="perspective", seed=3)
    lit = block_means(path).sum(-1) > 0.05 * block_means(path).sum(-1).max()
    np.testing.assert_allclose(block_means(traced).sum(-1)[lit],
                               block_means(path).sum(-1)[lit], rtol=RTOL_PTRACER)


@pytest.mark.parametrize("kind", ["sphere", "disk"])
@pytest.mark.parametrize("integrator", ["path", "volpath", "direct", "prb", "local"])
def test_attached_equals_next_event_only(variant_rgb, integrator, kind):
    """The light carried by its shape (hit by BSDF rays, MIS weights from pdf_direction)
    lights the plane as the same light without a shape (next-event estimation only)."""
    light = sphere_light(radius=0.3) if kind == "sphere" else disk_light(radius=0.3)
    attached = render_expanded(light, integrator, spp=64)
    alone = checks.render(light, integrator, spp=64)
    p = checks.positions()
    # Not under the source (seen from above it hides the plane, or shows itself).
    beside = np.hypot(p[..., 0] - 0.3, p[..., 2]) > 0.45
    lit = (alone > 0.05 * alone.max()) & beside[..., None]
    np.testing.assert_allclose(attached[lit].mean(), alone[lit].mean(), rtol=RTOL_MC)


# -- the scene loader ---------------------------------------------------------------------------


def test_expand_tree_resolves_parameters(variant_rgb, tmp_path):
    """A ``pointlight`` whose ``source_radius`` is ``$r`` (a scene default) becomes a black
    sphere carrying it; the loaded scene then has one shape more and one emitter."""
    from spectrace.scene import load_scene

    xml = """<scene version="3.0.0">
        <default name="r" value="0.1"/>
        <integrator type="path"/>
        <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/>
            <integer name="height" value="4"/></film></sensor>
        <emitter type="pointlight"><point name="position" x="0" y="1" z="0"/>
            <float name="source_radius" value="$r"/></emitter>
    </scene>"""
    path = tmp_path / "s.xml"
    path.write_text(xml)
    scene = load_scene(path)
    assert len(scene.shapes()) == 1 and scene.shapes()[0].emitter() is not None
    assert len(load_scene(path, {"r": "0"}).shapes()) == 0


# -- bad input ---------------------------------------------------------------------------------


@pytest.mark.parametrize(("kind", "extra", "words"), [
    ("sphere", {"source_radius": -0.1}, "'source_radius' must be >= 0"),
    ("sphere", {"source_radius": float("nan")}, "'source_radius'"),
    ("sphere", {"falloff": "none"}, "'falloff' must be inverse_square"),
    ("sphere", {"source_sampling": "cosine"}, "'source_sampling'"),
    ("disk", {"umbra_angle": 90.0, "penumbra_angle": 90.0}, "'penumbra_angle' must be < 90"),
])
def test_bad_input_fails_at_load_naming_the_parameter(variant_rgb, kind, extra, words):
    """Negative or NaN ``source_radius``, a non-physical law, an unknown sampling method
    or a full-intensity cone at 90 degrees: one line naming the parameter."""
    import mitsuba as mi

    light = sphere_light(**extra) if kind == "sphere" else disk_light(**extra)
    with pytest.raises(Exception) as error:
        mi.load_dict(light)
    message = str(error.value).strip().splitlines()[-1]
    assert words in message, message


def test_reference_page(variant_rgb):
    """The helper page of ``sized`` follows the one reference-page format."""
    from spectrace.plugins.emitters import sized

    assert set(checks.parse_reference_page(sized.__doc__, "sized")) == {"source_radius"}
