"""Scenes and oracles shared by the tests of ``pointlight``, ``spotlight`` and their falloff
laws (a plain module).

The radiometric set-up: a diffuse plane y = 0 of albedo RHO, seen straight from above by an
orthographic camera, with one sample per pixel exactly at the pixel centre (``stratified``
sampler without jitter, box filter) and the ``direct`` integrator. A light at ``p_light``
then gives every pixel the radiance

    L = RHO / pi * I(direction) * falloff(r) * cos(theta),   cos(theta) = (p_light.y) / r,

at the point p seen through the pixel (r = |p_light - p|); the points come from Mitsuba's
``aov`` integrator (position AOV) with the same sensor and sampler.

In spectral variants the film's conversion of a sampled spectrum to RGB has its own
wavelength noise, so the tests also compare against Mitsuba's built-in ``point`` light
rendered with the same seed: the two images then differ by exactly the factor
I(direction)/I0 * falloff(r) * r^2 at every pixel, whatever the wavelengths drawn.
"""

from __future__ import annotations

import numpy as np

#: Film side in pixels and plane albedo.
RES = 32
RHO = 0.5
#: Half-width of the orthographic view of the plane (scene units).
HALF_WIDTH = 2.0
#: Relative tolerance of a float32 render against a float64 formula.
RTOL_RENDER = 2e-4
#: Absolute tolerance, relative to the brightest pixel, for pixels that must be dark.
ATOL_RENDER = 1e-6


def transform():
    import mitsuba as mi

    return mi.ScalarTransform4f()


def uniform(value: float) -> dict:
    """A spectrum equal to ``value`` at every wavelength (a plain float is not, in spectral
    variants: Mitsuba turns an emissive float into an illuminant-shaped spectrum)."""
    return {"type": "uniform", "value": value}


def plane_scene(light: dict, integrator: str | dict = "direct", spp: int = 1,
                sensor: str = "orthographic", res: int = RES) -> dict:
    """A diffuse plane y = 0 under ``light`` and above nothing, seen from +y."""
    T = transform()
    if sensor == "orthographic":
        sensor_dict = {
            "type": "orthographic",
            "to_world": T.look_at([0, 8, 0], [0, 0, 0], [0, 0, 1]).scale(
                [HALF_WIDTH, HALF_WIDTH, 1]),
        }
    else:
        sensor_dict = {
            "type": "perspective",
            "fov": 60,
            "to_world": T.look_at([0, 4, 0.01], [0, 0, 0], [0, 1, 0]),
        }
    if spp == 1:
        sampler = {"type": "stratified", "sample_count": 1, "jitter": False}
    else:
        sampler = {"type": "independent", "sample_count": spp}
    sensor_dict["film"] = {"type": "hdrfilm", "width": res, "height": res,
                           "rfilter": {"type": "box"}}
    sensor_dict["sampler"] = sampler
    if isinstance(integrator, str):
        integrator = {"type": integrator}
    return {
        "type": "scene",
        "integrator": integrator,
        "sensor": sensor_dict,
        "plane": {
            "type": "rectangle",
            "to_world": T.rotate([1, 0, 0], -90).scale(10),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": RHO}},
        },
        "light": light,
    }


def render(light: dict, integrator: str | dict = "direct", seed: int = 0, **kwargs) -> np.ndarray:
    """Render the plane under ``light``: an (H, W, 3) float64 array."""
    import mitsuba as mi

    scene = mi.load_dict(plane_scene(light, integrator, **kwargs))
    return np.array(mi.render(scene, seed=seed), dtype=np.float64)[..., :3]


def positions(res: int = RES) -> np.ndarray:
    """World positions seen at the pixel centres, (H, W, 3), from Mitsuba's ``aov``."""
    light = {"type": "point", "position": [0, 1, 0]}
    return render(light, {"type": "aov", "aovs": "p:position"}, res=res)


def builtin_point(position, intensity: float, **kwargs) -> np.ndarray:
    """The plane under Mitsuba's ``point`` light (the oracle of the 1/r^2 law)."""
    return render({"type": "point", "position": list(position), "intensity": intensity},
                  **kwargs)


def closed_form(p: np.ndarray, p_light, directional) -> np.ndarray:
    """RHO/pi * I(direction) * falloff(r) * cos(theta) per pixel, (H, W).

    ``directional(d, r)`` gives I(direction) * falloff(r) for the unit directions d from the
    light to the points (..., 3) and the distances r.
    """
    v = p - np.asarray(p_light, dtype=np.float64)
    r = np.linalg.norm(v, axis=-1)
    d = v / r[..., None]
    cos_theta = -d[..., 1]
    return RHO / np.pi * directional(d, r) * cos_theta


