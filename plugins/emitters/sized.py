"""``sized``: lights with a size, one scene element each (helper page, not a plugin).

``pointlight`` and ``spotlight`` take ``source_radius``: the light is then a sphere (point
light) or a disk facing the spot's +Z (spot light) that emits the radiance of ``opening``
(L = I / A_proj), so that it casts soft shadows, lights the near field correctly and far
away is the point light. To be *seen* (camera rays, reflections) and to be hit by the rays
that a BSDF samples (multiple importance sampling in Mitsuba's ``path``, ``volpath`` and
``direct``), a light must be attached to a Mitsuba shape: the light is then an area emitter
(``mi.EmitterFlags.Surface``) of a ``sphere`` or ``disk`` with a black ``diffuse`` BSDF.

Design: the user keeps writing one ``<emitter>``. spectrace's scene loader
(``spectrace.scene.load_scene``: ``spectrace render``, ``lux``, ``sweep``, ...) rewrites
every ``pointlight``/``spotlight`` outside a ``<shape>`` whose ``source_radius`` is > 0
(after ``$name`` substitution; files the scene ``<include>``s are not rewritten) into that
shape with the emitter inside (:func:`expand_tree`); Python users of
``mi.load_dict`` call :func:`expand_dict` on their scene dictionary (Mitsuba 3.9 lets a
Python plugin neither add objects to a scene nor override ``Object::expand``, the C++ hook
that expands one element into several). The emitter takes its geometry from its own
parameters (``position`` or ``to_world``, ``source_radius``); the shape is where rays meet
it. A sized light that is not attached to a shape (``mi.load_file`` of the XML without
spectrace's loader) still casts its soft shadows through next-event estimation, marking its
samples as delta (``ds.delta``) so that integrators give them the full weight, but camera
and BSDF rays do not see it. Its flags are empty, neither ``DeltaPosition`` nor
``Surface``: Mitsuba 3.9's scene keeps a top-level emitter only when it is not flagged
``Surface`` (``src/render/scene.cpp``), and a shape registers its emitter whatever the
flags.

Parameters
----------

=================  ======  =======  ====  ===================================================
parameter          type    default  unit  description
=================  ======  =======  ====  ===================================================
``source_radius``  float   0        m     radius of the emitting sphere or disk, >= 0; 0: the
                                          delta light, exactly as before
=================  ======  =======  ====  ===================================================

With ``source_radius`` > 0 the distance law must be ``inverse_square`` (the other laws of
``falloff`` describe no emitting surface) and ``to_world`` must be rigid (rotation and
translation, as ``lookat`` gives: the size is ``source_radius``). ``source_radius`` is read
at load (not exposed); moving a sized light through ``mi.traverse`` (``position``,
``to_world``) moves its emission but not its shape: move the shape too. The shape is
black (it absorbs what falls on it) and opaque (it casts a shadow on what lies behind).

Formula
-------

::

    sphere:  L = I / (pi r^2)                      (flux 4 pi I, as the point light)
    disk:    L(omega) = I(omega) / (pi r^2 cos gamma)  (gamma from the spot's +Z)

Sources
-------

Pharr, Jakob, Humphreys (2023), *Physically Based Rendering* 4th ed., sec. 12.5 (area
lights); Jakob, Speierer, Roussel et al. (2022), Mitsuba 3, ``src/emitters/area.cpp`` (the
area-emitter interface reproduced) and ``src/render/python/emitter_v.cpp`` (what a Python
emitter may override).

Example
-------

A 5 cm bulb; ``spectrace render`` expands it into a sphere carrying the light::

    <emitter type="pointlight">
        <point name="position" x="0" y="2" z="0"/>
        <float name="luminous_flux" value="800"/>
        <float name="source_radius" value="0.05"/>
    </emitter>
"""

from __future__ import annotations

import copy
import math
import re
import xml.etree.ElementTree as ET

