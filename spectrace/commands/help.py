"""``spectrace help [NAME]``: a plugin's reference page, alone.

``spectrace help phong`` prints the page of the plugin whose XML type is ``phong`` (its
module docstring: parameter table, formula, sources, XML example), without Python's or
Mitsuba's inherited methods; helper pages (``falloff``, ``luminous``, ``fog``, ``lobes``,
``params``) too. ``spectrace help`` lists the pages; ``spectrace help render`` is
``spectrace render --help``. Pages are read from the plugins' source files, so the
command imports neither mitsuba nor the plugins.
"""

from __future__ import annotations

import argparse
import ast
import importlib.util

from spectrace.errors import UsageError, first_line

#: Modules of ``spectrace.plugins`` that are helper pages but not in PLUGIN_MODULES.
EXTRA_PAGES = ("params",)

#: What the marks of the parameter tables mean (Mitsuba's plugin reference uses the same).
MARKS = {
    "|exposed|": "exposed: listed by mi.traverse(), can be changed after loading",
    "|differentiable|": "differentiable: gradients flow through it",
    "|discontinuous|": "discontinuous: the image jumps where it changes (edges need care "
                       "in differentiable rendering)",
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", nargs="?", help="plugin XML type (phong, pointlight, local, "
                        "...), helper page (falloff, params, ...) or command; none: list")


def pages() -> dict[str, str]:
    """Page name -> module name under ``spectrace.plugins``, in registration order."""
    from spectrace.plugins import PLUGIN_MODULES

    names = {module.rsplit(".", 1)[-1]: module for module in PLUGIN_MODULES}
    names.update({name: name for name in EXTRA_PAGES})
    return names


def _source(module: str) -> str:
    spec = importlib.util.find_spec(f"spectrace.plugins.{module}")
    if spec is None or spec.origin is None:
        raise UsageError(f"no source for spectrace.plugins.{module}")
    with open(spec.origin, encoding="utf-8") as f:
        return f.read()


def page(name: str) -> str:
    """The reference page of ``name`` (its module docstring) with a legend of its marks."""
    modules = pages()
    if name not in modules and name.lower() in modules:
        name = name.lower()
    if name not in modules:
        import difflib

        close = difflib.get_close_matches(name.lower(), modules, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise UsageError(f"no page {name!r}; {hint}pages: {', '.join(modules)} (Mitsuba's "
                         "own plugins, such as path or diffuse, are described at "
                         "https://mitsuba.readthedocs.io)")
    text = ast.get_docstring(ast.parse(_source(modules[name])), clean=True) or ""
    legend = [f"  {mark} {meaning}" for mark, meaning in MARKS.items() if mark in text]
    if legend:
        text += "\n\nMarks\n-----\n\n" + "\n".join(legend)
    return text


def kind(module: str) -> str:
    """bsdf, emitter, integrator or helper, from the module's mi.register_* call."""
    source = _source(module)
    for plugin_kind in ("bsdf", "emitter", "integrator", "texture", "sensor"):
        if f"mi.register_{plugin_kind}(" in source:
            return plugin_kind
    return "helper"


#: Helper modules whose pages describe the machinery of plugins, not what a user sets: they
#: print with ``spectrace help NAME`` but are not listed.
UNLISTED = ("lobes", "delta")


def listing() -> str:
    """The plugins, one line each, then the helper pages that their pages refer to."""
    rows, helpers = [], []
    for name, module in pages().items():
        plugin_kind = kind(module)
        if plugin_kind == "helper":
            if name not in UNLISTED:
                helpers.append(name)
            continue
        doc = ast.get_docstring(ast.parse(_source(module))) or ""
        first = first_line(doc)
        first = first.split(":", 1)[1].strip() if first.startswith("``") and ":" in first \
            else first
        rows.append(f"  {name:<12} {plugin_kind:<11} {first.replace('``', '')}")
    return ("spectrace help NAME prints the reference page of a plugin:\n" + "\n".join(rows)
            + f"\nor of what the plugins share: {', '.join(helpers)};"
            + "\nand spectrace help COMMAND the options of a command.")


def run(args) -> int:
    if args.name is None:
        print(listing())
        return 0
    from spectrace.cli import COMMANDS, build_parser

    if args.name in COMMANDS and args.name not in pages():
        build_parser(only=args.name).parse_args([args.name, "--help"])
        return 0
    print(page(args.name))
    return 0