def assert_image_close(image: np.ndarray, expected: np.ndarray, rtol: float = RTOL_RENDER):
    """Every pixel and channel of ``image`` equals ``expected`` (broadcast over channels)."""
    if expected.ndim == image.ndim - 1:
        expected = np.repeat(expected[..., None], image.shape[-1], axis=-1)
    atol = ATOL_RENDER * float(np.max(np.abs(expected))) + 1e-30
    np.testing.assert_allclose(image, expected, rtol=rtol, atol=atol)


def wavelength_grid(n: int):
    """A SurfaceInteraction3f of n lanes at rest with wavelengths on a 1 nm grid in spectral
    variants (and nothing to set in RGB ones)."""
    import drjit as dr
    import mitsuba as mi

    si = dr.zeros(mi.SurfaceInteraction3f, n)
    if mi.is_spectral:
        w = dr.linspace(mi.Float, 400.0, 700.0, n)
        si.wavelengths = mi.UnpolarizedSpectrum(w)
    return si


def eval_intensity(emitter, directions: np.ndarray, distance: float = 1.0) -> np.ndarray:
    """``emitter.eval_direction`` from points at ``distance`` along the unit ``directions``
    (N, 3) leaving the emitter at ``origin``: (N, channels) float64."""
    import drjit as dr
    import mitsuba as mi

    origin = np.array(dr.slice(emitter_position(emitter)))
    n = directions.shape[0]
    it = wavelength_grid(n)
    points = origin[None, :] + distance * directions
    it.p = mi.Point3f(*(points[:, i].astype(np.float32) for i in range(3)))
    ds = dr.zeros(mi.DirectionSample3f, n)
    ds.p = mi.Point3f(*(float(c) for c in origin))
    ds.d = mi.Vector3f(*(-directions[:, i].astype(np.float32) for i in range(3)))
    ds.dist = mi.Float(distance)
    value = emitter.eval_direction(mi.Interaction3f(it), ds)
    return np.array(value, dtype=np.float64).T.reshape(n, -1)


def emitter_position(emitter):
    import mitsuba as mi

    ps, _ = emitter.sample_position(0.0, mi.Point2f(0.5))
    return ps.p


def sphere_quadrature(n_theta: int, n_phi: int):
    """Midpoint rule on the sphere: unit directions (N, 3) and solid-angle weights (N,)."""
    cos_t = 1.0 - (np.arange(n_theta) + 0.5) * (2.0 / n_theta)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    cos_t, phi = np.meshgrid(cos_t, phi, indexing="ij")
    sin_t = np.sqrt(1.0 - cos_t**2)
    d = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1).reshape(-1, 3)
    w = np.full(d.shape[0], 4.0 * np.pi / (n_theta * n_phi))
    return d, w


#: integral of the CIE 1931 ybar (= CIE 1924 V) over 360-830 nm (nm, 1 nm sum of
#: colour-science's table): the normalisation of the spectral film's Y (a constant spectrum
#: of radiance 1 has Y = 1; Mitsuba's own table sums to 0.1% less).
CIE_Y_INTEGRAL = 106.856895
#: K_m (lm/W), written here as the oracle's own constant (CIE 018:2019).
KM = 683.0


def lux_from_film_y(Y):
    """Illuminance (lux) on the diffuse plane of albedo RHO from the film's luminance Y of
    the plane's radiance, read with Mitsuba's own films (no spectrace code).

    Derivation: the plane is Lambertian, so its radiance is L(lambda) = RHO / pi *
    E(lambda), E the spectral irradiance. The illuminance is E_v = K_m integral V E dlambda
    = (pi / RHO) K_m integral V L dlambda. Spectral variants: the film's Y is
    integral L ybar dlambda / integral ybar dlambda with ybar = V (CIE 1931 ybar is the
    CIE 1924 V), so integral V L = CIE_Y_INTEGRAL * Y and E_v = (pi / RHO) K_m
    CIE_Y_INTEGRAL Y. RGB variants: Y = 0.2126 R + 0.7152 G + 0.0722 B of the linear
    sRGB radiance, and the photometric convention of RGB rendering is that a colour stands
    for the spectra of the same film Y, E_v = K_m CIE_Y_INTEGRAL Y(E): the same formula.
    Mono variants: Y is the one value, the same formula again.
    """
    return np.pi / RHO * KM * CIE_Y_INTEGRAL * np.asarray(Y)


def lux_at(light: dict, point, spp: int, seed: int = 0) -> float:
    """Illuminance (lux) that ``light`` gives at ``point`` = (x, z) of the plane y = 0,
    measured by a ``radiancemeter`` looking straight down at it (every sample on the same
    ray, so only the wavelengths vary) whose film gives the luminance Y."""
    import mitsuba as mi

    scene = plane_scene(light)
    scene["sensor"] = {
        "type": "radiancemeter", "origin": [point[0], 0.5, point[1]], "direction": [0, -1, 0],
        "film": {"type": "hdrfilm", "width": 1, "height": 1, "pixel_format": "luminance",
                 "rfilter": {"type": "box"}},
        "sampler": {"type": "independent", "sample_count": spp},
    }
    Y = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64).ravel()[0]
    return float(lux_from_film_y(Y))


