"""Near field of lights with a size: the study of ``notebooks/near_field.ipynb``.

Three questions about the lights with ``source_radius`` (see ``spectrace help sized``):

* how wrong the point approximation E = I cos(theta) / d^2 is near a luminous disk, a
  rectangle (a linear luminaire), a box (:func:`point_error_box`) and a sphere, against
  the distance in units of the luminous dimension D (the diameter, the rectangle's
  length, the box's largest side), and
  where it falls under 1 % compared with the photometric rule of thumb "five times the
  largest dimension" (:func:`point_error_closed_form` and :func:`point_error_rectangle`,
  closed forms, and
  :func:`point_error_measured`, the same measured on the lights' own next-event samples);
* the umbra and penumbra of a straight edge on the floor for source radii 0, 5 cm and
  20 cm (:func:`edge_profile`, an orthographic camera between the occluder and the floor,
  and :func:`penumbra_width`, the similar-triangle prediction);
* the noise of a soft shadow in the ``local`` integrator against its ``shadow_samples``
  (:func:`shadow_noise`).

Closed forms: a Lambertian disk of radiance L and radius r on its axis at height h gives
E = pi L r^2 / (r^2 + h^2), its point version (I = pi r^2 L) E = pi L r^2 / h^2: the
relative error is (r / h)^2, 1 % at h = 10 r = 5 D. The spot disk of ``spotlight`` with the
quadratic cone, umbra 90 degrees (I = I0 cos^2) gives E = 2 I0 (1 - cos^3 theta_m) /
(3 r^2). Under the centre of a Lambertian rectangle (length D, a linear luminaire when
long and narrow) the four quarters' configuration factors give E (Howell's catalogue,
"differential planar element to parallel rectangle"). A Lambertian sphere wholly above
the plane's horizon gives exactly
I cos(theta) / d^2 (Howell's catalogue, "differential planar element to sphere"): no
near-field error at all, whatever the distance. A box luminous on its six faces (uniform
L = I / A_proj) photometered about its centre has a face D / 2 nearer than the centre
straight below it: a first-order error, -D / d, 1 % only at about 100 D; along a diagonal
the first order cancels (about 7 D for a cube).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from spectrace.errors import ParameterError
from spectrace.studies import budget, display, text_table

__all__ = ["EdgeProfile", "box_irradiance", "box_projected_area", "budget", "display",
           "edge_profile", "penumbra_width", "point_error_box",
           "point_error_closed_form", "point_error_measured", "point_error_rectangle",
           "rectangle_corner_factor", "shadow_noise", "text_table", "under_one_percent"]

#: The relative error of the point approximation the study looks for.
ONE_PERCENT = 0.01
#: Heights of the light above the floor and of the straight edge (m) in the edge profiles.
LIGHT_HEIGHT, EDGE_HEIGHT = 2.0, 1.0


def point_error_closed_form(kind: str, distance_over_size) -> np.ndarray:
    """Relative error E_point / E - 1 of the point approximation on the axis of a light,
    at the distances ``distance_over_size`` (d / D, D the diameter 2 r).

    ``kind``: ``lambertian_disk`` (uniform L: (r / d)^2), ``spot_disk`` (spotlight's disk
    with I = I0 cos^2, quadratic cone with umbra 90 degrees) or ``sphere`` (0: exact while
    the sphere is above the horizon, d > r)."""
    x = np.asarray(distance_over_size, dtype=np.float64)
    h = 2.0 * x  # in units of r
    if kind == "lambertian_disk":
        return 1.0 / h**2
    if kind == "spot_disk":
        cos_m = h / np.sqrt(h**2 + 1.0)
        exact = 2.0 * (1.0 - cos_m**3) / 3.0  # E r^2 / I0
        return (1.0 / h**2) / exact - 1.0
    if kind == "sphere":
        return np.zeros_like(x)
    raise ValueError(f"point_error_closed_form: unknown kind {kind!r}")


def rectangle_corner_factor(X, Y) -> np.ndarray:
    """Configuration factor from a plane element to a parallel rectangle of sides X h and
    Y h whose corner lies straight above it at the height h (Howell's catalogue,
    "differential planar element to parallel rectangle")."""
    X, Y = np.asarray(X, np.float64), np.asarray(Y, np.float64)
    a, b = np.sqrt(1 + X**2), np.sqrt(1 + Y**2)
    return (X / a * np.arctan(Y / a) + Y / b * np.arctan(X / b)) / (2 * np.pi)


def point_error_rectangle(distance_over_length, aspect: float) -> np.ndarray:
    """Relative error of the point approximation under the centre of a Lambertian
    rectangle of length D and width D / ``aspect`` (a linear luminaire for a large
    aspect), at the distances ``distance_over_length`` (d / D): the exact E = pi L 4 F of
    the four quarter rectangles (:func:`rectangle_corner_factor`) against the point's
    L A / d^2."""
    h = np.asarray(distance_over_length, dtype=np.float64)  # in units of D
    half_length, half_width = 0.5, 0.5 / aspect
    exact = np.pi * 4 * rectangle_corner_factor(half_length / h, half_width / h)
    point = (1.0 / aspect) / h**2
    return point / exact - 1.0


def under_one_percent(kind: str, **parameters) -> float:
    """The distance d / D beyond which the point approximation errs by less than 1 %
    (bisection on :func:`point_error_closed_form`, or :func:`point_error_rectangle` for
    ``lambertian_rectangle`` with its ``aspect``, or :func:`point_error_box` for ``box``
    with its ``dims`` and ``direction``; 0.5 for the sphere: any distance outside it)."""
    if kind == "sphere":
        return 0.5

    def error(x):
        if kind == "lambertian_rectangle":
            return point_error_rectangle(x, **parameters)
        if kind == "box":
            return point_error_box(x, **parameters)[0]
        return point_error_closed_form(kind, x)

    low, high = 0.5, 1000.0
    for _ in range(60):
        mid = 0.5 * (low + high)
        if abs(error(mid)) > ONE_PERCENT:
            low = mid
        else:
            high = mid
    return high


def _irradiance_mc(light: dict, point, normal, samples: int, seed: int) -> float:
    """Next-event estimate of the irradiance ``light`` gives at ``point`` (normal)."""
    import drjit as dr
    import mitsuba as mi

    emitter = mi.load_dict(light)
    u = np.random.default_rng(seed).random((2, samples)).astype(np.float32)
    it = dr.zeros(mi.Interaction3f, samples)
    it.p = mi.Point3f(*(float(c) for c in point))
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[0], u[1]))
    cos = np.maximum(np.array(ds.d, dtype=np.float64).T @ np.asarray(normal, np.float64), 0)
    w = np.array(mi.unpolarized_spectrum(weight), dtype=np.float64)
    w = np.broadcast_to(w.reshape(w.shape[0], -1)[0], cos.shape)
    return float(np.mean(w * cos))


def point_error_measured(kind: str, distance_over_size, radius: float = 0.1,
                         samples: int | None = None, seed: int = 0) -> np.ndarray:
    """:func:`point_error_closed_form` measured with spectrace's lights (``spot_disk``:
    ``spotlight``, ``sphere``: ``pointlight``, both with ``source_radius`` = ``radius``),
    from their next-event samples at the point on the axis below them (in the active
    variant; ``samples`` per distance, default 2^18, 2^14 at test size)."""
    import mitsuba as mi

    samples = samples or budget(2**18, 2**14)
    T = mi.ScalarTransform4f()
    errors = []
    for x in np.atleast_1d(distance_over_size):
        d = 2.0 * radius * float(x)
        if kind == "sphere":
            light = {"type": "pointlight", "position": [0, d, 0], "source_radius": radius}
        elif kind == "spot_disk":
            light = {"type": "spotlight", "to_world": T.look_at([0, d, 0], [0, 0, 0], [0, 0, 1]),
                     "umbra_angle": 90.0, "penumbra_angle": 0.01, "source_radius": radius}
        else:
            raise ValueError(f"point_error_measured: unknown kind {kind!r}")
        light["intensity"] = {"type": "uniform", "value": 1.0}
        E = _irradiance_mc(light, (0, 0, 0), (0, 1, 0), samples, seed)
        errors.append((1.0 / d**2) / E - 1.0)
    return np.array(errors)


@dataclass
class EdgeProfile:
    """The floor's irradiance across the shadow of a straight edge."""

    x: np.ndarray  #: positions across the edge (m); the edge is above x = 0
    irradiance: np.ndarray  #: W/m^2 per position (mean over the rows of the render)
    radius: float  #: source radius (m)

    def fraction(self) -> np.ndarray:
        """The irradiance over the unshadowed one, I h / (x^2 + h^2)^(3/2) (exact for a
        sphere wholly above the floor's horizon, see the module)."""
        unshadowed = LIGHT_HEIGHT / (self.x**2 + LIGHT_HEIGHT**2) ** 1.5
        return self.irradiance / unshadowed