from spectrace.errors import ParameterError

#: XML type of a sizable light -> the Mitsuba shape it becomes.
SHAPES = {"pointlight": "sphere", "spotlight": "disk"}
#: Largest deviation of to_world's 3x3 part from a rotation for a sized light.
RIGID_TOLERANCE = 1e-4
_PARAMETER = re.compile(r"\$(\w+)")


def read_source_radius(props, plugin: str) -> float:
    """``source_radius`` (m, finite, >= 0; 0 when absent)."""
    from spectrace.plugins import params

    return params.read_float(props, plugin, "source_radius", 0.0, minimum=0.0, finite=True)


def check_sized(plugin: str, law, to_world=None) -> None:
    """A sized light needs the inverse-square law and a rigid ``to_world``."""
    if repr(law) != "inverse_square":
        raise ParameterError(
            f"{plugin}: parameter 'falloff' must be inverse_square with source_radius > 0 "
            f"(got {law!r})"
        )
    if to_world is not None:
        import numpy as np

        m = np.array(to_world.matrix, dtype=np.float64).reshape(4, 4)[:3, :3]
        if not np.allclose(m.T @ m, np.eye(3), atol=RIGID_TOLERANCE):
            raise ParameterError(
                f"{plugin}: parameter 'to_world' must be a rotation and translation with "
                "source_radius > 0 (its size is source_radius)"
            )


def direction_sample(emitter, it, p, n, pdf):
    """The ``mi.DirectionSample3f`` from ``it`` to the point ``p`` (normal ``n``) of the
    light's surface with density ``pdf``; delta when the light has no shape (see above)."""
    import drjit as dr
    import mitsuba as mi

    ds = dr.zeros(mi.DirectionSample3f)
    ds.p = p
    ds.n = n
    ds.time = it.time
    ds.pdf = pdf
    ds.delta = emitter.get_shape() is None
    ds.emitter = mi.EmitterPtr(emitter)
    d = mi.Vector3f(p - it.p)
    dist2 = dr.squared_norm(d)
    ds.dist = dr.sqrt(dist2)
    ds.d = d * dr.rsqrt(dist2)
    return ds


def spawn_ray(p, n, d, time, wavelengths):
    """The ray leaving the light's surface point ``p`` (normal ``n``) along ``d``, offset
    as Mitsuba offsets rays leaving surfaces (so that it does not hit its own shape)."""
    import drjit as dr
    import mitsuba as mi

    si = dr.zeros(mi.SurfaceInteraction3f)
    si.p = p
    si.n = n
    si.time = time
    si.wavelengths = wavelengths
    return si.spawn_ray(d)


def position_sample(time, p, n, area):
    """A ``mi.PositionSample3f`` uniform by area and its weight (the area)."""
    import drjit as dr
    import mitsuba as mi

    ps = dr.zeros(mi.PositionSample3f)
    ps.p = p
    ps.n = n
    ps.time = time
    ps.pdf = dr.rcp(area)
    ps.delta = False
    return ps, mi.Float(area)


# -- the expansion into shapes ---------------------------------------------------------------


def _black_bsdf_xml() -> ET.Element:
    bsdf = ET.Element("bsdf", type="diffuse")
    ET.SubElement(bsdf, "float", name="reflectance", value="0")
    return bsdf


def _radius_value(element: ET.Element, values: dict[str, str]):
    """The raw and the resolved ``source_radius`` of a light element (None when absent)."""
    for child in element:
        if child.get("name") == "source_radius":
            raw = child.get("value", "")
            resolved = _PARAMETER.sub(lambda m: values.get(m.group(1), m.group(0)), raw)
            try:
                return raw, float(resolved)
            except ValueError:
                return raw, None
    return None, None


