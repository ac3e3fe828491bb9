"""Benchmark: direct illuminance at calculation points from one photometric file, spectrace
against the physical floor (numpy E = I cos / r^2) and, where ``pyradiance`` is installed,
Radiance's ``rtrace -I -ab 0`` on the same points.

A floor 12 m square lit by scenes/luminaires/downlight.ies (800 lm, 25 degree beam) aimed
straight down from 2.5 m, as a point source (``opening`` ``point``: the file's 60 mm
opening would make it an area light, sampled; ``rtrace -ds 0`` also treats its source as
a point), a work plane at 0.8 m: a 13 x 13 and a 512 x 512 grid of points
over 6 m x 6 m, written to CSV (``x,y,z,nx,ny,nz``) as ``spectrace lux --points`` and
``rtrace`` read them. Timed, each the median of ``--repeats`` runs in one run of this
script:

* numpy: ``Photometry.intensity(gamma, C) cos / r^2`` at the points, already in memory
  (no shadow rays): the floor of this work;
* render: ``spectrace.lighting.points.measure_points`` in this process, the scene loaded
  and its kernels compiled by a first call (one exact sample per point, one shadow ray);
* spectrace: the whole ``spectrace lux SCENE --points FILE -o OUT.csv`` process (start-up,
  scene load, kernel compilation or cache, CSV in and out);
* rtrace: the whole ``rtrace -h -I -ab 0 -ds 0 -dj 0 OCTREE < points > out`` process (the
  octree built once by ``oconv`` from ``ies2rad``'s luminaire), lux = 179 (0.265 R +
  0.670 G + 0.065 B); only when ``pyradiance`` (PyPI, ships Radiance's binaries) is
  importable: ``pip install pyradiance`` (not a spectrace dependency); RAYPATH is set to
  its ``lib/``.

The table also shows the largest relative difference to the numpy values (points with at
least 1 % of the peak). Aims (issue 20): large grid spectrace process <= rtrace process;
render <= 5 x numpy. On the small grid start-up dominates; ``spectrace render`` of an 8 x 8
image of the same scene is shown beside it, and the seconds that both spend importing
colour-science (``import colour`` in a fresh interpreter, less the interpreter's start).

Run: ``.venv/bin/python benchmarks/bench_lux.py [--sizes 13,512] [--repeats 3]
[--variant llvm_ad_spectral]``
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _timing import print_table
from spectrace.scenes import FOLDER

import spectrace

IES = FOLDER / "luminaires" / "downlight.ies"
HEIGHT = 2.5
PLANE = 0.8
HALF_AREA = 3.0
#: Radiance's luminous efficacy of its "white" (lm/W) and RGB luminance weights.
RADIANCE_EFFICACY = 179.0
RADIANCE_WEIGHTS = (0.265, 0.670, 0.065)
SCENE = f"""<scene version="3.0.0">
    <integrator type="path"/>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 2, 5" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="6"/><rotate x="1" angle="-90"/></transform>
    </shape>
    <emitter type="ieslight">
        <string name="filename" value="{IES}"/>
        <string name="opening" value="point"/>
        <transform name="to_world"><lookat origin="0, {HEIGHT}, 0" target="0, 0, 0"
            up="0, 0, 1"/></transform>
    </emitter>
</scene>
"""


def grid_points(n: int) -> np.ndarray:
    c = (np.arange(n) + 0.5) / n * 2 * HALF_AREA - HALF_AREA
    x, z = np.meshgrid(c, c)
    return np.column_stack([x.ravel(), np.full(n * n, PLANE), z.ravel()])


def numpy_floor(photometry, p: np.ndarray) -> np.ndarray:
    """E = I(gamma, C) cos / r^2 on horizontal planes; the light frame: local x = world
    x, local y = world z, aim (local z) = world -y."""
    v = p - np.array([0.0, HEIGHT, 0.0])
    r2 = np.einsum("ij,ij->i", v, v)
    r = np.sqrt(r2)
    cos = -v[:, 1] / r
    gamma = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    c = np.degrees(np.arctan2(-v[:, 2], v[:, 0])) % 360.0
    return photometry.intensity(gamma, c) * cos / r2


def median_time(function, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def process_time(argv, repeats: int, env=None, stdin=None) -> float:
    def run():
        with open(stdin) if stdin else open(os.devnull) as f_in, open(os.devnull, "w") as out:
            subprocess.run(argv, check=True, stdin=f_in, stdout=out, env=env)
    run()  # warm: kernel cache, file cache
    return median_time(run, repeats)


def radiance(folder: Path):
    """(bin folder, environment, octree) of pyradiance's Radiance, or None."""
    try:
        import pyradiance
    except ImportError:
        return None
    root = Path(pyradiance.__file__).parent
    binaries, env = root / "bin", dict(os.environ, RAYPATH=str(root / "lib"))
    subprocess.run([str(binaries / "ies2rad"), "-dm", "-c", "1", "1", "1", "-o",
                    str(folder / "downlight"), str(IES)], check=True, env=env)
    (folder / "scene.rad").write_text(
        f"!xform -t 0 0 {HEIGHT} {folder / 'downlight.rad'}\n"
        "void plastic grey 0 0 5 0.5 0.5 0.5 0 0\n"
        "grey polygon floor 0 0 12 -6 -6 0 6 -6 0 6 6 0 -6 6 0\n")
    with open(folder / "scene.oct", "wb") as f:
        subprocess.run([str(binaries / "oconv"), str(folder / "scene.rad")], check=True,
                       stdout=f, env=env, cwd=folder)
    return binaries, env, folder / "scene.oct"


