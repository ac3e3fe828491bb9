"""Environment maps in every layout: the projector functions and the conversion between them.

An environment map stores the radiance arriving from every direction as an image. Each
layout is one projector: a map from a unit direction d = (x, y, z) (the direction light
comes *from*, scene frame with +Y up) to image coordinates (u, v) in [0, 1]^2, u to the
right and v downwards, and back. All arrays are numpy, with the vector axis last.

======================  ==============================================================
layout                  projector
======================  ==============================================================
``latlong``             Blinn and Newell (1976), Mitsuba's ``envmap`` convention:
                        u = atan2(x, -z) / (2 pi) (mod 1), v = acos(y) / pi; 2:1;
                        texel (i, j) at u = (j + 1/2) / W, v = i / (H - 1) (below)
``sphere``              mirror ball (sphere map) seen from +Z: the ball normal
                        n = normalize(d + (0, 0, 1)), u = (1 + n_x) / 2, v = (1 - n_y) / 2;
                        d = 2 n_z n - (0, 0, 1); 1:1
``angular``             Debevec's light probe: forward -Z at the centre, the radius r =
                        acos(-z) / pi proportional to the angle (r = 1: backward); 1:1
``cross_horizontal``    cube map (Greene 1986) unfolded as a 4:3 cross, row 2 left to
                        right -X, -Z (front), +X, +Z; +Y above and -Y below the front
``cross_vertical``      the same cube as a 3:4 cross: +Y, front, -Y, then +Z (turned by
                        180 degrees) in the middle column
======================  ==============================================================

Texels: in every layout but ``latlong``, texel (i, j) of an H x W image sits at its pixel
centre ((j + 1/2) / W, (i + 1/2) / H). A ``latlong`` map has its columns there too, but
its rows run from pole to pole, v_i = i / (H - 1) (theta_i = i Delta, Delta = pi / (H - 1)):
row 0 is the zenith, row H - 1 the nadir, as Mitsuba's ``envmap`` reads them (bilinear
between rows, :func:`texel_uv`, :func:`lookup`). The solid angle of a latlong texel is the
integral of its bilinear hat function, (2 pi / W) integral hat_i(theta) sin(theta) dtheta:
(2 pi / W) 2 (1 - cos Delta) / Delta sin(theta_i) inside, (2 pi / W) (1 - sin Delta / Delta)
for the two pole rows (:func:`latlong_solid_angles`); they sum to 4 pi exactly, so a
uniform map integrates exactly.

Cube faces are seen from inside: face f has a forward axis F, right R and up U, and its
pixel at (s, t) in [-1, 1]^2 (t downwards) looks along F + s R - t U, so that neighbouring
faces meet without seams. :func:`convert` resamples any layout into another (bilinear, at
pixel centres), so that any map feeds Mitsuba's ``envmap`` (which keeps its own importance
sampling) as ``latlong``. Photometric scale: :func:`horizontal_illuminance` is the lux a
horizontal plane receives from the map's upper hemisphere (the map in W/(m^2 sr) times
the convention of ``spectrace help luminous``, K_m integral V = 683 x 106.857 per unit of
luminance Y).

:func:`sh_project` and :func:`sh_irradiance` give a map's irradiance for any surface normal
from its spherical-harmonics projection of order 2 (the irradiance environment map of
Ramamoorthi and Hanrahan 2001).

Sources: Blinn, Newell (1976), "Texture and reflection in computer generated images",
CACM 19(10); Greene (1986), "Environment mapping and other applications of world
projections", IEEE CG&A 6(11); Debevec (1998), "Rendering synthetic objects into real
scenes", SIGGRAPH (angular map); Miller, Hoffman (1984), SIGGRAPH course notes (sphere
map); Ramamoorthi, Hanrahan (2001), "An efficient representation for irradiance environment
maps", SIGGRAPH.
"""

from __future__ import annotations

import numpy as np

from spectrace.errors import FileFormatError, ParameterError

