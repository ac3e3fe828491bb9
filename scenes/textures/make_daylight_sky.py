"""Make the environment maps shipped with the scenes (run from the repository root):

    .venv/bin/python scenes/textures/make_daylight_sky.py

``daylight_sky.exr``: a 64 x 128 latitude-longitude map (Mitsuba's ``envmap`` layout,
``spectrace.envmaps``) of the CIE clear sky of ISO 15469 type 12, the sun at azimuth 150
degrees (south-south-east) and 35 degrees elevation, above a ground of reflectance 0.2,
evaluated by the ``ciesky`` emitter itself (RGB variant, white spectrum) at the texels
(columns at their centres, rows from the zenith to the nadir as Mitsuba reads them:
``spectrace.envmaps.texel_uv``). Values are relative: the zenith is 1 (scale the map to
lux with ``spectrace envmap convert --illuminance``). ``uniform_sky.exr``: the same size,
1 above the horizon and 0.2 below (a constant sky over a ground of reflectance 0.2), for
comparisons. The sun's disk itself is not in the map (a 0.53 degree disk is far below one
texel: add a ``sun``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import spectrace
from spectrace import envmaps

HEIGHT = 64
FOLDER = Path(__file__).resolve().parent


def sky_map(props: dict) -> np.ndarray:
    """The ``ciesky`` of ``props`` at the texels of a HEIGHT x 2 HEIGHT latlong map,
    divided by the zenith luminance."""
    import drjit as dr
    import mitsuba as mi

    spectrace.set_variant("llvm_ad_rgb")
    sky = mi.load_dict({"type": "ciesky", "zenith_luminance": 1.0, **props})
    uv = envmaps.texel_uv(HEIGHT, 2 * HEIGHT, "latlong").reshape(-1, 2)
    d = envmaps.latlong_to_direction(uv)
    si = dr.zeros(mi.SurfaceInteraction3f, d.shape[0])
    si.wi = mi.Vector3f(*(-d[:, i].astype(np.float32) for i in range(3)))
    value = np.array(sky.eval(si), dtype=np.float64).T
    zenith = dr.zeros(mi.SurfaceInteraction3f)
    zenith.wi = mi.Vector3f(0, -1, 0)
    value /= np.array(sky.eval(zenith), dtype=np.float64).ravel()[None, :]
    return value.reshape(HEIGHT, 2 * HEIGHT, 3)


def main() -> None:
    clear = sky_map({"sky_type": 12, "sun_azimuth": 150.0, "sun_elevation": 35.0,
                     "ground_reflectance": 0.2})
    envmaps.write_map(FOLDER / "daylight_sky.exr", clear)
    uniform = sky_map({"sky_type": "uniform", "ground_reflectance": 0.2})
    envmaps.write_map(FOLDER / "uniform_sky.exr", uniform)


if __name__ == "__main__":
    main()
