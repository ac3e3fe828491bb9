"""Loading Mitsuba XML scenes with errors a user can read.

Mitsuba reports XML and plugin errors as ``RuntimeError`` with a source-location prefix
and sometimes several lines; :func:`load_scene` turns them into one-line
:class:`~spectrace.errors.UserError` messages that keep the file, line and parameter.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path

from spectrace.errors import UserError
from spectrace.signals import defer_sigint

_PARAMETER = re.compile(r"\$(\w+)")
_CPP_PREFIX = re.compile(r"\[[\w./-]+\.(?:cpp|h|py):\d+\]\s*")
# A Python plugin's exception arrives with its traceback: keep only the final message.
_PY_TRACEBACK = re.compile(r"Traceback \(most recent call last\):.*?^\w+(?:Error|Exception): ",
                           re.DOTALL | re.MULTILINE)


def one_line(message: str) -> str:
    """Mitsuba's message without ``[file.cpp:123]`` prefixes, its lines joined by '; '."""
    text = _PY_TRACEBACK.sub("", _CPP_PREFIX.sub("", str(message)))
    lines = [ln.strip(" -") for ln in text.splitlines() if ln.strip(" -")]
    return "; ".join(lines).replace(":;", ":")


def parse_defines(defines: list[str] | None) -> dict[str, str]:
    """``["name=value", ...]`` from ``-D`` options -> dict."""
    params = {}
    for item in defines or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise UserError(f"-D {item!r}: expected name=value")
        params[name.strip()] = value
    return params


def read_scene_xml(path: str | Path) -> ET.Element:
    """Parse the scene file; a missing or malformed file is a UserError naming it."""
    path = Path(path)
    if path.is_dir():
        raise UserError(f"scene {path}: is a folder, not a scene file")
    if not path.is_file():
        raise UserError(f"scene {path}: no such file")
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as e:
        raise UserError(f"scene {path}: malformed XML: {e}") from None
    except OSError as e:
        raise UserError(f"scene {path}: {e.strerror or e}") from None


def load_scene(path: str | Path, params: dict[str, str] | None = None, root=None):
    """Load a Mitsuba scene to render from ``path`` with XML parameters ``params`` (``$name``).

    The scene must have a sensor and an integrator (UserError otherwise).

    ``root``, when given, is a (possibly modified) parsed tree of that file: it is loaded
    instead of the file, with relative asset paths still resolved against the file's folder.
    """
    import mitsuba as mi

    path = Path(path)
    tree = read_scene_xml(path) if root is None else root
    if tree.tag != "scene":
        raise UserError(f"scene {path}: the root element is <{tree.tag}>, expected <scene>")
    params = {k: str(v) for k, v in (params or {}).items()}
    from spectrace import registry

    if any(element.get("name") == "source_radius" for element in tree.iter()):
        from spectrace.plugins.emitters import sized  # lights with a size: onto their shapes

        if sized.expand_tree(tree, {**scene_defaults(tree), **params}):
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
            raise UserError(_unused_parameters(path, tree, str(e))) from None
        msg = one_line(e) + _variant_hint(str(e))
        raise UserError(msg if str(path) in msg else f"scene {path}: {msg}") from None
    finally:
        _remove_path(resolver, folder)
    if not scene.sensors():
        raise UserError(f"scene {path}: no <sensor> to render from")
    if scene.integrator() is None:
        raise UserError(f'scene {path}: no <integrator> (add one, e.g. <integrator type="path"/>)')
    for sensor in scene.sensors():
        film = sensor.film()
        width, height = (int(v) for v in film.crop_size())
        if width <= 0 or height <= 0:
            full = "x".join(str(int(v)) for v in film.size())
            raise UserError(
                f"scene {path}: the film's width and height must be > 0 (got {width}x{height}"
                f"{'' if full == f'{width}x{height}' else f', full size {full}'})"
            )
    return scene


def plugin_names(tree: ET.Element, params: dict[str, str] | None = None) -> set[str]:
    """The plugin types the tree names (its ``type`` attributes), each ``$name`` in them
    replaced by its value from ``params`` or the scene's ``<default>``. Files the scene
    ``<include>``s are not read."""
    values = {**scene_defaults(tree), **(params or {})}
    return {_PARAMETER.sub(lambda m: values.get(m.group(1), m.group(0)), kind)
            for element in tree.iter() if (kind := element.get("type"))}


def scene_defaults(tree: ET.Element) -> dict[str, str]:
    """The scene's parameters: name -> value of every ``<default>`` in the tree."""
    return {d.get("name"): d.get("value", "") for d in tree.iter("default") if d.get("name")}


def _unused_parameters(path: Path, tree: ET.Element, message: str) -> str:
    """-D naming parameters the scene does not have: name them and list the scene's own."""
    names = sorted(set(re.findall(r"\$(\w+)=", message)))
    named = ", ".join(f"'{n}'" for n in names) or "some -D parameters"
    defaults = scene_defaults(tree)
    has = (f"its parameters (<default>): {', '.join(f'{k}={v}' for k, v in defaults.items())}"
           if defaults else "it has no <default> parameters")
    return f"scene {path}: -D {named}: the scene has no such parameter; {has}"


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
    return "llvm_ad_spectral_polarized" if polarized else "llvm_ad_spectral"


def _variant_hint(message: str) -> str:
    """'; render it with --variant V' when a plugin needs another polarization mode."""
    import mitsuba as mi

    if _NEEDS_POLARIZED in message:
        return f"; render it with --variant {polarized_variant(mi.variant(), True)}"
    if _REFUSES_POLARIZED in message:
        return f"; render it with --variant {polarized_variant(mi.variant(), False)}"
    return ""


def _remove_path(resolver, folder: str) -> None:
    paths = [resolver[i] for i in range(len(resolver)) if str(resolver[i]) != folder]
    resolver.clear()
    for p in paths:
        resolver.append(p)