def _shape_xml(element: ET.Element, raw_radius: str) -> ET.Element:
    kind = element.get("type")
    shape = ET.Element("shape", type=SHAPES[kind])
    to_world = next((c for c in element if c.tag == "transform"
                     and c.get("name") == "to_world"), None)
    if kind == "pointlight":
        position = next((c for c in element if c.get("name") == "position"), None)
        if position is not None:
            center = copy.deepcopy(position)
            center.set("name", "center")
            shape.append(center)
        elif to_world is not None:
            shape.append(copy.deepcopy(to_world))
        ET.SubElement(shape, "float", name="radius", value=raw_radius)
    else:
        transform = ET.SubElement(shape, "transform", name="to_world")
        ET.SubElement(transform, "scale", x=raw_radius, y=raw_radius, z="1")
        if to_world is not None:
            transform.extend(copy.deepcopy(list(to_world)))
    shape.append(_black_bsdf_xml())
    shape.append(element)
    return shape


def expand_tree(root: ET.Element, values: dict[str, str] | None = None,
                folder=None) -> bool:
    """Rewrite, in place, every ``pointlight``/``spotlight`` element of ``root`` that is not
    inside a ``<shape>`` and whose ``source_radius`` is > 0 (``$name`` replaced from
    ``values``) into a black sphere or disk that carries it, and every ``ieslight`` with an
    opening into its shape (:func:`expand_ies_tree`, files looked up in ``folder``).
    Returns whether it changed anything."""
    values = values or {}
    changed = expand_ies_tree(root, values, folder)
    for parent in root.iter():
        if parent.tag == "shape":
            continue
        for index, element in enumerate(list(parent)):
            if element.tag != "emitter" or element.get("type") not in SHAPES:
                continue
            raw, radius = _radius_value(element, values)
            if radius is None or not radius > 0 or not math.isfinite(radius):
                continue  # absent, 0 or invalid: the plugin itself reports a bad value
            parent.remove(element)
            parent.insert(index, _shape_xml(element, raw))
            changed = True
    return changed


def expand_dict(scene: dict) -> dict:
    """The ``mi.load_dict`` scene dictionary with each top-level ``pointlight`` or
    ``spotlight`` of ``source_radius`` > 0 carried by its black sphere or disk, and each
    ``ieslight`` with an opening by its shape (:func:`expand_ies_dict`; a new dictionary;
    the others entries are kept as they are)."""
    import mitsuba as mi

    scene = expand_ies_dict(scene)
    out = {}
    for key, value in scene.items():
        radius = value.get("source_radius", 0.0) if isinstance(value, dict) else 0.0
        if (not isinstance(value, dict) or value.get("type") not in SHAPES
                or not isinstance(radius, (int, float)) or not radius > 0):
            out[key] = value
            continue
        shape = {"type": SHAPES[value["type"]],
                 "bsdf": {"type": "diffuse", "reflectance": 0.0}, "emitter": value}
        to_world = value.get("to_world", mi.ScalarTransform4f())
        if value["type"] == "pointlight":
            if "position" in value:
                shape["center"] = value["position"]
            else:
                shape["to_world"] = to_world
            shape["radius"] = float(radius)
        else:
            shape["to_world"] = mi.ScalarTransform4f(to_world) @ mi.ScalarTransform4f().scale(
                [float(radius), float(radius), 1.0])
        out[key] = shape
    return out


# -- the luminous openings of ieslight -----------------------------------------------------

#: ``ieslight``'s ``opening`` -> the size parameters it takes (m, each > 0). ``file``: the
#: shape and size that the photometric file gives; ``point``: the delta light.
IES_OPENINGS = {
    "file": (),
    "point": (),
    "rectangle": ("width", "length"),
    "disk": ("diameter",),
    "sphere": ("diameter",),
    "box": ("width", "length", "height"),
    "cylinder": ("diameter", "height"),
}
#: Every size parameter of ``ieslight``'s openings.
IES_SIZES = ("width", "length", "height", "diameter")
#: The openings of ``Photometry.opening`` that ``ieslight`` renders -> its ``opening``.
IES_FILE_SHAPES = {"point": "point", "rectangle": "rectangle", "disk": "disk",
                   "sphere": "sphere", "box": "box", "vertical_cylinder": "cylinder"}
