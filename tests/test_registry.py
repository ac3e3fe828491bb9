"""Plugins registered when a scene needs them (spectrace.registry, spectrace.plugins.register).

Each check runs in a fresh interpreter, since what is registered is the state of a process:
a script sets the variant as the command line does (``lazy=True``), loads scenes, and
prints what it found as JSON. Oracles: ``sys.modules`` (which plugin modules were
executed), Mitsuba's own plugin lookup (a scene loads or fails), and the images of a full
``spectrace.set_variant``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from spectrace import plugins

ROOT = Path(__file__).resolve().parents[1]
#: The module of one of Mitsuba's Python integrators (``prb``) and of some spectrace plugins.
PRB = "mitsuba.python.ad.integrators.prb"
PHONG = "spectrace.plugins.bsdfs.phong"
IESLIGHT = "spectrace.plugins.emitters.ieslight"

SENSOR = """
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/>
            <integer name="height" value="16"/></film>
    </sensor>
    <emitter type="constant"/>
"""


def scene_xml(integrator: str = "path", bsdf: str = "diffuse", extra: str = "",
              defaults: str = "") -> str:
    return (f'<scene version="3.0.0">{defaults}<integrator type="{integrator}"/>{SENSOR}'
            f'<shape type="sphere"><bsdf type="{bsdf}"/></shape>{extra}</scene>')


def run_script(body: str, cwd: Path) -> dict:
    """Run ``body`` after ``import spectrace`` in a fresh interpreter; its JSON answer."""
    script = "import json, sys\nimport spectrace\n" + textwrap.dedent(body)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          cwd=cwd, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


LOAD = """
from spectrace.scene import load_scene
def load(name, **params):
    return load_scene(name, params)
def has(module):
    return module in sys.modules
"""


def test_lazy_variant_executes_no_plugin_module(tmp_path):
    """A lazily set variant executes neither Mitsuba's Python integrators nor spectrace's
    plugins, and a scene of built-in plugins loads and renders without them."""
    (tmp_path / "builtin.xml").write_text(scene_xml())
    answer = run_script(LOAD + """
PREFIXES = ("spectrace.plugins.", "mitsuba.python.ad.integrators.")
spectrace.set_variant("llvm_ad_rgb", lazy=True)
before = [m for m in sys.modules if m.startswith(PREFIXES)]
result = spectrace.render(load("builtin.xml"), spp=4)
after = [m for m in sys.modules if m.startswith(PREFIXES)]
print(json.dumps({"before": before, "after": after, "mean": float(result.image.mean())}))
""", tmp_path)
    assert answer["before"] == [] and answer["after"] == []
    assert answer["mean"] > 0


def test_scene_registers_the_plugins_it_names(tmp_path):
    """A scene naming ``prb`` and ``phong`` gets Mitsuba's Python integrators and phong
    (with its helpers), not the plugins it does not name (``ieslight``)."""
    (tmp_path / "s.xml").write_text(scene_xml("prb", "phong"))
    answer = run_script(LOAD + f"""
spectrace.set_variant("llvm_ad_rgb", lazy=True)
scene = load("s.xml")
print(json.dumps({{"prb": has("{PRB}"), "phong": has("{PHONG}"), "ies": has("{IESLIGHT}"),
                  "integrator": type(scene.integrator()).__name__}}))
""", tmp_path)
    assert answer == {"prb": True, "phong": True, "ies": False, "integrator": "PRBIntegrator"}


def test_parameter_typed_plugin_is_registered(tmp_path):
    """``type="$bsdf"`` is resolved from the scene's <default> and from -D values."""
    (tmp_path / "s.xml").write_text(scene_xml(
        bsdf="$bsdf", defaults='<default name="bsdf" value="phong"/>'))
    answer = run_script(LOAD + """
spectrace.set_variant("llvm_ad_rgb", lazy=True)
a = type(load("s.xml").shapes()[0].bsdf()).__name__
b = type(load("s.xml", bsdf="blinnphong").shapes()[0].bsdf()).__name__
print(json.dumps([a, b]))
""", tmp_path)
    assert answer == ["Phong", "BlinnPhong"]


def test_plugin_named_in_an_included_file_is_registered(tmp_path):
    """A plugin that only an <include>d file names is registered when Mitsuba reports it
    missing, and the scene loads on the second try."""
    (tmp_path / "part.xml").write_text(
        '<scene version="3.0.0"><shape type="sphere"><bsdf type="blinnphong"/></shape>'
        "</scene>")
    (tmp_path / "s.xml").write_text(scene_xml(extra='<include filename="part.xml"/>'))
    answer = run_script(LOAD + """
spectrace.set_variant("llvm_ad_rgb", lazy=True)
scene = load("s.xml")
print(json.dumps(sorted(type(s.bsdf()).__name__ for s in scene.shapes())))
""", tmp_path)
    assert len(answer) == 2 and "BlinnPhong" in answer


