"""Benchmark: ``spectrace render`` against Mitsuba's own ``mitsuba`` executable, whole runs.

What a user waits for and what the machine holds: the wall time and the peak resident
memory of one process that loads a scene, renders it and writes the image, from start to
exit. Both programs render the same XML file in the same variant at the same resolution
and sample count; ``spectrace render`` writes its EXR and its sRGB PNG, ``mitsuba`` its
EXR. The scenes use only Mitsuba's built-in plugins (the executable knows no others):

* ``cornell_box``: Mitsuba's tutorial Cornell box (``mi.cornell_box()``, written to XML),
  ``path``, 256 x 256, 128 spp -- the scene of issue 12;
* ``spheres``: the project's mesh sphere (``scenes/meshes/sphere_high.obj``) and an
  analytic sphere, rough plastic, under a point light and a constant sky, ``path``;
* ``fog_volpath``: the project's ``scenes/fog_volpath.xml`` (volpath in a homogeneous
  medium), at 64 spp;
* ``tiny``: the Cornell box at 32 x 32, 4 spp: next to no rendering, so the ratio is that
  of the start-ups (imports, plugin registration, writing the files).

Each (scene, variant) pair runs once per program to fill the kernel cache (and Python's
bytecode cache: the runs do not inherit ``PYTHONDONTWRITEBYTECODE``), then
``--repeats`` rounds alternate the two programs (ABBA order, so drift hits both alike).
The table gives the medians and the median over rounds of the ratios spectrace / mitsuba
(aim: wall time within 1.05x, peak memory within 1.3x), and the ratio of the fastest runs
("best ratio"), the steadier figure on a machine that others load too.

Mitsuba's ``mitsuba`` is a Python script that imports mitsuba (no variant) and then runs
the C++ executable in a child process: its wall time is the two together, its peak memory
the larger of the two (``wait4`` reports a child's largest descendant). ``spectrace render``
does all in one process.

    .venv/bin/python benchmarks/bench_cli.py [--repeats 5] [--spp-per-pass K] [--scenes a,b]
        [--variants llvm_ad_rgb,llvm_ad_spectral]

A quick look (about a minute): ``--scenes tiny,fog_volpath --repeats 3``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timing import VARIANTS, print_table

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
MITSUBA = BIN / "mitsuba"
SPECTRACE = BIN / "spectrace"

#: XML tag of each plugin type used by the scenes.
TAGS = {"diffuse": "bsdf", "rectangle": "shape", "cube": "shape", "perspective": "sensor",
        "path": "integrator", "hdrfilm": "film", "independent": "sampler", "area": "emitter",
        "gaussian": "rfilter", "box": "rfilter"}


def _xml(name, value, indent="    ") -> list[str]:
    """XML lines of one entry of a Mitsuba scene dictionary (the types mi.cornell_box uses)."""
    named = f' name="{name}"' if name else ""
    if isinstance(value, dict):
        kind = value["type"]
        if kind == "ref":
            return [f'{indent}<ref id="{value["id"]}"{named}/>']
        if kind == "rgb":
            rgb = ", ".join(f"{c:g}" for c in value["value"])
            return [f'{indent}<rgb{named} value="{rgb}"/>']
        tag = name if name in ("bsdf", "emitter", "film", "sampler", "integrator", "sensor",
                               "rfilter") \
            else TAGS[kind]
        ident = "" if name in TAGS.values() else f' id="{name}"'
        lines = [f'{indent}<{tag} type="{kind}"{ident}>']
        for key, item in value.items():
            if key != "type":
                lines += _xml(key, item, indent + "    ")
        return lines + [f"{indent}</{tag}>"]
    if isinstance(value, bool):
        return [f'{indent}<boolean{named} value="{str(value).lower()}"/>']
    if isinstance(value, int):
        return [f'{indent}<integer{named} value="{value}"/>']
    if isinstance(value, float):
        return [f'{indent}<float{named} value="{value:g}"/>']
    if isinstance(value, str):
        return [f'{indent}<string{named} value="{value}"/>']
    matrix = " ".join(f"{v:.9g}" for row in value.matrix.numpy() for v in row)  # a transform
    return [f'{indent}<transform{named}>', f'{indent}    <matrix value="{matrix}"/>',
            f"{indent}</transform>"]


def cornell_box_xml() -> str:
    """Mitsuba's tutorial Cornell box as an XML file with ``res`` and ``spp`` defaults."""
    import spectrace

    spectrace.set_variant("llvm_ad_rgb")
    import mitsuba as mi

    scene = mi.cornell_box()
    scene["sensor"]["film"].update(width="$res", height="$res")
    scene["sensor"]["sampler"]["sample_count"] = "$spp"
    lines = []
    for name, value in scene.items():
        if name != "type":
            lines += _xml(name, value)
    body = "\n".join(lines)
    for name, value in (("width", "$res"), ("height", "$res"), ("sample_count", "$spp")):
        body = body.replace(f'<string name="{name}" value="{value}"/>',
                            f'<integer name="{name}" value="{value}"/>')
    return ('<scene version="3.0.0">\n    <default name="res" value="256"/>\n'
            f'    <default name="spp" value="128"/>\n{body}\n</scene>\n')


