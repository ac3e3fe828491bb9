"""Setting the Mitsuba variant with the plugins registered when a scene needs them.

``mi.set_variant`` ends by executing Mitsuba's Python integrators (``prb``, ``prbvolpath``,
``direct_projective``, ...: the package ``mitsuba.python.ad.integrators``), whose source
Dr.Jit rewrites (``@dr.syntax``): 70 to 110 ms on these machines, longer than a small
render. spectrace's own plugins take another 15 to 25 ms. A command that renders a scene of
Mitsuba's built-in plugins needs neither, and Mitsuba's ``mitsuba`` executable pays for
neither. So the command line sets the variant with ``lazy=True`` (:func:`set_variant`), and
:func:`require` registers what a scene names just before it loads
(:func:`spectrace.scene.load_scene` calls it):

* spectrace's plugins by their XML names (:data:`spectrace.plugins.PLUGINS`);
* Mitsuba's Python integrators when the scene names a plugin that is neither spectrace's
  nor in Mitsuba's C++ library (``PluginManager.plugin_type`` knows only those).

How the Python integrators are held back: ``mi.set_variant`` reloads the package
``mitsuba.python.ad.integrators``. For the length of that one call, a finder at the head of
``sys.meta_path`` (the import system's documented hook) answers for that package alone with
a loader that executes nothing, and the package's own attributes are put back afterwards.
:func:`load_python_integrators` later reloads it for real, as ``mi.set_variant`` would have.
A Mitsuba that no longer reloads that package never asks the finder, and then nothing is
held back.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import re
import sys

#: The package of Mitsuba's Python integrators that ``mi.set_variant`` reloads.
PYTHON_INTEGRATORS = "mitsuba.python.ad.integrators"
#: The module attributes an import sets, put back after the held-back reload.
_MODULE_ATTRIBUTES = ("__spec__", "__loader__", "__path__", "__file__", "__cached__",
                      "__package__")
#: Mitsuba's words for a plugin it does not know (the name is group 1).
_NOT_FOUND = re.compile(r'Plugin "([^"]+)" not found')

#: Variants whose Python integrators were held back and are not executed yet.
_held_back: set[str] = set()


class _HoldBack:
    """A meta path finder for :data:`PYTHON_INTEGRATORS` alone, and its loader, which
    executes nothing (the protocols are duck-typed: ``importlib.abc`` would cost an
    import)."""

    def __init__(self):
        self.asked = False

    def find_spec(self, fullname, path=None, target=None):
        if fullname != PYTHON_INTEGRATORS:
            return None
        self.asked = True
        return importlib.machinery.ModuleSpec(fullname, self, is_package=True)

    def create_module(self, spec):
        return None

    def exec_module(self, module):
        pass


def set_variant(name: str, lazy: bool = False) -> None:
    """``mi.set_variant(name)``; with ``lazy``, without executing Mitsuba's Python
    integrators (:func:`load_python_integrators` does that when a scene needs them)."""
    import mitsuba as mi

    package = sys.modules.get(PYTHON_INTEGRATORS)
    if not lazy or package is None:
        mi.set_variant(name)
        _held_back.discard(name)
        return
    saved = {k: package.__dict__[k] for k in _MODULE_ATTRIBUTES if k in package.__dict__}
    finder = _HoldBack()
    sys.meta_path.insert(0, finder)
    try:
        mi.set_variant(name)
    finally:
        sys.meta_path.remove(finder)
        package.__dict__.update(saved)
    if finder.asked:
        _held_back.add(name)


def load_python_integrators() -> bool:
    """Execute Mitsuba's Python integrators for the active variant if they were held back;
    whether it did."""
    import mitsuba as mi

    variant = mi.variant()
    if variant not in _held_back:
        return False
    _held_back.discard(variant)
    importlib.reload(sys.modules[PYTHON_INTEGRATORS])
    return True


def require(names) -> bool:
    """Register the plugins among ``names`` (XML type names) that the active variant lacks;
    whether anything was registered.

    spectrace's plugins are registered by name; Mitsuba's held-back Python integrators are
    executed when some name is neither spectrace's nor one of Mitsuba's C++ plugins.
    """
    import mitsuba as mi

    from spectrace import plugins

    names = set(names)
    done = bool(plugins.register(names))  # it ignores the names that are not spectrace's
    others = names - plugins.PLUGINS.keys()
    if others and mi.variant() in _held_back:
        manager = mi.PluginManager.instance()
        if any(manager.plugin_type(n) == mi.ObjectType.Unknown for n in others):
            done = load_python_integrators() or done
    return done


def require_all() -> None:
    """Everything ``mi.set_variant`` and :func:`spectrace.plugins.register` would have
    registered for the active variant."""
    from spectrace import plugins

    load_python_integrators()
    plugins.register()


def missing_plugin(message: str) -> str | None:
    """The plugin name in Mitsuba's "Plugin "X" not found" error, or None."""
    m = _NOT_FOUND.search(message)
    return m.group(1) if m else None