LAYOUTS = ("latlong", "sphere", "angular", "cross_horizontal", "cross_vertical")
#: Width / height of each layout's image.
ASPECTS = {"latlong": 2.0, "sphere": 1.0, "angular": 1.0, "cross_horizontal": 4.0 / 3.0,
           "cross_vertical": 3.0 / 4.0}
#: K_m integral V dlambda: lux per unit of luminance Y of irradiance (spectrace help luminous).
LUX_PER_Y = 683.0 * 106.856895

#: Cube faces: name -> (forward, right, up) as seen from inside.
FACES = {
    "-z": ((0, 0, -1), (1, 0, 0), (0, 1, 0)),
    "+x": ((1, 0, 0), (0, 0, 1), (0, 1, 0)),
    "+z": ((0, 0, 1), (-1, 0, 0), (0, 1, 0)),
    "-x": ((-1, 0, 0), (0, 0, -1), (0, 1, 0)),
    "+y": ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
    "-y": ((0, -1, 0), (1, 0, 0), (0, 0, -1)),
}
#: Where each face sits in a cross (column, row), and whether it is turned by 180 degrees.
CROSS_CELLS = {
    "cross_horizontal": ({"-x": (0, 1), "-z": (1, 1), "+x": (2, 1), "+z": (3, 1),
                          "+y": (1, 0), "-y": (1, 2)}, (4, 3), ()),
    "cross_vertical": ({"-x": (0, 1), "-z": (1, 1), "+x": (2, 1), "+y": (1, 0),
                        "-y": (1, 2), "+z": (1, 3)}, (3, 4), ("+z",)),
}


def _normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# -- latitude-longitude -------------------------------------------------------------------

def latlong_to_uv(d):
    u = np.mod(np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi), 1.0)
    v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi
    return np.stack([u, v], axis=-1)


def latlong_to_direction(uv):
    phi, theta = 2 * np.pi * uv[..., 0], np.pi * uv[..., 1]
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta),
                     -np.sin(theta) * np.cos(phi)], axis=-1)


# -- mirror ball --------------------------------------------------------------------------

def sphere_to_uv(d):
    n = _normalize(d + np.array([0.0, 0.0, 1.0]))
    return np.stack([(1 + n[..., 0]) / 2, (1 - n[..., 1]) / 2], axis=-1)


def sphere_to_direction(uv):
    s, t = 2 * uv[..., 0] - 1, 1 - 2 * uv[..., 1]
    n_z = np.sqrt(np.clip(1 - s * s - t * t, 0.0, 1.0))
    n = np.stack([s, t, n_z], axis=-1)
    return 2 * n_z[..., None] * n - np.array([0.0, 0.0, 1.0])


def sphere_valid(uv):
    s, t = 2 * uv[..., 0] - 1, 1 - 2 * uv[..., 1]
    return s * s + t * t <= 1.0


# -- angular (light probe) ----------------------------------------------------------------

def angular_to_uv(d):
    r = np.arccos(np.clip(-d[..., 2], -1.0, 1.0)) / np.pi
    h = np.hypot(d[..., 0], d[..., 1])
    safe = np.where(h > 0, h, 1.0)
    s, t = r * d[..., 0] / safe, r * d[..., 1] / safe
    return np.stack([(1 + s) / 2, (1 - t) / 2], axis=-1)


def angular_to_direction(uv):
    s, t = 2 * uv[..., 0] - 1, 1 - 2 * uv[..., 1]
    r = np.hypot(s, t)
    theta = np.pi * np.clip(r, 0.0, 1.0)
    safe = np.where(r > 0, r, 1.0)
    return np.stack([np.sin(theta) * s / safe, np.sin(theta) * t / safe, -np.cos(theta)],
                    axis=-1)


angular_valid = sphere_valid


# -- cube crosses -------------------------------------------------------------------------

def _face_axes(layout, name):
    forward, right, up = (np.array(v, dtype=np.float64) for v in FACES[name])
    if name in CROSS_CELLS[layout][2]:
        right, up = -right, -up
    return forward, right, up


