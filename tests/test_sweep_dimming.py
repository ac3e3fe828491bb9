"""Dimming sweeps (issue 22.5): a swept ``<default>`` that only scales a light is relit
from one light-group render, and equals the rendered sweep within Monte Carlo noise."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from spectrace import sweeps
from spectrace.cli import main
from spectrace.images import read_exr
from spectrace.scene import read_scene_xml
from spectrace.sweeps.dimming import dimming_emitters

VARIANT = "llvm_ad_rgb"
#: Relit against rendered images (256 spp, 24 x 24): relative difference of the mean
#: luminance, and relative RMS of the per-pixel difference (measured 0.02-0.07: noise).
MEAN_RTOL = 0.03
RMS_RTOL = 0.12

SCENE = """<scene version="3.0.0">
  <default name="dim" value="1"/>
  <default name="sky" value="0.2"/>
  <default name="albedo" value="0.5"/>
  <integrator type="path"><integer name="max_depth" value="3"/></integrator>
  <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 3"
      target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="256"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
    <rfilter type="box"/></film></sensor>
  <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="$albedo"/>
  </bsdf></shape>
  <emitter type="point"><point name="position" x="0.3" y="0" z="1"/>
    <float name="intensity" value="$dim"/></emitter>
  <emitter type="constant"><rgb name="radiance" value="$sky"/></emitter>
</scene>
"""


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "dim.xml"
    path.write_text(SCENE)
    return path


def test_only_emitter_intensities_are_dimming_parameters(scene):
    """$dim and $sky are a light's intensity or radiance; $albedo is a BSDF's: not one."""
    root = read_scene_xml(scene)
    assert [e.get("type") for e in dimming_emitters(root, "dim")] == ["point"]
    assert dimming_emitters(root, "albedo") is None
    grid = sweeps.Grid.make(scene, {"dim": [0.5, 2], "sky": [0, 0.2]}, VARIANT)
    assert sweeps.dimming_plan(grid) == {"dim": 1, "sky": 1}
    mixed = sweeps.Grid.make(scene, {"dim": [0.5, 2], "albedo": [0.2, 0.8]}, VARIANT)
    assert sweeps.dimming_plan(mixed) is None


def test_dimming_sweep_is_relit_and_equals_the_rendered_sweep(scene, tmp_path, capsys,
                                                              local_cluster):
    """-D dim=0.25,1,3: one light-group render, relit three times (said on stdout); each
    image equals the rendered image of that value (relight=False) within noise, and
    results.csv has the usual columns."""
    out = tmp_path / "relit"
    assert main(["sweep", str(scene), "-D", "dim=0.25,1,3", "--variants", VARIANT,
                 "-o", str(out), "-q", "--scheduler", local_cluster.scheduler_address]) == 0
    said = capsys.readouterr().out
    assert "dim (1 light): only scales lights; 1 light-group render" in said
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["dim"] for r in rows] == ["0.25", "1", "3"]
    assert set(rows[0]) >= {"spp", "file", "seconds", "mean_luminance"}
    from distributed import Client

    with Client(local_cluster, set_as_default=False) as client:
        grid = sweeps.Grid.make(scene, {"dim": ["0.25", "1", "3"]}, VARIANT, [1])
        rendered = sweeps.run(grid, client, tmp_path / "rendered", relight=False)
    for row, o in zip(rows, rendered, strict=True):
        relit, ref = read_exr(out / row["file"])[0], o.image
        assert abs(relit.mean() / ref.mean() - 1) < MEAN_RTOL
        rms = np.sqrt(np.mean((relit - ref) ** 2) / np.mean(ref ** 2))
        assert rms < RMS_RTOL, (row["dim"], rms)


#: A `local` scene with point lights is deterministic: relit equals rendered to float
#: rounding.
LOCAL_ATOL = 1e-6


def test_dimming_sweep_of_a_local_scene_keeps_its_ambient(tmp_path, local_cluster):
    """integrator local with an ambient term: the ambient layer keeps scale 1 and the
    relit images equal the rendered ones (the local model has no noise here)."""
    scene = tmp_path / "local.xml"
    scene.write_text(SCENE.replace(
        '<integrator type="path"><integer name="max_depth" value="3"/></integrator>',
        '<integrator type="local"><float name="ambient" value="0.1"/></integrator>'))
    grid = sweeps.Grid.make(scene, {"dim": [0.5, 2]}, VARIANT)
    assert sweeps.dimming_plan(grid) == {"dim": 1}
    from distributed import Client

    with Client(local_cluster, set_as_default=False) as client:
        relit = sweeps.run(grid, client, tmp_path / "relit")
        rendered = sweeps.run(grid, client, tmp_path / "rendered", relight=False)
    for a, b in zip(relit, rendered, strict=True):
        assert a.status == b.status == "rendered"
        np.testing.assert_allclose(a.image, b.image, rtol=0, atol=LOCAL_ATOL)
