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
    resolver = mi.file_resolver()
    folder = str(path.resolve().parent)
    try:
        resolver.prepend(folder)
        if root is None:
            scene = mi.load_file(str(path), **params)
        else:
            scene = mi.load_string(ET.tostring(tree, encoding="unicode"), **params)
    except (RuntimeError, ValueError, TypeError) as e:
        msg = one_line(e)
        raise UserError(msg if str(path) in msg else f"scene {path}: {msg}") from None
    finally:
        _remove_path(resolver, folder)
    if not scene.sensors():
        raise UserError(f"scene {path}: no <sensor> to render from")
    if scene.integrator() is None:
        raise UserError(f'scene {path}: no <integrator> (add one, e.g. <integrator type="path"/>)')
    return scene


def _remove_path(resolver, folder: str) -> None:
    paths = [resolver[i] for i in range(len(resolver)) if str(resolver[i]) != folder]
    resolver.clear()
    for p in paths:
        resolver.append(p)