def to_radiance(p: np.ndarray) -> np.ndarray:
    """spectrace (+Y up) -> Radiance (+Z up): (x, y, z) -> (x, -z, y)."""
    return np.column_stack([p[:, 0], -p[:, 2], p[:, 1]])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="13,512")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--variant", default="llvm_ad_spectral")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    spectrace_cli = shutil.which("spectrace", path=str(Path(sys.executable).parent)) or \
        "spectrace"
    from spectrace.photometry import read_photometry

    from spectrace.lighting.points import measure_points, read_points_csv

    photometry = read_photometry(IES)
    spectrace.set_variant(args.variant)
    import mitsuba as mi

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        scene_path = folder / "scene.xml"
        scene_path.write_text(SCENE)
        scene = mi.load_file(str(scene_path))
        rad = radiance(folder)
        render_process = process_time([spectrace_cli, "render", str(scene_path), "-o",
                                       str(folder / "r.exr"), "--variant", args.variant,
                                       "-q"], args.repeats)
        # what the start-up of both commands spends importing colour-science (the
        # photopic V of the luminous lights; it imports colour.plotting and matplotlib)
        colour_import = process_time([sys.executable, "-c", "import colour"], args.repeats) \
            - process_time([sys.executable, "-c", "pass"], args.repeats)
        for n in sizes:
            p = grid_points(n)
            up = np.tile([0.0, 1.0, 0.0], (len(p), 1))
            csv_in = folder / f"points{n}.csv"
            np.savetxt(csv_in, np.column_stack([p, up]), delimiter=",", fmt="%.9g",
                       header="x,y,z,nx,ny,nz", comments="")
            p, up = read_points_csv(csv_in)
            expected = numpy_floor(photometry, p)
            t_numpy = median_time(lambda p=p: numpy_floor(photometry, p), args.repeats)
            lux, _, _ = measure_points(scene, p, up)  # compiles the kernels
            t_render = median_time(lambda p=p, up=up: measure_points(scene, p, up),
                                   args.repeats)
            out = folder / f"out{n}.csv"
            t_process = process_time([spectrace_cli, "lux", str(scene_path), "--points",
                                      str(csv_in), "-o", str(out), "--variant",
                                      args.variant, "-q"], args.repeats)
            lit = expected > 0.01 * expected.max()
            got = np.loadtxt(out, delimiter=",", skiprows=1)[:, 6]
            diff = float(np.max(np.abs(got[lit] / expected[lit] - 1.0)))
            t_rtrace, diff_rtrace = float("nan"), float("nan")
            if rad is not None:
                binaries, env, octree = rad
                text_in = folder / f"points{n}.txt"
                np.savetxt(text_in, np.column_stack([to_radiance(p), to_radiance(up)]),
                           fmt="%.9g")
                argv = [str(binaries / "rtrace"), "-h", "-I", "-ab", "0", "-ds", "0", "-dj",
                        "0", str(octree)]
                t_rtrace = process_time(argv, args.repeats, env=env, stdin=text_in)
                with open(text_in) as f_in:
                    result = subprocess.run(argv, check=True, stdin=f_in, env=env,
                                            capture_output=True, text=True).stdout
                rgb = np.loadtxt(result.splitlines())
                lux_r = RADIANCE_EFFICACY * rgb @ np.asarray(RADIANCE_WEIGHTS)
                diff_rtrace = float(np.max(np.abs(lux_r[lit] / expected[lit] - 1.0)))
            rows.append((f"{n}x{n}", t_numpy, t_render, t_render / t_numpy, t_process,
                         t_rtrace, t_process / t_rtrace, render_process, colour_import, diff,
                         diff_rtrace))
    print(f"direct illuminance from {IES.name}, {args.variant}, median of {args.repeats}")
    print_table([("grid", ">9", ""), ("numpy (s)", ">10", ".4f"), ("render (s)", ">10", ".4f"),
                 ("render/numpy", ">12", ".2f"), ("spectrace (s)", ">13", ".3f"),
                 ("rtrace (s)", ">10", ".3f"), ("spectrace/rtrace", ">16", ".2f"),
                 ("render cmd (s)", ">14", ".3f"), ("colour import (s)", ">17", ".3f"),
                 ("err vs numpy", ">12", ".1e"),
                 ("rtrace err", ">10", ".1e")], rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