#: ``ieslight`` opening -> the Mitsuba shape that carries it.
#: (``cylinder``: a closed mesh made at load, see :func:`cylinder_shape`.)
IES_SHAPES = {"rectangle": "rectangle", "disk": "disk", "sphere": "sphere", "box": "cube",
              "cylinder": "mesh"}
#: Sides of the mesh that carries a ``cylinder`` opening (its area is within 1e-4 of the
#: cylinder's, which the light samples exactly).
CYLINDER_SEGMENTS = 256


def resolve_opening(values: dict, file_opening, plugin: str = "ieslight"):
    """The kind of an ``ieslight``'s opening ("point", "rectangle", "disk", "sphere",
    "box", "cylinder") and its half-extents (hx, hy, hz) along local x (C0-C180, the
    length), y (C90-C270, the width) and z (the height; 0 for a flat opening; a radius for
    disks and spheres; hx = hy the radius of a cylinder), from ``values`` (``opening``
    and the size parameters; None when absent) and the file's ``Opening``
    (``file_opening``: a callable returning it, or None).

    Raises ``ParameterError`` naming the parameter: an unknown opening, a size that does
    not apply to it, a missing, negative, NaN or zero size."""
    name = values.get("opening")
    name = "file" if name is None else name
    if name not in IES_OPENINGS:
        raise ParameterError(f"{plugin}: parameter 'opening' must be one of "
                             f"{', '.join(IES_OPENINGS)} (got {name!r})")
    needed = IES_OPENINGS[name]
    for size in IES_SIZES:
        if values.get(size) is not None and size not in needed:
            takes = ", ".join(needed) or "no size"
            raise ParameterError(f"{plugin}: parameter '{size}' does not apply to opening "
                                 f"'{name}' (it takes {takes})")
    sizes = {}
    for size in needed:
        value = values.get(size)
        if value is None:
            raise ParameterError(f"{plugin}: parameter '{size}' (m) is required with opening "
                                 f"'{name}'")
        if not (math.isfinite(value) and value > 0.0):
            raise ParameterError(f"{plugin}: parameter '{size}' must be a finite size > 0 m "
                                 f"(got {value:g}: a degenerate opening)")
        sizes[size] = float(value)
    if name == "point":
        return "point", (0.0, 0.0, 0.0)
    if name == "file":
        opening = None if file_opening is None else file_opening()
        if opening is None or opening.shape == "point":
            return "point", (0.0, 0.0, 0.0)
        if opening.shape not in IES_FILE_SHAPES:
            raise ParameterError(
                f"{plugin}: parameter 'opening': the file's luminous opening is a "
                f"{opening.shape.replace('_', ' ')}, which the light does not render; give "
                f"opening 'point' or one of {', '.join(IES_SHAPES)} with its sizes")
        name = IES_FILE_SHAPES[opening.shape]
        sizes = {"width": opening.width, "length": opening.length,
                 "height": opening.height, "diameter": opening.width}
        if any(not sizes[s] > 0.0 for s in IES_OPENINGS[name]):
            raise ParameterError(f"{plugin}: parameter 'opening': the file's {name} has a "
                                 "zero size (a degenerate opening); give opening 'point'")
    if name == "rectangle":
        return name, (0.5 * sizes["length"], 0.5 * sizes["width"], 0.0)
    if name == "box":
        return name, (0.5 * sizes["length"], 0.5 * sizes["width"], 0.5 * sizes["height"])
    if name == "cylinder":
        radius = 0.5 * sizes["diameter"]
        return name, (radius, radius, 0.5 * sizes["height"])
    radius = 0.5 * sizes["diameter"]
    return name, (radius, radius, radius if name == "sphere" else 0.0)


