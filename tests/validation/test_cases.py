"""The validation cases pass at their quick size in RGB and spectral variants, and a
deliberately wrong setting of the scene (never of the reference) makes them fail."""

from __future__ import annotations

import pytest

from spectrace import validation
from spectrace.validation import cases as C

#: A light 5 % too strong (or a surface 5 % too bright, a glass of the wrong index):
#: case -> XML parameters of its scene.
WRONG = {
    "point_horizontal": {"intensity": "1050"},
    "point_asymmetric": {"scale": "1.05"},
    "flux_closed_room": {"scale": "1.05"},
    "area_disk_parallel": {"radiance": repr(C._radiance(1.05 * C.SOURCE_LUMINANCE))},
    "area_rectangle_parallel": {"radiance": repr(C._radiance(1.05 * C.SOURCE_LUMINANCE))},
    "integrating_sphere": {"flux": "1050"},
    "area_sphere": {"intensity": "1050"},
    "diffuse_reflection_obstructed": {"rho": "0.525"},
    "glass_transmittance": {"ior": "1.6"},
    "daylight_facade_overcast": {"zenith_luminance": "1050"},
}


def test_every_modelled_case_passes_in_rgb(variant_rgb):
    """Every case agrees with its closed form (RGB: delta lights exact)."""
    results = validation.run(quick=True)
    assert [r.name for r in results] == list(C.CASES)
    for r in results:
        assert r.modelled and r.passed, (r.name, r.relative_error.max())


@pytest.mark.parametrize("name", sorted(WRONG))
def test_a_wrong_setting_fails(variant_spectral, name):
    """The same case with its scene 5 % off (the reference unchanged) fails: the
    tolerances are tight enough to see it."""
    good, = validation.run([name], quick=True)
    bad, = validation.run([name], quick=True, params=WRONG[name])
    assert good.passed and not bad.passed


def test_unknown_case_is_named(variant_rgb):
    with pytest.raises(ValueError, match="unknown case 'nope'"):
        validation.run(["nope"])


@pytest.mark.parametrize("scene", sorted(p.name for p in C.folder().glob("*.xml")))
def test_every_case_scene_renders(tmp_path, scene):
    """Each case's scene is one a user can render and look at with spectrace render."""
    from spectrace.cli import main

    out = tmp_path / "case.exr"
    assert main(["render", str(C.folder() / scene), "-D", "res=8", "-D", "spp=2", "-q",
                 "-m", "llvm_ad_rgb", "-o", str(out)]) == 0
    assert out.is_file() and out.with_suffix(".png").is_file()
