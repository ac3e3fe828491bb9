"""Scenes and oracles shared by the tests of ``ciesky`` and ``sun`` (a plain module).

Illuminance is read with Mitsuba's own sensors, never spectrace's integrators: an
``irradiancemeter`` on a small horizontal square (the sensor's rays leave it in a cosine
distribution and ``direct`` evaluates the sky they reach), its film's luminance Y turned
into lux as in ``emitter_checks.lux_from_film_y`` (E_v = K_m CIE_Y_INTEGRAL Y).
"""

from __future__ import annotations

import numpy as np
from emitter_checks import CIE_Y_INTEGRAL, KM

#: Side (m) of the horizontal square that carries the irradiance meter.
METER_SIDE = 0.002


def meter(position=(0.0, 0.0, 0.0), spp: int = 4096) -> dict:
    """A small upward-facing square at ``position`` carrying an ``irradiancemeter``."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    return {
        "type": "rectangle",
        "to_world": T.translate(list(position)).rotate([1, 0, 0], -90).scale(METER_SIDE / 2),
        "sensor": {
            "type": "irradiancemeter",
            "film": {"type": "hdrfilm", "width": 1, "height": 1, "pixel_format": "luminance",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
    }


def meter_lux(light: dict, shapes: dict | None = None, position=(0.0, 0.0, 0.0),
              spp: int = 4096, seed: int = 0, integrator: str = "direct") -> float:
    """Illuminance (lux) on the horizontal meter at ``position`` under ``light``, with
    ``shapes`` (name -> shape dict) around it."""
    import mitsuba as mi

    scene = {"type": "scene", "integrator": {"type": integrator}, "light": light,
             "meter": meter(position, spp)}
    scene.update(shapes or {})
    Y = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64).ravel()[0]
    return float(KM * CIE_Y_INTEGRAL * Y)


def roof_with_opening(height: float, a: float, b: float, extent: float = 50.0) -> dict:
    """A horizontal black roof at ``height`` with a centred opening of a x b (along x and
    z), as four rectangles, each with its own BSDF instance (see the merge trap of
    issue 23 in the module of ``ciesky``'s tests)."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    pieces = {
        # name: (centre x, centre z, half size x, half size z)
        "roof_west": (-(extent + a / 2) / 2, 0.0, (extent - a / 2) / 2, extent),
        "roof_east": ((extent + a / 2) / 2, 0.0, (extent - a / 2) / 2, extent),
        "roof_north": (0.0, -(extent + b / 2) / 2, a / 2, (extent - b / 2) / 2),
        "roof_south": (0.0, (extent + b / 2) / 2, a / 2, (extent - b / 2) / 2),
    }
    shapes = {}
    for k, (name, (x, z, hx, hz)) in enumerate(pieces.items()):
        shapes[name] = {
            "type": "rectangle",
            # facing down (the underside is what the meter sees)
            "to_world": T.translate([x, height, z]).rotate([1, 0, 0], 90).scale([hx, hz, 1]),
            "bsdf": {"type": "diffuse",
                     "reflectance": {"type": "uniform", "value": 1e-6 * (k + 1)}},
        }
    return shapes


def rectangle_configuration_factor(a: float, b: float, c: float) -> float:
    """Configuration factor from a horizontal differential area to a parallel a x b
    rectangle at height c, centred above it: 4 x the corner case (Howell, *A Catalog of
    Radiation Heat Transfer Configuration Factors*, B-3; Hottel 1931)."""
    A, B = (a / 2) / c, (b / 2) / c
    corner = (A / np.sqrt(1 + A * A) * np.arctan(B / np.sqrt(1 + A * A))
              + B / np.sqrt(1 + B * B) * np.arctan(A / np.sqrt(1 + B * B))) / (2 * np.pi)
    return 4.0 * corner


def closed_box(reflectance: float = 0.5) -> dict:
    """The inside of a cube of side 2 m as six rectangles of identical grey BSDFs (facing
    in): Mitsuba 3.9.1 merges them into one mesh whose bounding box is invalid."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    faces = [T.translate([0, 0, -1]), T.translate([0, 0, 1]).rotate([0, 1, 0], 180),
             T.translate([1, 0, 0]).rotate([0, 1, 0], -90),
             T.translate([-1, 0, 0]).rotate([0, 1, 0], 90),
             T.translate([0, 1, 0]).rotate([1, 0, 0], 90),
             T.translate([0, -1, 0]).rotate([1, 0, 0], -90)]
    return {f"wall{k}": {"type": "rectangle", "to_world": face,
                         "bsdf": {"type": "diffuse",
                                  "reflectance": {"type": "rgb", "value": reflectance}}}
            for k, face in enumerate(faces)}


def render_inside_box(light: dict, integrator: str = "direct", spp: int = 64) -> tuple:
    """(image, number of shapes after loading) of a camera at the centre of
    :func:`closed_box` under ``light``."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    scene = {"type": "scene", "integrator": {"type": integrator}, "light": light,
             "sensor": {"type": "perspective", "fov": 90,
                        "to_world": T.look_at([0, 0, 0], [0, 0, -1], [0, 1, 0]),
                        "film": {"type": "hdrfilm", "width": 16, "height": 16},
                        "sampler": {"type": "independent", "sample_count": spp}},
             **closed_box()}
    loaded = mi.load_dict(scene)
    return np.array(mi.render(loaded, seed=0)), len(loaded.shapes())


def axis_rectangle(axis: str, at: float, first: tuple, second: tuple, reflectance: float):
    """A black-ish diffuse rectangle in the plane ``axis`` = ``at`` spanning ``first`` and
    ``second`` (ranges of the two other axes, in x, y, z order); its own BSDF instance."""
    import mitsuba as mi

    T = mi.ScalarTransform4f()
    (a0, a1), (b0, b1) = first, second
    ca, cb, ha, hb = (a0 + a1) / 2, (b0 + b1) / 2, (a1 - a0) / 2, (b1 - b0) / 2
    if axis == "x":  # spans y, z
        to_world = T.translate([at, ca, cb]).rotate([0, 1, 0], 90).scale([hb, ha, 1])
    elif axis == "y":  # spans x, z
        to_world = T.translate([ca, at, cb]).rotate([1, 0, 0], 90).scale([ha, hb, 1])
    else:  # spans x, y
        to_world = T.translate([ca, cb, at]).scale([ha, hb, 1])
    return {"type": "rectangle", "to_world": to_world,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": reflectance}}}


def room_with_window(x: tuple, z: tuple, height: float, window_x: tuple,
                     window_y: tuple) -> dict:
    """The ceiling and four walls of a room x in ``x``, z in ``z``, y in [0, height], with an
    opening window_x x window_y in the north wall z = z[0] (no floor: the meter faces up)."""
    (x0, x1), (z0, z1) = x, z
    (wx0, wx1), (wy0, wy1) = window_x, window_y
    parts = [
        ("y", height, (x0, x1), (z0, z1)),
        ("x", x0, (0.0, height), (z0, z1)), ("x", x1, (0.0, height), (z0, z1)),
        ("z", z1, (x0, x1), (0.0, height)),
        # the north wall around the window
        ("z", z0, (x0, wx0), (0.0, height)), ("z", z0, (wx1, x1), (0.0, height)),
        ("z", z0, (wx0, wx1), (0.0, wy0)), ("z", z0, (wx0, wx1), (wy1, height)),
    ]
    return {f"part{k}": axis_rectangle(axis, at, first, second, 1e-6 * (k + 1))
            for k, (axis, at, first, second) in enumerate(parts)}