def _ies_values(element: ET.Element, values: dict[str, str]):
    """The ``filename``, ``opening`` and sizes of an ``ieslight`` element (``$name``
    resolved), or None when one does not parse (the plugin then reports it)."""
    found = {}
    for child in element:
        name = child.get("name")
        if name in ("filename", "opening", *IES_SIZES):
            raw = _PARAMETER.sub(lambda m: values.get(m.group(1), m.group(0)),
                                 child.get("value", ""))
            if name in IES_SIZES:
                try:
                    raw = float(raw)
                except ValueError:
                    return None
            found[name] = raw
    return found


def _ies_opening(found: dict, folder=None):
    """The resolved opening of an ``ieslight``'s parameters, or None when it is a point
    or cannot be resolved (the plugin reports the error at load)."""
    from pathlib import Path

    from spectrace.errors import SpectraceError

    def file_opening():
        from spectrace.photometry import read_photometry

        path = Path(found.get("filename", ""))
        if folder is not None and not path.is_absolute() and (Path(folder) / path).is_file():
            path = Path(folder) / path
        return read_photometry(path).opening

    if found is None or (found.get("opening", "file") == "file" and "filename" not in found):
        return None
    try:
        kind, half = resolve_opening(found, file_opening)
    except (SpectraceError, OSError, ValueError):
        return None
    return None if kind == "point" else (kind, half)


def _ies_scale(kind: str, half) -> tuple[float, float, float]:
    """The scale of the Mitsuba shape (rectangle, disk, sphere: unit; cube: [-1, 1]^3)."""
    hx, hy, hz = half
    return (hx, hy, 1.0) if kind in ("rectangle", "disk") else (hx, hy, hz)


def _ies_shape_xml(element: ET.Element, kind: str, half) -> ET.Element:
    if kind == "cylinder":  # Mitsuba's own cylinder is open: the closed mesh from a file
        shape = ET.Element("shape", type="ply")
        ET.SubElement(shape, "string", name="filename", value=unit_cylinder_ply())
    else:
        shape = ET.Element("shape", type=IES_SHAPES[kind])
    transform = ET.SubElement(shape, "transform", name="to_world")
    x, y, z = (repr(float(v)) for v in _ies_scale(kind, half))
    ET.SubElement(transform, "scale", x=x, y=y, z=z)
    to_world = next((c for c in element if c.tag == "transform"
                     and c.get("name") == "to_world"), None)
    if to_world is not None:
        transform.extend(copy.deepcopy(list(to_world)))
    shape.append(_black_bsdf_xml())
    shape.append(element)
    return shape


def expand_ies_tree(root: ET.Element, values: dict[str, str] | None = None,
                    folder=None) -> bool:
    """Rewrite, in place, every ``ieslight`` of ``root`` outside a ``<shape>`` whose
    opening is not a point (its ``opening``, or the file's: a relative ``filename`` is
    looked up in ``folder``) into the black rectangle, disk, sphere or cube that carries
    it (a cylinder: the closed mesh of :func:`unit_cylinder_ply`, scaled). Returns whether
    it changed anything."""
    values = values or {}
    changed = False
    for parent in root.iter():
        if parent.tag == "shape":
            continue
        for index, element in enumerate(list(parent)):
            if element.tag != "emitter" or element.get("type") != "ieslight":
                continue
            resolved = _ies_opening(_ies_values(element, values), folder)
            if resolved is None:
                continue
            parent.remove(element)
            parent.insert(index, _ies_shape_xml(element, *resolved))
            changed = True
    return changed