#: File-name tags of six separate cube faces (``IN_{face}.exr``) -> face.
FACE_TAGS = {"px": "+x", "nx": "-x", "py": "+y", "ny": "-y", "pz": "+z", "nz": "-z"}


def assemble_cross(faces: dict, layout: str = "cross_horizontal", name: str = "faces"):
    """A cross image of ``layout`` from six square face images {face: (N, N, C)} (faces
    named as in :data:`FACES`, each seen from inside as there: right R, up U)."""
    cells, (columns, rows), turned = CROSS_CELLS[layout]
    if set(faces) != set(FACES):
        raise FileFormatError(f"{name}: need the six faces {', '.join(FACES)}")
    shapes = {np.shape(image) for image in faces.values()}
    size = next(iter(shapes))[0]
    if len(shapes) != 1 or next(iter(shapes))[1] != size:
        raise FileFormatError(f"{name}: the six faces must be squares of one size "
                              f"(got {sorted(s[:2] for s in shapes)})")
    channels = next(iter(shapes))[2]
    cross = np.zeros((rows * size, columns * size, channels))
    for face, (column, row) in cells.items():
        image = np.asarray(faces[face], dtype=np.float64)
        if face in turned:
            image = image[::-1, ::-1]
        cross[row * size:(row + 1) * size, column * size:(column + 1) * size] = image
    return cross


def split_cross(cross, layout: str = "cross_horizontal") -> dict:
    """The six faces {face: image} of a cross image (the inverse of :func:`assemble_cross`)."""
    cells, (columns, rows), turned = CROSS_CELLS[layout]
    size = cross.shape[0] // rows
    faces = {}
    for face, (column, row) in cells.items():
        image = cross[row * size:(row + 1) * size, column * size:(column + 1) * size]
        faces[face] = image[::-1, ::-1] if face in turned else image
    return faces


def cube_to_uv(d, layout="cross_horizontal"):
    """(u, v) in the cross of ``layout`` of the directions ``d``."""
    cells, (columns, rows), _ = CROSS_CELLS[layout]
    uv = np.zeros(d.shape[:-1] + (2,))
    axis = np.argmax(np.abs(d), axis=-1)
    sign = np.take_along_axis(d, axis[..., None], axis=-1)[..., 0] > 0
    for name, (column, row) in cells.items():
        index = "xyz".index(name[1])
        mask = (axis == index) & (sign == (name[0] == "+"))
        if not np.any(mask):
            continue
        forward, right, up = _face_axes(layout, name)
        dm = d[mask]
        depth = dm @ forward
        s, t = (dm @ right) / depth, -(dm @ up) / depth
        uv[mask, 0] = (column + (s + 1) / 2) / columns
        uv[mask, 1] = (row + (t + 1) / 2) / rows
    return uv


def cube_to_direction(uv, layout="cross_horizontal"):
    """Directions of the cross's (u, v); NaN outside the six faces."""
    cells, (columns, rows), _ = CROSS_CELLS[layout]
    d = np.full(uv.shape[:-1] + (3,), np.nan)
    column = np.clip(np.floor(uv[..., 0] * columns), 0, columns - 1).astype(int)
    row = np.clip(np.floor(uv[..., 1] * rows), 0, rows - 1).astype(int)
    for name, (c, r) in cells.items():
        mask = (column == c) & (row == r)
        forward, right, up = _face_axes(layout, name)
        s = 2 * (uv[mask, 0] * columns - c) - 1
        t = 2 * (uv[mask, 1] * rows - r) - 1
        d[mask] = _normalize(forward + s[:, None] * right - t[:, None] * up)
    return d


def cube_valid(uv, layout="cross_horizontal"):
    cells, (columns, rows), _ = CROSS_CELLS[layout]
    column = np.clip(np.floor(uv[..., 0] * columns), 0, columns - 1).astype(int)
    row = np.clip(np.floor(uv[..., 1] * rows), 0, rows - 1).astype(int)
    valid = np.zeros(uv.shape[:-1], dtype=bool)
    for c, r in cells.values():
        valid |= (column == c) & (row == r)
    return valid


