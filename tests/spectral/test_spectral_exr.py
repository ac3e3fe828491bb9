"""Spectral OpenEXR in the Fichet et al. 2021 layout: round trip and colour-science interop."""

from __future__ import annotations

import os
import stat

import numpy as np
import OpenEXR
import pytest

from spectrace import spectral as S
from spectrace.errors import FileAccessError, FileFormatError

# colour-science warns when it resamples the oracle data; expected here.
pytestmark = pytest.mark.filterwarnings("ignore::colour.utilities.ColourRuntimeWarning")

PREVIEW_RTOL = 1e-5


@pytest.fixture
def spectral(rng):
    wl = np.array([400.0, 412.5, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0, 1000.0])
    return rng.uniform(0, 2, (5, 7, wl.size)).astype(np.float32), wl


def test_file_mode_follows_the_umask(tmp_path, spectral):
    """OUT.spectral.exr gets the umask's mode like the other outputs (not mkstemp's 0600),
    and no temporary file is left beside it."""
    image, wl = spectral
    old = os.umask(0o022)
    try:
        path = S.write_spectral_exr(tmp_path / "m.spectral.exr", image, wl)
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    assert [p.name for p in tmp_path.iterdir()] == ["m.spectral.exr"]


def test_round_trip_and_layout(tmp_path, spectral):
    """What is written reads back bit-exact, wavelengths in order; channels are named
    S0.<nm with comma>nm and the header has spectralLayoutVersion and emissiveUnits."""
    img, wl = spectral
    path = S.write_spectral_exr(tmp_path / "a.exr", img, wl, attributes={"spp": 16})
    back, wl_back, header = S.read_spectral_exr(path, with_header=True)
    np.testing.assert_array_equal(wl_back, wl)
    np.testing.assert_array_equal(back, img)
    with OpenEXR.File(str(path), separate_channels=True) as f:
        names = set(f.channels())
        hdr = dict(f.header())
    assert {"S0.412,5nm", "S0.400nm", "S0.1000nm", "R", "G", "B"} <= names
    assert hdr["spectralLayoutVersion"] == "1.0"
    assert hdr["emissiveUnits"] == "W.m^-2.sr^-1"
    assert header["spp"] == 16
    assert not list(tmp_path.glob(".*"))  # no temporary file left behind


def test_preview_is_linear_srgb_of_the_spectra(tmp_path, spectral):
    """The R, G, B preview channels hold spectral_image_to_linear_srgb of the data."""
    img, wl = spectral
    path = S.write_spectral_exr(tmp_path / "a.exr", img, wl)
    with OpenEXR.File(str(path), separate_channels=True) as f:
        rgb = np.stack([f.channels()[c].pixels for c in "RGB"], axis=-1)
    np.testing.assert_allclose(
        rgb, S.spectral_image_to_linear_srgb(img, wl), rtol=PREVIEW_RTOL, atol=1e-6
    )


def test_explicit_or_no_preview(tmp_path, spectral):
    """preview=array stores that array as R, G, B; preview=False writes no RGB channels."""
    img, wl = spectral
    rgb = np.arange(5 * 7 * 3, dtype=np.float32).reshape(5, 7, 3)
    path = S.write_spectral_exr(tmp_path / "p.exr", img, wl, preview=rgb)
    with OpenEXR.File(str(path), separate_channels=True) as f:
        np.testing.assert_array_equal(f.channels()["G"].pixels, rgb[..., 1])
    path = S.write_spectral_exr(tmp_path / "n.exr", img, wl, preview=False)
    with OpenEXR.File(str(path), separate_channels=True) as f:
        assert "R" not in f.channels()
    with pytest.raises(ValueError, match="preview"):
        S.write_spectral_exr(tmp_path / "x.exr", img, wl, preview=rgb[:2])


def test_reflective_uses_t_channels(tmp_path, spectral):
    """kind='reflective' writes T.<nm> channels without emissiveUnits and reads back."""
    img, wl = spectral
    path = S.write_spectral_exr(tmp_path / "r.exr", img, wl, kind="reflective")
    back, wl_back, header = S.read_spectral_exr(path, with_header=True)
    np.testing.assert_array_equal(back, img)
    assert "emissiveUnits" not in header


def test_colour_science_reads_our_file(tmp_path, spectral):
    """colour-science's Fichet 2021 reader (through OpenImageIO) finds the same S0 component,
    wavelengths and values in a file written here."""
    import colour

    img, wl = spectral
    path = S.write_spectral_exr(tmp_path / "c.exr", img, wl)
    components, spec = colour.io.read_spectral_image_Fichet2021(str(path), additional_data=True)
    assert spec.is_emissive
    wl_theirs, values = components["S0"]
    order = np.argsort(wl_theirs)  # colour keeps the file's alphabetical channel order
    np.testing.assert_allclose(np.asarray(wl_theirs)[order], wl)
    np.testing.assert_array_equal(values[..., order], img)


def test_we_read_colour_science_file(tmp_path, rng):
    """A file written by colour-science's Fichet 2021 writer reads back with our reader."""
    import colour

    wl = np.arange(400.0, 701.0, 25.0)  # its RGB preview needs a regular grid
    img = rng.uniform(0, 2, (4, 3, wl.size)).astype(np.float32)
    path = tmp_path / "theirs.exr"
    spec = colour.io.Specification_Fichet2021(is_emissive=True)
    colour.io.write_spectral_image_Fichet2021({"S0": (wl, img)}, str(path), "float32", spec)
    back, wl_back = S.read_spectral_exr(path)
    np.testing.assert_allclose(wl_back, wl)
    np.testing.assert_array_equal(back, img)


def test_bad_files_and_input(tmp_path, spectral):
    """Missing, non-EXR or non-spectral files raise FileAccessError or FileFormatError; bad
    arrays ValueError."""
    img, wl = spectral
    with pytest.raises(FileAccessError, match="no such file"):
        S.read_spectral_exr(tmp_path / "missing.exr")
    junk = tmp_path / "junk.exr"
    junk.write_text("not an exr")
    with pytest.raises(FileFormatError, match="OpenEXR"):
        S.read_spectral_exr(junk)
    rgb_only = tmp_path / "rgb.exr"
    with OpenEXR.File({}, {"R": img[..., 0], "G": img[..., 1], "B": img[..., 2]}) as f:
        f.write(str(rgb_only))
    with pytest.raises(FileFormatError, match="no spectral channels"):
        S.read_spectral_exr(rgb_only)
    with pytest.raises(ValueError, match="mismatched"):
        S.write_spectral_exr(tmp_path / "x.exr", img, wl[:-1])
    with pytest.raises(ValueError, match=r"\(H, W, N\)"):
        S.write_spectral_exr(tmp_path / "x.exr", img[0], wl)
    with pytest.raises(ValueError, match="NaN"):
        S.write_spectral_exr(tmp_path / "x.exr", np.full_like(img, np.nan), wl)