def penumbra_width(radius: float, light_height: float = LIGHT_HEIGHT,
                   edge_height: float = EDGE_HEIGHT) -> float:
    """Similar triangles: the floor between full shadow and full light of an edge at
    ``edge_height`` under a source of ``radius`` at ``light_height`` is 2 r h_e / (h_l -
    h_e) wide."""
    return 2.0 * radius * edge_height / (light_height - edge_height)


def edge_profile(radius: float, res: int | None = None, spp: int | None = None,
                 half_width: float = 0.5, seed: int = 0) -> EdgeProfile:
    """The irradiance on a white floor across the shadow of a half-plane (x < 0, height
    1 m) under a sphere light (intensity I = 1 W/sr, height 2 m, above x = 0): a ``direct``
    render by an orthographic camera just above the floor, below the edge (the
    occluder does not hide the floor from it), E = pi L_floor."""
    import mitsuba as mi

    from spectrace.plugins.emitters import sized

    res = res or budget(128, 48)
    spp = spp or budget(256, 32)
    T = mi.ScalarTransform4f()
    light = {"type": "pointlight", "position": [0, LIGHT_HEIGHT, 0],
             "intensity": {"type": "uniform", "value": 1.0}, "source_radius": radius}
    scene = sized.expand_dict({
        "type": "scene", "integrator": {"type": "direct"},
        "sensor": {"type": "orthographic",
                   "to_world": T.look_at([0, 0.05, 0], [0, 0, 0], [0, 0, 1]).scale(
                       [half_width, half_width, 1]),
                   "film": {"type": "hdrfilm", "width": res, "height": res,
                            "rfilter": {"type": "box"}, "pixel_format": "luminance"},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(10),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 1}}},
        "edge": {"type": "rectangle", "to_world": T.translate([-5, EDGE_HEIGHT, 0])
                 @ T.rotate([1, 0, 0], 90).scale(5),
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0}}},
        "light": light,
    })
    image = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)[..., 0]
    x = (np.arange(res) + 0.5) / res * 2 * half_width - half_width
    return EdgeProfile(x=x, irradiance=np.pi * image.mean(axis=0)[::-1], radius=radius)