def plane_lux(light: dict, spp: int, res: int = RES, seed: int = 0) -> np.ndarray:
    """Illuminance (lux) on the plane y = 0 per pixel of the orthographic view from above,
    (res, res): each pixel the mean over its square of side 2 HALF_WIDTH / res (independent
    samples, box filter), so the sum times the pixel area is the luminous flux received."""
    import mitsuba as mi

    scene = plane_scene(light, spp=max(spp, 2), res=res)
    scene["sensor"]["sampler"] = {"type": "independent", "sample_count": spp}
    scene["sensor"]["film"]["pixel_format"] = "luminance"
    Y = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)[..., 0]
    return lux_from_film_y(Y)


def pixel_area(res: int = RES) -> float:
    """Area (m^2) of the plane seen by one pixel of the orthographic view."""
    return (2.0 * HALF_WIDTH / res) ** 2


#: The columns of every parameter table, and the marks a description may end with.
PAGE_COLUMNS = ["parameter", "type", "default", "unit", "description"]
PAGE_MARKS = {"exposed", "differentiable", "discontinuous"}
PAGE_SECTIONS = ["Parameters", "Formula", "Sources", "Example"]


def parse_reference_page(doc: str, name: str) -> dict[str, dict]:
    """Check that ``doc`` follows the one format of the plugin reference pages and return
    its parameter table as {parameter: {"type", "default", "unit", "description",
    "marks"}}.

    The format: first line "``name``: summary."; sections underlined with '-' named
    Parameters, Formula, Sources, Example in this order; Parameters opens with ONE
    reStructuredText simple table with exactly PAGE_COLUMNS, no cell text crossing a
    column gap (descriptions may continue on rows whose first cells are empty), marks
    among PAGE_MARKS; Example holds a literal block (``::``) of XML; no reference to
    material users do not have.
    """
    import re

    lines = doc.splitlines()
    assert re.fullmatch(rf"``{name}``: \S.*\.", lines[0]), lines[0]
    titles = [(i, lines[i]) for i in range(len(lines) - 1)
              if lines[i] and set(lines[i + 1]) == {"-"} and len(lines[i + 1]) == len(lines[i])]
    assert [t for _, t in titles] == PAGE_SECTIONS, titles
    assert "lecture" not in doc.lower() and "DESIGN" not in doc
    start = titles[0][0] + 2
    body = lines[start:titles[1][0]]
    while body and not body[0].strip():
        body.pop(0)
    border = body[0]
    assert re.fullmatch(r"=+( {2,}=+)+", border), border
    spans = [m.span() for m in re.finditer(r"=+", border)]
    assert len(spans) == len(PAGE_COLUMNS)
    borders = [i for i, line in enumerate(body) if line == border]
    assert len(borders) == 3 and borders[:2] == [0, 2], "one simple table, one header row"
    assert sum(1 for line in body if re.fullmatch(r"=+( {2,}=+)+", line)) == 3

    def cells(line: str) -> list[str]:
        for (_, end), (begin, _) in zip(spans[:-1], spans[1:], strict=True):
            assert line[end:begin].strip() == "", f"text crosses a column gap: {line!r}"
        return [line[a:b if k < len(spans) - 1 else None].strip()
                for k, (a, b) in enumerate(spans)]

    assert cells(body[1]) == PAGE_COLUMNS
    table: dict[str, dict] = {}
    current = None
    for line in body[3:borders[2]]:
        row = cells(line)
        if row[0]:
            match = re.fullmatch(r"``(\w+)``", row[0])
            assert match, row[0]
            entry = dict(zip(PAGE_COLUMNS[1:], row[1:], strict=True))
            current = table.setdefault(match.group(1), entry)
        else:
            assert current is not None and not any(row[1:4]), line
            current["description"] += " " + row[4]
    for entry in table.values():
        marks = re.findall(r"\|(\w+)\|", entry["description"])
        assert set(marks) <= PAGE_MARKS, marks
        entry["marks"] = set(marks)
    example = "\n".join(lines[titles[3][0] + 2:])
    assert "::" in example and "<" in example.split("::", 1)[1]
    return table


def check_marks_against_traverse(table: dict, plugin) -> None:
    """Every parameter that ``mi.traverse(plugin)`` lists is marked |exposed| in the page,
    and marked |differentiable| exactly when traverse says it is."""
    import mitsuba as mi

    params = mi.traverse(plugin)
    names = {key.split(".")[0] for key in params.keys()}
    for name in names:
        assert name in table, f"{name} is exposed but not in the page"
        assert "exposed" in table[name]["marks"], name
        keys = [k for k in params.keys() if k.split(".")[0] == name]
        differentiable = any(
            not params.flags(k) & int(mi.ParamFlags.NonDifferentiable) for k in keys)
        assert differentiable == ("differentiable" in table[name]["marks"]), name