def test_unknown_plugin_is_still_one_error(tmp_path):
    """A plugin nobody registers is refused as before: a FileFormatError naming it."""
    (tmp_path / "s.xml").write_text(scene_xml(bsdf="nosuchbsdf"))
    answer = run_script(LOAD + """
spectrace.set_variant("llvm_ad_rgb", lazy=True)
try:
    load("s.xml")
    print(json.dumps("loaded"))
except spectrace.errors.FileFormatError as e:
    print(json.dumps(str(e)))
""", tmp_path)
    assert "nosuchbsdf" in answer and "not found" in answer and "\n" not in answer


def test_full_variant_after_lazy_registers_everything(tmp_path):
    """``spectrace.set_variant(v)`` after a lazy one of the same variant registers every
    plugin (what notebooks rely on: ``mi.load_dict`` of any plugin), and a lazy switch to
    another variant registers its plugins on demand there too."""
    (tmp_path / "s.xml").write_text(scene_xml("prb", "phong"))
    answer = run_script(LOAD + """
import mitsuba as mi
spectrace.set_variant("llvm_ad_rgb", lazy=True)
spectrace.set_variant("llvm_ad_rgb")
full = [type(mi.load_dict({"type": t})).__name__ for t in ("prb", "pointlight")]
spectrace.set_variant("llvm_ad_mono", lazy=True)
scene = load("s.xml")
mono = [type(scene.integrator()).__name__, type(scene.shapes()[0].bsdf()).__name__]
image = spectrace.render(scene, spp=4).image
print(json.dumps({"full": full, "mono": mono, "finite": bool((image == image).all())}))
""", tmp_path)
    assert answer == {"full": ["PRBIntegrator", "PointLight"],
                      "mono": ["PRBIntegrator", "Phong"], "finite": True}


def test_held_back_package_keeps_its_identity(tmp_path):
    """While Mitsuba's Python integrators are held back, their package keeps its file and
    search path (so that loading them later, or ``importlib.reload``, finds the real
    files); the mechanism engaged (the variant is recorded as held back)."""
    answer = run_script("""
from spectrace import registry
package = __import__("mitsuba.python.ad.integrators", fromlist=["_"])
spectrace.set_variant("llvm_ad_rgb", lazy=True)
print(json.dumps({"held": sorted(registry._held_back), "file": package.__file__,
                  "path": list(package.__path__), "loader": type(package.__loader__).__name__,
                  "finders": [type(f).__name__ for f in sys.meta_path]}))
""", tmp_path)
    assert answer["held"] == ["llvm_ad_rgb"]
    assert answer["file"].endswith("__init__.py") and answer["path"]
    assert answer["loader"] != "_HoldBack" and "_HoldBack" not in answer["finders"]


def test_register_names_registers_only_those(variant_rgb):
    """``plugins.register(names)`` registers the named plugins once per variant and ignores
    names that are not spectrace's; ``register()`` then adds the rest."""
    plugins.register(force=True)
    assert plugins.register({"phong", "path"}) == []  # already registered: nothing to do
    assert plugins.register({"phong"}, force=True) == ["phong"]
    assert plugins.register({"path", "diffuse"}) == []
    assert set(plugins.PLUGINS) == {"phong", "blinnphong", "pointlight", "spotlight",
                                    "ieslight", "ciesky", "sun", "local", "illuminance",
                                    "lightgroups"}


def test_plugin_modules_are_named_after_their_xml_type():
    """Every module of PLUGINS registers the XML type it is named after (the mapping the
    on-demand registration trusts)."""
    for name, module in plugins.PLUGINS.items():
        source = (ROOT / "plugins" / (module.replace(".", "/") + ".py")).read_text()
        assert (f'register_{module.split(".")[0][:-1]}("{name}"' in source
                or f'PLUGIN = "{name}"' in source), module


@pytest.mark.parametrize("message, name", [
    ('[parser.cpp:1718] At x.xml (line 1, col 25): failed to instantiate integrator plugin of '
     'type "prb": [PluginManager] Plugin "prb" not found!', "prb"),
    ("unrelated error", None),
])
def test_missing_plugin_is_read_from_mitsubas_message(message, name):
    from spectrace.registry import missing_plugin

    assert missing_plugin(message) == name