def shadow_noise(counts=(1, 4, 16, 64), radius: float = 0.2, res: int | None = None,
                 reference_count: int = 256) -> dict[int, float]:
    """RMS error of the ``local`` render of :func:`edge_profile`'s scene (seen from above
    the edge, a penumbra on the floor) per ``shadow_samples`` count, against
    ``reference_count`` shadow samples with the same pixel samples (same seed)."""
    import mitsuba as mi

    from spectrace.plugins.emitters import sized

    res = res or budget(96, 32)
    T = mi.ScalarTransform4f()
    scene = mi.load_dict(sized.expand_dict({
        "type": "scene",
        "sensor": {"type": "perspective", "fov": 50,
                   "to_world": T.look_at([0, 1.6, 1.2], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res},
                   "sampler": {"type": "independent", "sample_count": 1}},
        "floor": {"type": "rectangle", "to_world": T.rotate([1, 0, 0], -90).scale(5)},
        "ball": {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.3},
        "light": {"type": "pointlight", "position": [0.3, LIGHT_HEIGHT, -0.5],
                  "intensity": {"type": "uniform", "value": 4.0}, "source_radius": radius},
    }))

    def render(n):
        integrator = mi.load_dict({"type": "local", "shadow_samples": n})
        return np.array(mi.render(scene, integrator=integrator, seed=0), dtype=np.float64)

    reference = render(reference_count)
    return {n: float(np.sqrt(np.mean((render(n) - reference) ** 2))) for n in counts}