def expand_ies_dict(scene: dict) -> dict:
    """The ``mi.load_dict`` scene dictionary with each top-level ``ieslight`` whose opening
    is not a point carried by its black shape (a new dictionary; a cylinder: the
    ``mi.Mesh`` of :func:`cylinder_shape`)."""
    import mitsuba as mi

    out = {}
    for key, value in scene.items():
        resolved = None
        if isinstance(value, dict) and value.get("type") == "ieslight":
            found = {k: value[k] for k in ("filename", "opening", *IES_SIZES) if k in value}
            if all(isinstance(found.get(k, 0.0), (int, float)) for k in IES_SIZES):
                resolved = _ies_opening(found)
        if resolved is None:
            out[key] = value
            continue
        kind, half = resolved
        to_world = mi.ScalarTransform4f(value.get("to_world", mi.ScalarTransform4f()))
        if kind == "cylinder":
            out[key] = cylinder_shape(mi.load_dict(value), to_world, half)
            continue
        out[key] = {"type": IES_SHAPES[kind],
                    "to_world": to_world @ mi.ScalarTransform4f().scale(
                        list(_ies_scale(kind, half))),
                    "bsdf": {"type": "diffuse", "reflectance": 0.0}, "emitter": value}
    return out


def unit_cylinder_ply() -> str:
    """The path of the closed unit cylinder of :func:`opening.cylinder_mesh` (radius 1, z
    from -1 to 1, CYLINDER_SEGMENTS sides) as an ASCII PLY file, which an XML scene's
    ``<shape type="ply">`` loads: written once, atomically, to the user's cache folder
    (``$XDG_CACHE_HOME`` or ``~/.cache``)/spectrace, or to the temporary folder when that
    cannot be written."""
    import tempfile
    from pathlib import Path

    from spectrace.plugins.cache import cache_folder
    from spectrace.plugins.emitters import opening

    from spectrace.errors import FileAccessError
    from spectrace.images import atomic_path

    name = f"unit_cylinder_{CYLINDER_SEGMENTS}.ply"
    folders = (cache_folder(), Path(tempfile.gettempdir()) / "spectrace")
    for folder in folders:
        if (folder / name).is_file():
            return str(folder / name)
    vertices, faces = opening.cylinder_mesh(CYLINDER_SEGMENTS)
    lines = ["ply", "format ascii 1.0", f"element vertex {len(vertices)}",
             "property float x", "property float y", "property float z",
             f"element face {len(faces)}", "property list uchar int vertex_indices",
             "end_header"]
    lines += [" ".join(f"{c:.9g}" for c in v) for v in vertices]
    lines += ["3 " + " ".join(str(int(i)) for i in f) for f in faces]
    for folder in folders:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            with atomic_path(folder / name) as tmp, open(tmp, "w") as f:
                f.write("\n".join(lines) + "\n")
            return str(folder / name)
        except OSError:
            continue
    raise FileAccessError(f"ieslight: cannot write the cylinder mesh {name} to "
                          f"{' or '.join(str(f) for f in folders)}")


def cylinder_shape(emitter, to_world, half):
    """The closed cylinder (half-extents ``half`` = (r, r, hz) along the local axes of
    ``to_world``) as ONE black ``mi.Mesh`` of CYLINDER_SEGMENTS sides carrying the loaded
    ``emitter`` (Mitsuba's own ``cylinder`` is open, and an emitter has one shape)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np
    from spectrace.plugins.emitters import opening

    vertices, faces = opening.cylinder_mesh(CYLINDER_SEGMENTS)
    matrix = np.array(to_world.matrix, dtype=np.float64) @ np.diag([*half, 1.0])
    world = vertices.astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
    props = mi.Properties()
    props["emitter"] = emitter
    props["bsdf"] = mi.load_dict({"type": "diffuse", "reflectance": 0.0})
    mesh = mi.Mesh("ieslight_cylinder", len(world), len(faces), props)
    params = mi.traverse(mesh)
    params["vertex_positions"] = dr.ravel(mi.Point3f(world.T.astype(np.float32)))
    params["faces"] = dr.ravel(mi.Vector3u(faces.T))
    params.update()
    return mesh