# -- one mapping name -> functions ----------------------------------------------------------

#: layout -> (direction -> uv, uv -> direction, uv -> inside the layout's image area)
PROJECTORS = {
    "latlong": (latlong_to_uv, latlong_to_direction, lambda uv: np.ones(uv.shape[:-1], bool)),
    "sphere": (sphere_to_uv, sphere_to_direction, sphere_valid),
    "angular": (angular_to_uv, angular_to_direction, angular_valid),
    "cross_horizontal": (lambda d: cube_to_uv(d, "cross_horizontal"),
                         lambda uv: cube_to_direction(uv, "cross_horizontal"),
                         lambda uv: cube_valid(uv, "cross_horizontal")),
    "cross_vertical": (lambda d: cube_to_uv(d, "cross_vertical"),
                       lambda uv: cube_to_direction(uv, "cross_vertical"),
                       lambda uv: cube_valid(uv, "cross_vertical")),
}


def direction_to_uv(d, layout: str):
    """Image coordinates (u, v) in [0, 1]^2 of unit directions ``d`` (..., 3)."""
    return PROJECTORS[_check_layout(layout)][0](np.asarray(d, dtype=np.float64))


def uv_to_direction(uv, layout: str):
    """Unit directions of image coordinates ``uv`` (..., 2)."""
    return PROJECTORS[_check_layout(layout)][1](np.asarray(uv, dtype=np.float64))


def _check_layout(layout: str) -> str:
    if layout not in PROJECTORS:
        raise ParameterError(f"layout must be one of {', '.join(LAYOUTS)} (got {layout!r})")
    return layout


def detect_layout(shape, hint: str | None = None, name: str = "image") -> str:
    """The layout of an image of ``shape`` (H, W, ...) from its aspect ratio: 2:1 latlong,
    4:3 and 3:4 crosses; a square image is ``sphere`` unless ``hint`` says ``angular``.
    ``hint`` ``cube`` accepts either cross. Raises ``FileFormatError`` naming ``name``."""
    height, width = shape[:2]
    ratio = width / height
    matches = [layout for layout, aspect in ASPECTS.items() if abs(ratio - aspect) < 1e-9]
    if hint in (None, "cube") and matches and matches[0] in ("cross_horizontal",
                                                           "cross_vertical"):
        if width % (4 if matches[0] == "cross_horizontal" else 3):
            matches = []
    if hint == "cube":
        matches = [m for m in matches if m.startswith("cross")]
        if not matches:
            raise FileFormatError(
                f"{name}: a cube cross must be 4:3 (horizontal) or 3:4 (vertical) with "
                f"square faces (got {width} x {height})")
        return matches[0]
    if hint is not None:
        _check_layout(hint)
        if abs(ratio - ASPECTS[hint]) > 1e-9:
            raise FileFormatError(f"{name}: a {hint} map must have the aspect ratio "
                                  f"{ASPECTS[hint]:g} (got {width} x {height})")
        return hint
    if not matches:
        raise FileFormatError(
            f"{name}: {width} x {height} is no environment map layout (latlong 2:1, "
            "sphere or angular 1:1, cube cross 4:3 or 3:4)")
    return matches[0]