#: The box's six faces: (axis of the normal, sign).
_BOX_FACES = [(axis, sign) for axis in range(3) for sign in (-1.0, 1.0)]


def box_projected_area(dims, direction) -> float:
    """A_proj(omega) = |w_x| b c + |w_y| a c + |w_z| a b of a box of sides ``dims`` =
    (a, b, c): the area its faces present to a plane normal to ``direction``."""
    a, b, c = (float(v) for v in dims)
    w = np.abs(np.asarray(direction, np.float64)) / np.linalg.norm(direction)
    return float(w[0] * b * c + w[1] * a * c + w[2] * a * b)


def box_irradiance(dims, point, normal, n: int = 200) -> float:
    """Irradiance E / L at ``point`` (receiver ``normal``) from a box of sides ``dims``
    centred at the origin whose faces all emit the uniform radiance L (so that L =
    I(omega) / A_proj(omega), the luminous box of ``ieslight``): the midpoint rule on an
    ``n`` x ``n`` grid per face of L cos(face) cos(receiver) / t^2, the faces the point
    lies in front of (the box is convex), the receiver's cosine clamped at its horizon."""
    half = 0.5 * np.asarray(dims, np.float64)
    p, nr = np.asarray(point, np.float64), np.asarray(normal, np.float64)
    nr = nr / np.linalg.norm(nr)
    u = (np.arange(n) + 0.5) / n * 2 - 1
    total = 0.0
    for axis, sign in _BOX_FACES:
        if sign * p[axis] <= half[axis]:
            continue  # behind the face's plane: hidden by the box
        i, j = [k for k in range(3) if k != axis]
        q = np.zeros((n, n, 3))
        q[..., axis] = sign * half[axis]
        q[..., i], q[..., j] = np.meshgrid(u * half[i], u * half[j], indexing="ij")
        t = q - p
        t2 = np.sum(t**2, axis=-1)
        cos_face = -sign * t[..., axis] / np.sqrt(t2)
        cos_receiver = np.maximum(t @ nr / np.sqrt(t2), 0.0)
        area = 4 * half[i] * half[j] / n**2
        total += float(np.sum(cos_face * cos_receiver / t2) * area)
    return total


def point_error_box(distance_over_size, dims=(1.0, 1.0, 1.0), direction=(0.0, 0.0, -1.0),
                    n: int = 200) -> np.ndarray:
    """Relative error E_point / E - 1 of the point approximation at the distances
    ``distance_over_size`` (d / D, D the box's largest side) from the box's centre (its
    photometric centre) along ``direction``, on a receiver facing the centre: the point's
    L A_proj(omega) / d^2 against :func:`box_irradiance`. Along a face's normal the face
    lies c / 2 closer than the centre (c the box's side along it), so the error is first
    order, about -c / d (the disks' and rectangles' is second order); along a diagonal
    the first-order terms cancel (the faces that come closer are seen more obliquely)."""
    dims = np.asarray(dims, np.float64)
    w = np.asarray(direction, np.float64) / np.linalg.norm(direction)
    size = float(dims.max())
    area = box_projected_area(dims, w)
    errors = []
    for x in np.atleast_1d(np.asarray(distance_over_size, np.float64)):
        d = float(x) * size
        if np.all(np.abs(d * w) <= dims / 2):
            raise ParameterError(f"point_error_box: distance_over_size {x:g} lies inside "
                                 f"the box {tuple(dims)} along {tuple(w)}")
        errors.append(area / d**2 / box_irradiance(dims, d * w, -w, n) - 1.0)
    return np.array(errors)
