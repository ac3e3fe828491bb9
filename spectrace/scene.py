"""Loading Mitsuba XML scenes with errors a user can read.

Mitsuba reports XML and plugin errors as ``RuntimeError`` with a source-location prefix
and sometimes several lines (a plugin's error as its traceback); :func:`load_scene` turns
them into one-line :mod:`spectrace.errors` exceptions (:func:`load_error`) that keep the
file, line and parameter.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

from spectrace.errors import (
    FileAccessError,
    FileFormatError,
    ParameterError,
    SetupError,
    SpectraceError,
    first_line,
)
from spectrace.signals import defer_sigint

_PARAMETER = re.compile(r"\$(\w+)")
#: How Mitsuba's loader introduces the Python traceback of a plugin's constructor.
_TRACEBACK = "Traceback (most recent call last):"
#: The library's exception classes by name, as a traceback's last line names them.
_CLASSES = {cls.__name__: cls for cls in (ParameterError, FileFormatError, FileAccessError,
                                          SetupError)}


def load_error(error: BaseException) -> SpectraceError:
    """The user's mistake in a Mitsuba load error (``mi.load_file``/``load_string``/
    ``load_dict``), as one line.

    A spectrace plugin's constructor raises a :mod:`spectrace.errors` class naming the
    plugin and its parameter; Mitsuba's loader hands it on as a ``RuntimeError`` holding the
    traceback, and it comes back as that class, with the message and Mitsuba's location of
    the plugin in the file (``At scene.xml (line 3, col 2)``). Mitsuba's own errors become a
    :class:`~spectrace.errors.FileFormatError` of their lines joined by '; ', without the
    ``[parser.cpp:123]`` source locations.
    """
    text = str(error)
    head, found, trace = text.partition(_TRACEBACK)
    if found:
        last = trace.strip().splitlines()[-1]  # "spectrace.errors.ParameterError: phong: ..."
        name, _, message = last.partition(": ")
        cls = _CLASSES.get(name.rpartition(".")[2], ParameterError)
        where = first_line(head).partition(": failed to instantiate")[0]
        if where and "dictionary node" not in where:  # a file's line, not a dict's key
            message = f"{where}: {message}"
        return cls(message)
    lines = [first_line(line).strip(" -") for line in text.splitlines()]
    return FileFormatError("; ".join(ln for ln in lines if ln).replace(":;", ":"))


def read_scene_xml(path: str | Path) -> ET.Element:
    """Parse the scene file; a missing file is a FileAccessError, a malformed one a
    FileFormatError, naming it."""
    path = Path(path)
    if path.is_dir():
        raise FileAccessError(f"scene {path}: is a folder, not a scene file")
    if not path.is_file():
        raise FileAccessError(f"scene {path}: no such file")
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as e:
        raise FileFormatError(f"scene {path}: malformed XML: {e}") from None
    except OSError as e:
        raise FileAccessError(f"scene {path}: {e.strerror or e}") from None


def load_scene(path: str | Path, params: dict[str, str] | None = None, root=None):
    """Load a Mitsuba scene to render from ``path`` with XML parameters ``params`` (``$name``).

    The scene must have a sensor and an integrator (FileFormatError otherwise).

    ``root``, when given, is a (possibly modified) parsed tree of that file: it is loaded
    instead of the file, with relative asset paths still resolved against the file's folder.
    """
    import mitsuba as mi

    path = Path(path)
    tree = read_scene_xml(path) if root is None else root
    if tree.tag != "scene":
        raise FileFormatError(f"scene {path}: the root element is <{tree.tag}>, expected <scene>")
    params = {k: str(v) for k, v in (params or {}).items()}
    check_finite_numbers(tree, params, path)
    from spectrace import registry

    if any(element.get("name") == "source_radius" or element.get("type") == "ieslight"
           for element in tree.iter()):
        from spectrace.plugins.emitters import sized  # lights with a size: onto their shapes

        if sized.expand_tree(tree, {**scene_defaults(tree), **params},
                             str(path.resolve().parent)):
            root = tree

    with defer_sigint():  # plugin modules execute Mitsuba calls: no Ctrl-C inside them
        registry.require(plugin_names(tree, params))  # what a lazily set variant lacks
    resolver = mi.file_resolver()
    folder = str(path.resolve().parent)
    try:
        resolver.prepend(folder)
        while True:
            with defer_sigint() as sigint:
                try:
                    if root is None:
                        scene = mi.load_file(str(path), **params)
                    else:
                        scene = mi.load_string(ET.tostring(tree, encoding="unicode"),
                                               **params)
                    break
                except (RuntimeError, ValueError, TypeError) as e:
                    # A plugin named where plugin_names does not look (an <include>d
                    # file): registered now, then the scene is loaded again.
                    missing = registry.missing_plugin(str(e))
                    if sigint.seen or missing is None or not registry.require({missing}):
                        raise
    except (RuntimeError, ValueError, TypeError) as e:
        if sigint.seen or "KeyboardInterrupt" in str(e):
            # Ctrl-C inside a Python plugin's constructor comes back as a plugin error
            # (or leaves a half-imported module behind): an interrupt, not a mistake.
            raise KeyboardInterrupt from None
        if "unused parameters" in str(e):
            raise ParameterError(_unused_parameters(path, tree, str(e))) from None
        error = load_error(e)
        msg = str(error) + _variant_hint(str(e))
        raise type(error)(msg if str(path) in msg else f"scene {path}: {msg}") from None
    finally:
        _remove_path(resolver, folder)
    if not scene.sensors():
        raise FileFormatError(f"scene {path}: no <sensor> to render from")
    if scene.integrator() is None:
        raise FileFormatError(
            f'scene {path}: no <integrator> (add one, e.g. <integrator type="path"/>)')
    check_scene = getattr(scene.integrator(), "check_scene", None)
    if check_scene is not None:  # an integrator that needs more of the scene (local)
        try:
            check_scene(scene)
        except SpectraceError as e:
            raise type(e)(f"scene {path}: {e}") from None
    for sensor in scene.sensors():
        film = sensor.film()
        width, height = (int(v) for v in film.crop_size())
        if width <= 0 or height <= 0:
            full = "x".join(str(int(v)) for v in film.size())
            raise ParameterError(
                f"scene {path}: the film's width and height must be > 0 (got {width}x{height}"
                f"{'' if full == f'{width}x{height}' else f', full size {full}'})"
            )
    return scene


#: The elements of a Mitsuba scene that hold numbers, and their attributes that do.
_NUMBER_ATTRIBUTES = {
    "float": ("value",), "rgb": ("value",), "spectrum": ("value",),
    "point": ("value", "x", "y", "z"), "vector": ("value", "x", "y", "z"),
    "translate": ("value", "x", "y", "z"), "scale": ("value", "x", "y", "z"),
    "rotate": ("value", "x", "y", "z", "angle"), "matrix": ("value",),
    "lookat": ("origin", "target", "up"),
}
#: The largest float32: Mitsuba stores scene numbers in float32, so beyond it is infinite.
FLOAT32_MAX = 3.4028234663852886e38


def check_finite_numbers(tree: ET.Element, params: dict[str, str] | None = None,
                         path: str | Path = "scene") -> None:
    """FileFormatError unless every number the scene gives (emission, positions, transforms,
    ... : the attributes of :data:`_NUMBER_ATTRIBUTES`, with ``$name`` replaced by
    ``params`` or the scene's ``<default>``) is finite in float32: an infinite intensity, a
    power of 1e39 or a NaN translation would render a black image without an error."""
    values = {**scene_defaults(tree), **(params or {})}
    parents = {child: parent for parent in tree.iter() for child in parent}
    for element in tree.iter():
        for attribute in _NUMBER_ATTRIBUTES.get(element.tag, ()):
            text = element.get(attribute)
            if text is None:
                continue
            text = _PARAMETER.sub(lambda m: values.get(m.group(1), m.group(0)), text)
            for token in text.replace(",", " ").replace(":", " ").split():
                try:
                    number = float(token)
                except ValueError:
                    continue  # a file name, a $name left unset: Mitsuba says what it is
                if not (math.isfinite(number) and abs(number) <= FLOAT32_MAX):
                    raise FileFormatError(
                        f"scene {path}: {_where(element, parents)}: {attribute}={text!r} "
                        f"must be finite{' (beyond float32)' if math.isfinite(number) else ''}")


def _where(element: ET.Element, parents: dict) -> str:
    """``emitter 'light' (point): <rgb name="intensity">``: the element and its plugin."""
    name = element.get("name")
    shown = f'<{element.tag} name="{name}">' if name else f"<{element.tag}>"
    parent = parents.get(element)
    while parent is not None and parent.get("type") is None:
        if parent.get("name"):
            shown = f'<{parent.tag} name="{parent.get("name")}"> {shown}'
        parent = parents.get(parent)
    if parent is None or parent.tag == "scene":
        return shown
    ident = f" '{parent.get('id')}'" if parent.get("id") else ""
    return f"{parent.tag}{ident} ({parent.get('type')}): {shown}"


def plugin_names(tree: ET.Element, params: dict[str, str] | None = None) -> set[str]:
    """The plugin types the tree names (its ``type`` attributes), each ``$name`` in them
    replaced by its value from ``params`` or the scene's ``<default>``. Files the scene
    ``<include>``s are not read."""
    values = {**scene_defaults(tree), **(params or {})}
    return {_PARAMETER.sub(lambda m: values.get(m.group(1), m.group(0)), kind)
            for element in tree.iter() if (kind := element.get("type"))}


#: The film parameters a replacement film keeps (its geometry): :func:`new_film`.
FILM_GEOMETRY = ("width", "height", "crop_offset_x", "crop_offset_y", "crop_width",
                 "crop_height", "sample_border")


def new_film(sensor: ET.Element, film_type: str, keep_rfilter: bool = False) -> ET.Element:
    """Put a ``<film type=film_type>`` in ``sensor`` where its ``<film>`` was (appended when
    it has none: Mitsuba's default film), keeping the old film's ``id`` and geometry
    (:data:`FILM_GEOMETRY`; with ``keep_rfilter`` its ``<rfilter>``), values such as
    ``$res`` copied verbatim. Returns the new film, for the caller's own parameters."""
    old = sensor.find("film")
    film = ET.Element("film", {"type": film_type})
    if old is None:
        sensor.append(film)
        return film
    if "id" in old.attrib:
        film.set("id", old.get("id"))
    for child in old:
        if child.get("name") in FILM_GEOMETRY or (keep_rfilter and child.tag == "rfilter"):
            film.append(child)
    sensor.insert(list(sensor).index(old), film)
    sensor.remove(old)
    return film


def uses_parameter(tree: ET.Element, name: str) -> bool:
    """Whether an attribute of the tree refers to the parameter ``$name`` (Mitsuba refuses
    a parameter given to a scene that never uses it)."""
    return any(m.group(1) == name for element in tree.iter()
               for value in element.attrib.values() for m in _PARAMETER.finditer(value))


def scene_defaults(tree: ET.Element) -> dict[str, str]:
    """The scene's parameters: name -> value of every ``<default>`` in the tree."""
    return {d.get("name"): d.get("value", "") for d in tree.iter("default") if d.get("name")}


def _unused_parameters(path: Path, tree: ET.Element, message: str) -> str:
    """``params`` naming parameters the scene does not have: name them and list the scene's
    own."""
    names = sorted(set(re.findall(r"\$(\w+)=", message)))
    named = ", ".join(f"'{n}'" for n in names) or "some of the given ones"
    defaults = scene_defaults(tree)
    has = (f"its parameters (<default>): {', '.join(f'{k}={v}' for k, v in defaults.items())}"
           if defaults else "it has no <default> parameters")
    return f"scene {path}: parameter {named}: the scene has no such parameter; {has}"


#: Mitsuba's words for a plugin that needs (or refuses) a polarized variant.
_NEEDS_POLARIZED = "only be used in polarized mode"
_REFUSES_POLARIZED = "not support polarized mode"


def polarized_variant(variant: str, polarized: bool) -> str:
    """The variant closest to ``variant`` that is (or is not) polarized: the same backend
    and colour mode where Mitsuba has it (there is no polarized RGB: spectral then)."""
    import mitsuba as mi

    base = variant.removesuffix("_polarized")
    backend = base.rsplit("_", 1)[0]  # llvm_ad, cuda_ad, scalar
    wanted = [f"{base}_polarized", f"{backend}_spectral_polarized"] if polarized else [base]
    for name in wanted:
        if name in mi.variants():
            return name
    from spectrace import DEFAULT_VARIANT

    return f"{DEFAULT_VARIANT}_polarized" if polarized else DEFAULT_VARIANT


def _variant_hint(message: str) -> str:
    """'; it needs the variant V' when a plugin needs another polarization mode."""
    import mitsuba as mi

    if _NEEDS_POLARIZED in message:
        return f"; it needs the variant {polarized_variant(mi.variant(), True)}"
    if _REFUSES_POLARIZED in message:
        return f"; it needs the variant {polarized_variant(mi.variant(), False)}"
    return ""


def _remove_path(resolver, folder: str) -> None:
    paths = [resolver[i] for i in range(len(resolver)) if str(resolver[i]) != folder]
    resolver.clear()
    for p in paths:
        resolver.append(p)