def pixel_centres(height: int, width: int):
    """(u, v) of the pixel centres, (H, W, 2)."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    uu, vv = np.meshgrid(u, v)
    return np.stack([uu, vv], axis=-1)


def _latlong_rows(height: int) -> int:
    """H - 1, the number of row intervals from pole to pole (a latlong map needs 2 rows)."""
    if height < 2:
        raise ParameterError(f"a latlong map needs at least 2 rows (got {height})")
    return height - 1


def texel_uv(height: int, width: int, layout: str):
    """(u, v) of the texels of an H x W image of ``layout``, (H, W, 2): the pixel centres,
    except that latlong rows run from pole to pole, v = i / (H - 1) (Mitsuba's ``envmap``)."""
    uv = pixel_centres(height, width)
    if _check_layout(layout) == "latlong":
        uv[..., 1] = (np.arange(height) / _latlong_rows(height))[:, None]
    return uv


def _hat_integrals(height: int, F0, F1, theta_max=np.pi):
    """integral hat_i(theta) g(theta) dtheta over [0, theta_max] for each latlong row i,
    hat_i the bilinear weight of row i (1 at theta_i, 0 at its neighbours), given
    antiderivatives F0 of g and F1 of theta g."""
    delta = np.pi / _latlong_rows(height)
    lower = np.arange(height - 1) * delta  # interval k = [theta_k, theta_k+1]: rows k, k + 1
    a, b = np.minimum(lower, theta_max), np.minimum(lower + delta, theta_max)
    g0, g1 = F0(b) - F0(a), F1(b) - F1(a)  # integral g, integral theta g over the interval
    weights = np.zeros(height)
    weights[:-1] += ((lower + delta) * g0 - g1) / delta  # falling side of row k
    weights[1:] += (g1 - lower * g0) / delta  # rising side of row k + 1
    return weights


def latlong_solid_angles(height: int, width: int):
    """Solid angle (sr) of each texel of an H x W latlong map, (H, W): the integral of its
    bilinear hat function over the sphere (module docstring); they sum to 4 pi."""
    rows = _hat_integrals(height, lambda t: -np.cos(t), lambda t: np.sin(t) - t * np.cos(t))
    return np.repeat((2 * np.pi / width) * rows[:, None], width, axis=1)


def lookup(image, uv, layout: str):
    """Bilinear lookup of ``image`` (H, W, C) at ``uv`` (..., 2) between its texels
    (:func:`texel_uv`); latlong wraps in u, as Mitsuba's ``envmap`` evaluates it."""
    height, width = image.shape[:2]
    x = uv[..., 0] * width - 0.5
    y = (uv[..., 1] * _latlong_rows(height) if layout == "latlong"
         else uv[..., 1] * height - 0.5)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]

    def at(xi, yi):
        xi = np.mod(xi, width) if layout == "latlong" else np.clip(xi, 0, width - 1)
        return image[np.clip(yi, 0, height - 1), xi]

    if layout.startswith("cross"):  # no blending across face borders: nearest texel
        return image[np.clip(np.floor(uv[..., 1] * height).astype(int), 0, height - 1),
                     np.clip(np.floor(uv[..., 0] * width).astype(int), 0, width - 1)]
    return ((1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0)
            + (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1))


