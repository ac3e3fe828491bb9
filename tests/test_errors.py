"""The library's exceptions (issue 18 A1): classes a Python caller can catch as ValueError or
OSError, messages that name function and plugin parameters (never command-line flags), one
first-line helper, and a plugin's error handed back through Mitsuba's loader as its class."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from spectrace import errors
from spectrace.errors import (
    FileAccessError,
    FileFormatError,
    ParameterError,
    SetupError,
    SpectraceError,
    UsageError,
    first_line,
)

ROOT = Path(__file__).resolve().parents[1]
#: The library: everything but the command line.
LIBRARY = [p for folder in ("spectrace", "plugins", "spectral", "photometry")
           for p in (ROOT / folder).rglob("*.py")
           if "commands" not in p.parts and p.name != "cli.py"]
SHOWCASE = ROOT / "scenes" / "showcase.xml"


def test_classes_are_the_builtin_types_a_caller_expects():
    """Values are ValueErrors, files OSErrors, every one a SpectraceError (what the command
    line turns into exit 2); UserError is gone."""
    assert issubclass(ParameterError, ValueError) and issubclass(FileFormatError, ValueError)
    assert issubclass(FileAccessError, OSError)
    for cls in (ParameterError, FileFormatError, FileAccessError, SetupError, UsageError):
        assert issubclass(cls, SpectraceError)
    assert not hasattr(errors, "UserError")


def test_first_line():
    """The first non-empty line, without Mitsuba's [file.cpp:N] location; the type name of
    an empty error."""
    assert first_line(RuntimeError("\n  [properties.cpp:693] bad value\nmore")) == "bad value"
    assert first_line(KeyError()) == "KeyError"
    assert first_line("[LowDiscrepancySampler] kept") == "[LowDiscrepancySampler] kept"
    assert first_line("") == ""


def test_library_raises_no_usage_error_and_names_no_flag_of_render():
    """No library module raises UsageError (the command line's class) or says --spp."""
    for path in LIBRARY:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.exc is not None:
                call = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
                assert getattr(call, "id", "") != "UsageError", f"{path}:{node.lineno}"
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                assert "--spp" not in node.value, f"{path}:{node.lineno}"


#: Library modules whose strings may name flags: llvm.py is its own ``python -m`` command
#: line, studies/pictures.py labels its figures with the options they show.
NAMES_FLAGS = {ROOT / "spectrace" / "llvm.py", ROOT / "spectrace" / "studies" / "pictures.py"}
FLAG = re.compile(r"(?<![\w-])--[a-z][\w-]*")


def _docstrings(tree) -> set[int]:
    kinds = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    return {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, kinds) and node.body and isinstance(node.body[0], ast.Expr)
            and isinstance(node.body[0].value, ast.Constant)}


def test_library_strings_name_no_flag():
    """No string of the library but its docstrings names a command-line flag (--plane,
    --range, --variant, --film, ...): messages name function and plugin parameters, and the
    commands translate them to their flags."""
    for path in LIBRARY:
        if path in NAMES_FLAGS:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        docs = _docstrings(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and \
                    id(node) not in docs:
                assert not FLAG.search(node.value), f"{path}:{node.lineno}: {node.value!r}"


@pytest.fixture(scope="module")
def tiny_scene(variant_rgb_module):
    from spectrace.scene import load_scene

    return load_scene(SHOWCASE, {"res": "4"})


@pytest.fixture(scope="module")
def variant_rgb_module():
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    return "llvm_ad_rgb"


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"spp": 0}, "spp must be a positive integer (got 0)"),
    ({"spp": 2.5}, "spp must be a positive integer (got 2.5)"),
    ({"spp": True}, "spp must be a positive integer (got True)"),
    ({"spp": 4, "spp_per_pass": 0}, "spp_per_pass must be a positive integer (got 0)"),
    ({"spp": 4, "spp_per_pass": 1.0}, "spp_per_pass must be a positive integer (got 1.0)"),
    ({"spp": 4, "seed": 1.5}, "seed must be an integer (got 1.5)"),
    ({"spp": 4, "seed": 2**40}, "seed must be between"),
])
def test_render_names_its_parameters(tiny_scene, kwargs, words):
    """spectrace.render(spp=0 / 2.5 / ...) is a ParameterError naming the Python parameter
    (not the flag --spp and not a bare TypeError from Dr.Jit)."""
    import spectrace

    with pytest.raises(ParameterError) as info:
        spectrace.render(tiny_scene, **kwargs)
    assert words in str(info.value) and "--" not in str(info.value)


def test_numpy_integers_are_sample_counts(tiny_scene):
    """A numpy integer is a valid count (operator.index), as Python ints are."""
    import numpy as np

    import spectrace

    assert spectrace.render(tiny_scene, spp=np.int64(4), seed=np.int32(1)).spp == 4


def test_plugin_error_comes_back_as_its_class(variant_rgb_module, tmp_path):
    """A plugin's ParameterError, which Mitsuba's loader turns into a RuntimeError holding
    the traceback, comes back from load_scene and load_bsdf as a ParameterError of one line
    with the plugin, the parameter and the file's line; Mitsuba's own errors as a
    FileFormatError."""
    from spectrace.furnace import load_bsdf
    from spectrace.scene import load_scene

    scene = tmp_path / "bad.xml"
    scene.write_text('<scene version="3.0.0"><integrator type="path"/>\n'
                     '<bsdf type="phong"><float name="exponent" value="-1"/></bsdf></scene>')
    with pytest.raises(ParameterError) as info:
        load_scene(scene)
    message = str(info.value)
    assert "\n" not in message and "Traceback" not in message
    assert f"{scene} (line 2" in message and "phong: parameter 'exponent' must be > 0" in message
    with pytest.raises(ParameterError) as info:
        load_bsdf({"type": "phong", "exponet": 2.0})
    assert str(info.value).startswith("phong: unknown parameter(s) 'exponet'")
    assert "unknown plugin" not in str(info.value)
    with pytest.raises(FileFormatError) as info:
        load_bsdf({"type": "diffuse", "exponet": 2.0})
    assert "exponet" in str(info.value) and "[parser" not in str(info.value)


def test_missing_scene_file_is_an_oserror(tmp_path):
    """A missing scene is a FileAccessError, which ``except OSError`` catches."""
    from spectrace.scene import read_scene_xml

    with pytest.raises(OSError, match="no such file"):
        read_scene_xml(tmp_path / "absent.xml")
