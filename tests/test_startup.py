"""A lean start-up: a command imports colour-science, scipy, matplotlib or Dask only when
it uses them, and ``spectrace render -q`` not even numpy, OpenEXR, Pillow or rich (issue 12
item 1).

Checked on the modules a fresh process holds when the command ends (``sys.modules``),
which is what ``python -X importtime`` lists and more: importtime does not see modules
imported through ``importlib.import_module``, which is how the command line loads its
commands."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from spectrace.cli import COMMANDS

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "showcase.xml"
#: Libraries that cost a second or more to import and that rendering does not need.
HEAVY = ("colour", "scipy", "matplotlib", "dask", "distributed", "xarray", "pandas")
#: Runs the command line in a fresh interpreter, then writes the names in sys.modules.
RUNNER = """
import json, sys
from spectrace.cli import main
try:
    code = main(sys.argv[2:])
finally:  # --help ends in SystemExit
    json.dump(sorted(sys.modules), open(sys.argv[1], "w"))
sys.exit(code)
"""


def imported_modules(args: list[str], cwd: Path) -> tuple[set[str], subprocess.CompletedProcess]:
    """The modules ``spectrace ARGS`` has imported when it ends, and the run."""
    listing = cwd / "modules.json"
    done = subprocess.run([sys.executable, "-c", RUNNER, str(listing), *args],
                          capture_output=True, text=True, cwd=cwd, timeout=300)
    modules = set(json.loads(listing.read_text())) if listing.is_file() else set()
    return modules, done


def top_level(modules: set[str]) -> set[str]:
    return {name.split(".")[0] for name in modules}


#: What ``spectrace render -q`` of the scene's own film does not need either (issue 12:
#: as lean as ``mitsuba``): OpenEXR and Pillow (``mi.Bitmap`` writes the EXR and the PNG),
#: rich (no progress bar is shown); numpy is checked on its own (the passes are summed in
#: Dr.Jit, but a plugin module may import it).
LEAN = ("OpenEXR", "PIL", "rich")
RENDER_VARIANTS = ["llvm_ad_rgb", "llvm_ad_spectral", "llvm_ad_mono"]


@pytest.fixture(scope="module")
def quiet_render(tmp_path_factory):
    """variant -> (modules, run) of ``spectrace render SCENE -q`` (8 x 8, 1 spp), once each."""
    runs = {}

    def get(variant):
        if variant not in runs:
            folder = tmp_path_factory.mktemp(variant)
            out = folder / "x.exr"
            modules, done = imported_modules(
                ["render", str(SCENE), "-o", str(out), "--variant", variant, "--spp", "1",
                 "-D", "res=8", "-q"], folder)
            assert done.returncode == 0, done.stderr[-2000:]
            assert out.is_file() and out.with_suffix(".png").is_file()
            runs[variant] = modules, done
        return runs[variant]

    return get


@pytest.mark.parametrize("variant", RENDER_VARIANTS)
def test_render_imports_no_heavy_library(quiet_render, variant):
    """``spectrace render`` of a scene (EXR and PNG written) imports mitsuba but none of
    colour-science, scipy, matplotlib, Dask."""
    modules, _ = quiet_render(variant)
    assert "mitsuba" in modules  # the import list was read
    assert top_level(modules).isdisjoint(HEAVY), sorted(top_level(modules) & set(HEAVY))


@pytest.mark.parametrize("variant", RENDER_VARIANTS)
def test_quiet_render_imports_no_openexr_pillow_rich(quiet_render, variant):
    """``spectrace render -q`` writes its EXR and PNG through Mitsuba and shows no bar: it
    imports neither OpenEXR, Pillow nor rich."""
    modules, _ = quiet_render(variant)
    assert "mitsuba" in modules
    assert top_level(modules).isdisjoint(LEAN), sorted(top_level(modules) & set(LEAN))


@pytest.mark.parametrize("variant", RENDER_VARIANTS)
def test_quiet_render_imports_no_numpy(quiet_render, variant):
    """``spectrace render -q`` imports no numpy (about 0.1 s and 14 MB that ``mitsuba``
    does not pay): the pass loop and the writers work on Dr.Jit tensors, and a plugin
    module imports numpy only inside the functions that use it."""
    modules, _ = quiet_render(variant)
    assert "mitsuba" in modules
    assert "numpy" not in modules, "numpy imported: a module imports it at its top"


@pytest.mark.parametrize("variant", RENDER_VARIANTS)
def test_render_registers_only_the_plugins_the_scene_names(quiet_render, variant):
    """``spectrace render`` sets the variant lazily: of spectrace's plugins only those the
    scene names are executed (the showcase has no ``ieslight``, ``local`` or
    ``illuminance``), and none of Mitsuba's Python integrators (it renders with ``path``),
    whose source transformation costs more than a small render."""
    modules, _ = quiet_render(variant)
    assert {"spectrace.plugins.bsdfs.phong", "spectrace.plugins.emitters.spotlight"} <= modules
    unnamed = {"spectrace.plugins.emitters.ieslight", "spectrace.plugins.integrators.local",
               "spectrace.plugins.integrators.illuminance"}
    assert not modules & unnamed, sorted(modules & unnamed)
    assert not any(m.startswith("mitsuba.python.ad.integrators.") for m in modules)


def test_import_spectrace_imports_no_numpy():
    """``import spectrace`` (and ``spectrace.render`` looked up) loads neither numpy nor
    mitsuba: ``spectrace.render`` and ``RenderResult`` come from the pass loop on first use."""
    code = ("import sys, spectrace; spectrace.render; spectrace.RenderResult; "
            "from spectrace import render; assert render is spectrace.render; "
            "bad = {'numpy', 'mitsuba', 'drjit'} & set(sys.modules); assert not bad, bad")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_command_help_imports_only_its_command(tmp_path, command):
    """``spectrace COMMAND --help`` imports that command's module, no other command, no
    mitsuba and no heavy library."""
    modules, done = imported_modules([command, "--help"], tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert COMMANDS[command][0] in modules
    others = {module for name, (module, _) in COMMANDS.items() if name != command}
    assert not modules & others, sorted(modules & others)
    assert top_level(modules).isdisjoint({"mitsuba", "drjit", *HEAVY})


def test_srgb_encoding_without_colour_science():
    """``spectrace.spectral.srgb`` (the PNG's transfer function) and the package's lazy
    names load numpy only; the colorimetry names bring colour-science when first used."""
    code = ("import sys; from spectrace.spectral import encode_srgb; encode_srgb(0.5); "
            "assert 'colour' not in sys.modules, 'colour imported'; "
            "from spectrace.spectral import spd_to_xyz; assert 'colour' in sys.modules")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