def output_shape(layout: str, size: int) -> tuple[int, int]:
    """(H, W) of a ``layout`` image whose height is ``size`` (a cross: 3 or 4 faces)."""
    if layout == "latlong":
        return size, 2 * size
    if layout == "cross_horizontal":
        face = max(size // 3, 1)
        return 3 * face, 4 * face
    if layout == "cross_vertical":
        face = max(size // 4, 1)
        return 4 * face, 3 * face
    return size, size


def convert(image, source: str, target: str, size: int | None = None):
    """Resample ``image`` (H, W, C) of layout ``source`` into layout ``target``, height
    ``size`` (default: the source's height); texels outside a sphere, angular map or cross
    are 0."""
    image = np.asarray(image, dtype=np.float64)
    _check_layout(source)
    _check_layout(target)
    height, width = output_shape(target, size or image.shape[0])
    uv = texel_uv(height, width, target)
    valid = PROJECTORS[target][2](uv)
    d = uv_to_direction(uv, target)
    d = np.where(valid[..., None], d, np.array([0.0, 1.0, 0.0]))
    out = lookup(image, direction_to_uv(d, source), source)
    return np.where(valid[..., None], out, 0.0)


def horizontal_illuminance(image, layout: str, up=(0.0, 1.0, 0.0)) -> float:
    """Illuminance (lux) on a horizontal plane from the map's upper hemisphere: the
    integral of the luminance Y (Rec. 709 weights of linear RGB radiance) times cos(theta)
    over the map as Mitsuba's ``envmap`` renders it (bilinear between the texels of its
    latlong form), times K_m integral V (the photometric convention of ``spectrace help
    luminous``). For ``up`` = +Y this is exact: texel (i, j) weighs (2 pi / W) integral
    hat_i(theta) sin(theta) max(cos(theta), 0) dtheta; another ``up`` sums the texels'
    solid angles (:func:`latlong_solid_angles`) times max(up . omega, 0)."""
    latlong = image if layout == "latlong" else convert(image, layout, "latlong",
                                                        max(image.shape[0], 64))
    height, width = latlong.shape[:2]
    Y = latlong[..., :3] @ np.array([0.2126, 0.7152, 0.0722]) if latlong.shape[-1] >= 3 \
        else latlong[..., 0]
    up = np.asarray(up, dtype=np.float64)
    if np.allclose(up, (0.0, 1.0, 0.0)):
        rows = _hat_integrals(height, lambda t: np.sin(t) ** 2 / 2,
                              lambda t: np.sin(2 * t) / 8 - t * np.cos(2 * t) / 4, np.pi / 2)
        return float(LUX_PER_Y * (2 * np.pi / width) * np.sum(rows @ Y))
    d = latlong_to_direction(texel_uv(height, width, "latlong"))
    cos = np.clip(d @ up, 0.0, None)
    return float(LUX_PER_Y * np.sum(Y * cos * latlong_solid_angles(height, width)))


# -- files ----------------------------------------------------------------------------------

#: Target names of ``spectrace envmap convert --to`` -> layout.
TARGETS = {"latlong": "latlong", "cube": "cross_horizontal", "faces": "cross_horizontal",
           "cross_horizontal": "cross_horizontal", "cross_vertical": "cross_vertical",
           "sphere": "sphere", "angular": "angular"}
#: Image files read and written (linear radiance; PNG/JPEG are sRGB-decoded when read).
READ_SUFFIXES = (".exr", ".hdr", ".png", ".jpg", ".jpeg")
WRITE_SUFFIXES = (".exr", ".hdr")


def read_map(path):
    """An environment map file as (H, W, 3) float64 linear RGB."""
    from pathlib import Path

    from spectrace import images
    from spectrace.errors import FileAccessError

    path = Path(path)
    if not path.is_file():
        raise FileAccessError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix not in READ_SUFFIXES:
        raise FileFormatError(f"{path}: not an image this reads ({', '.join(READ_SUFFIXES)})")
    if suffix == ".hdr":
        import mitsuba as mi

        if mi.variant() is None:
            mi.set_variant("scalar_rgb")
        try:
            bitmap = mi.Bitmap(str(path)).convert(mi.Bitmap.PixelFormat.RGB,
                                                  mi.Struct.Type.Float32, srgb_gamma=False)
        except RuntimeError as error:
            raise FileFormatError(f"cannot read {path}: {first_line_of(error)}") from None
        return np.array(bitmap, dtype=np.float64)
    try:
        return np.asarray(images.read_image(path), dtype=np.float64)
    except Exception as error:  # noqa: BLE001 - the readers' own errors name the file
        raise FileFormatError(first_line_of(error)) from None


def first_line_of(error) -> str:
    from spectrace.errors import first_line

    return first_line(error)


def write_map(path, image) -> None:
    """Write a map atomically as float32 EXR (R, G, B) or Radiance RGBE (.hdr)."""
    from pathlib import Path

    from spectrace import images

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in WRITE_SUFFIXES:
        raise ParameterError(f"{path}: write an environment map as {' or '.join(WRITE_SUFFIXES)}")
    images.check_writable(path)
    if suffix == ".exr":
        images.write_exr(path, np.asarray(image, dtype=np.float32))
        return
    import mitsuba as mi

    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bitmap = mi.Bitmap(np.ascontiguousarray(image, dtype=np.float32), mi.Bitmap.PixelFormat.RGB)
    with images.atomic_path(path) as tmp:
        bitmap.write(tmp, mi.Bitmap.FileFormat.RGBE)


def convert_file(source_path, target_path, to: str, source_layout: str | None = None,
                 size: int | None = None, illuminance: float | None = None,
                 scale: float | None = None) -> dict:
    """Convert an environment map file to layout ``to`` (a key of :data:`TARGETS`), scaled
    by ``scale`` or to ``illuminance`` lux on a horizontal plane from the upper hemisphere.
    Nothing is written on error. Returns a summary (layouts, shape, lux before and after)."""
    if to not in TARGETS:
        raise ParameterError(f"to must be one of {', '.join(TARGETS)} (got {to!r})")
    if illuminance is not None and scale is not None:
        raise ParameterError("give either illuminance or scale, not both")
    if size is not None and size < 1:
        raise ParameterError(f"size must be >= 1 (got {size})")
    from pathlib import Path

    if to == "faces" and "{face}" not in str(target_path):
        raise ParameterError(f"{target_path}: six faces need a file name with {{face}} "
                             "(replaced by px, nx, py, ny, pz, nz)")
    if Path(target_path).suffix.lower() not in WRITE_SUFFIXES:
        raise ParameterError(
            f"{target_path}: write an environment map as {' or '.join(WRITE_SUFFIXES)}")
    if "{face}" in str(source_path):  # six separate faces
        faces = {face: read_map(str(source_path).replace("{face}", tag))
                 for tag, face in FACE_TAGS.items()}
        image, layout = assemble_cross(faces, name=str(source_path)), "cross_horizontal"
    else:
        image = read_map(source_path)
        hint = {"cube": "cube"}.get(source_layout, source_layout)
        layout = detect_layout(image.shape, hint, str(source_path))
    target = TARGETS[to]
    before = horizontal_illuminance(image, layout)
    factor = 1.0 if scale is None else float(scale)
    if illuminance is not None:
        if not before > 0:
            raise FileFormatError(f"{source_path}: the upper hemisphere is black; it cannot be "
                                  "scaled to an illuminance")
        factor = illuminance / before
    out = factor * (image if target == layout and size is None
                    else convert(image, layout, target, size))
    if not np.all(np.isfinite(out)):
        raise FileFormatError(f"{source_path}: the map holds non-finite values")
    if to == "faces":
        from spectrace import images

        for tag in FACE_TAGS:
            images.check_writable(str(target_path).replace("{face}", tag))
        faces = split_cross(out)
        for tag, face in FACE_TAGS.items():
            write_map(str(target_path).replace("{face}", tag), faces[face])
    else:
        write_map(target_path, out)
    return {"from": layout, "to": target, "shape": out.shape[:2], "lux_in": before,
            "lux_out": horizontal_illuminance(out, target), "scale": factor}


# -- irradiance environment maps (spherical harmonics, order 2) ------------------------------

#: A_l: the clamped cosine's spherical-harmonic coefficients for l = 0, 1, 2 (Ramamoorthi
#: and Hanrahan 2001, eq. 8): E(n) = sum A_l L_lm Y_lm(n).
SH_COSINE_LOBE = (np.pi, 2.0 * np.pi / 3.0, np.pi / 4.0)


#: The exact normalizations 1/(2 sqrt(pi)), sqrt(3/(4 pi)), sqrt(15/(4 pi)) of the bands
#: (0.282095, 0.488603, 1.092548 rounded in Ramamoorthi and Hanrahan 2001, eq. 3; Y_20 and
#: Y_22 take sqrt(5/(16 pi)) = c_2 / (2 sqrt(3)) and sqrt(15/(16 pi)) = c_2 / 2).
SH_NORMALIZATION = (0.5 / np.sqrt(np.pi), np.sqrt(3.0 / (4.0 * np.pi)),
                    np.sqrt(15.0 / (4.0 * np.pi)))


def sh_basis(d):
    """The 9 real spherical harmonics Y_lm (l <= 2, orthonormal on the sphere) at unit
    directions ``d`` (..., 3): (..., 9) in the order (0,0), (1,-1), (1,0), (1,1), (2,-2),
    (2,-1), (2,0), (2,1), (2,2) with y, z, x as in Ramamoorthi and Hanrahan (2001), eq. 3."""
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    c0, c1, c2 = SH_NORMALIZATION
    return np.stack([
        np.full_like(x, c0), c1 * y, c1 * z, c1 * x,
        c2 * x * y, c2 * y * z, 0.5 * c2 / np.sqrt(3.0) * (3 * z * z - 1), c2 * x * z,
        0.5 * c2 * (x * x - y * y)], axis=-1)


#: Band l of each of the 9 coefficients of :func:`sh_basis`.
SH_BANDS = (0, 1, 1, 1, 2, 2, 2, 2, 2)


def sh_project(image, layout: str = "latlong"):
    """L_lm = integral L(omega) Y_lm(omega) d omega of a map (H, W, C): (9, C), the
    integral a sum over the texels of its latlong form times their solid angles
    (:func:`latlong_solid_angles`)."""
    latlong = np.asarray(image, dtype=np.float64)
    if layout != "latlong":
        latlong = convert(latlong, layout, "latlong", max(latlong.shape[0], 64))
    height, width = latlong.shape[:2]
    d = latlong_to_direction(texel_uv(height, width, "latlong"))
    Y = sh_basis(d) * latlong_solid_angles(height, width)[..., None]
    return np.einsum("hwk,hwc->kc", Y, latlong)


def sh_irradiance(coefficients, normals):
    """Irradiance E(n) = integral L(omega) max(n . omega, 0) d omega (W/m^2, or the map's
    unit times sr) at unit ``normals`` (..., 3) from the order-2 projection
    ``coefficients`` (9, C) of :func:`sh_project`: (..., C). Exact for maps without bands
    above 2; within a few percent for natural maps (Ramamoorthi and Hanrahan 2001)."""
    A = np.array([SH_COSINE_LOBE[band] for band in SH_BANDS])
    return sh_basis(np.asarray(normals, dtype=np.float64)) @ (A[:, None] * coefficients)


def sphere_quadrature(n: int):
    """Directions (2 n^2, 3) and weights (2 n^2,) summing to 4 pi for integrals over the
    sphere: Gauss-Legendre in y = cos(theta) (n nodes) times the midpoint rule in the
    azimuth (2 n nodes, the latlong convention's phi). Exact for polynomials in (x, y, z)
    of degree < 2 n, hence for the order-2 projection of any map of degree <= 2 n - 3."""
    y, w_y = np.polynomial.legendre.leggauss(int(n))
    phi = (np.arange(2 * n) + 0.5) * (np.pi / n)
    sin_theta = np.sqrt(np.maximum(1.0 - y * y, 0.0))[:, None]
    d = np.stack(np.broadcast_arrays(sin_theta * np.sin(phi), y[:, None],
                                     -sin_theta * np.cos(phi)), axis=-1)
    w = np.broadcast_to(w_y[:, None] * (np.pi / n), d.shape[:-1])
    return d.reshape(-1, 3), np.ascontiguousarray(w).reshape(-1)


def sh_project_samples(radiance, weights, directions):
    """L_lm = sum_i w_i L(d_i) Y_lm(d_i): the order-2 projection (9, C) of radiance samples
    (N, C) at unit ``directions`` (N, 3) with quadrature ``weights`` (N,), e.g. those of
    :func:`sphere_quadrature`."""
    Y = sh_basis(np.asarray(directions, dtype=np.float64)) * np.asarray(weights)[:, None]
    return Y.T @ np.asarray(radiance, dtype=np.float64)


def sh_irradiance_coefficients(coefficients):
    """A_l L_lm (9, C): the coefficients of the irradiance E(n) = sum_k c_k Y_k(n) of
    :func:`sh_irradiance`, for evaluation elsewhere (e.g. in a Dr.Jit kernel)."""
    A = np.array([SH_COSINE_LOBE[band] for band in SH_BANDS])
    return A[:, None] * np.asarray(coefficients, dtype=np.float64)