SPHERES_XML = f"""<scene version="3.0.0">
    <default name="res" value="256"/>
    <default name="spp" value="64"/>
    <integrator type="path"><integer name="max_depth" value="6"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 3, 7" target="0, 0.8, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="$res"/><integer name="height" value="$res"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="-90"/><scale value="6"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.45"/></bsdf>
    </shape>
    <shape type="obj">
        <string name="filename" value="{ROOT / 'scenes' / 'meshes' / 'sphere_high.obj'}"/>
        <transform name="to_world"><translate x="1.1" y="1" z="0"/></transform>
        <bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.6, 0.2, 0.1"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="-1.1" y="1" z="0"/>
        <bsdf type="roughconductor"/>
    </shape>
    <emitter type="point">
        <point name="position" x="3" y="5" z="3"/>
        <rgb name="intensity" value="40"/>
    </emitter>
    <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
</scene>
"""


def scenes(folder: Path) -> dict[str, tuple[Path, list[str]]]:
    """Scene name -> (XML file, -D definitions)."""
    cornell = folder / "cornell_box.xml"
    cornell.write_text(cornell_box_xml())
    spheres = folder / "spheres.xml"
    spheres.write_text(SPHERES_XML)
    return {
        "cornell_box": (cornell, []),
        "spheres": (spheres, []),
        "fog_volpath": (ROOT / "scenes" / "fog_volpath.xml", ["spp=64"]),
        "tiny": (cornell, ["res=32", "spp=4"]),
    }


def run(command: list[str], env: dict) -> tuple[float, float]:
    """(wall seconds, peak resident memory in MiB) of one process, from start to exit."""
    start = time.perf_counter()
    process = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise RuntimeError(f"{command[0]} failed ({process.returncode}): "
                           f"{process.stderr.read().decode()[-500:]}")
    process.stderr.close()
    return wall, usage.ru_maxrss / 1024.0  # ru_maxrss is in KiB on Linux


def commands(xml: Path, defines: list[str], variant: str, out: Path, spp_per_pass):
    d = [arg for define in defines for arg in ("-D", define)]
    mitsuba = [str(MITSUBA), "-m", variant, *d, "-o", str(out / "mitsuba.exr"), str(xml)]
    spectrace = [str(SPECTRACE), "render", str(xml), "--variant", variant, *d, "-q",
                 "-o", str(out / "spectrace.exr")]
    if spp_per_pass:
        spectrace += ["--spp-per-pass", str(spp_per_pass)]
    return {"mitsuba": mitsuba, "spectrace": spectrace}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scenes", default="cornell_box,spheres,fog_volpath,tiny",
                        help="comma-separated scenes to run (default: all)")
    parser.add_argument("--variants", default=",".join(VARIANTS))
    parser.add_argument("--spp-per-pass", type=int, default=None,
                        help="spectrace's --spp-per-pass (default: its own default)")
    args = parser.parse_args()

    from spectrace.llvm import configure_libllvm

    env = dict(os.environ)
    configure_libllvm(env)  # both programs get the same libLLVM (DRJIT_LIBLLVM_PATH)
    # Python's default: compiled modules are cached. Mitsuba's wheel was compiled when it was
    # installed; an editable spectrace compiles its modules on the warm-up run. Without this,
    # a machine that sets PYTHONDONTWRITEBYTECODE recompiles spectrace at every start.
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        chosen = args.scenes.split(",")
        for scene, (xml, defines) in scenes(folder).items():
            if scene not in chosen:
                continue
            for variant in args.variants.split(","):
                pair = commands(xml, defines, variant, folder, args.spp_per_pass)
                for command in pair.values():  # warm-up: fill the kernel cache
                    run(command, env)
                times = {name: [] for name in pair}
                for repeat in range(args.repeats):
                    order = list(pair) if repeat % 2 == 0 else list(pair)[::-1]
                    for name in order:
                        times[name].append(run(pair[name], env))
                pairs = list(zip(times["spectrace"], times["mitsuba"], strict=True))
                wall = [s[0] / m[0] for s, m in pairs]
                memory = [s[1] / m[1] for s, m in pairs]
                rows.append((
                    scene, variant,
                    statistics.median(t for t, _ in times["mitsuba"]),
                    statistics.median(t for t, _ in times["spectrace"]),
                    statistics.median(wall),
                    min(t for t, _ in times["spectrace"]) / min(t for t, _ in times["mitsuba"]),
                    statistics.median(m for _, m in times["mitsuba"]),
                    statistics.median(m for _, m in times["spectrace"]),
                    statistics.median(memory),
                ))
    per_pass = args.spp_per_pass or "default"
    print(f"spectrace render vs mitsuba, whole process, median of {args.repeats} alternating "
          f"runs (spectrace --spp-per-pass {per_pass})")
    print_table([("scene", "<12", ""), ("variant", "<26", ""), ("mitsuba [s]", ">11", ".2f"),
                 ("spectrace [s]", ">13", ".2f"), ("wall ratio", ">10", ".2f"),
                 ("best ratio", ">10", ".2f"),
                 ("mitsuba [MiB]", ">13", ".0f"), ("spectrace [MiB]", ">15", ".0f"),
                 ("memory ratio", ">12", ".2f")], rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
