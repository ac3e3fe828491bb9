"""Malformed or unreadable photometric files raise FileFormatError or FileAccessError: one
line naming the file and the field."""

from __future__ import annotations

import numpy as np
import pytest
from spectrace.photometry import generate as G
from spectrace.photometry import read_photometry

from spectrace.errors import FileAccessError, FileFormatError

GAMMA = np.arange(0.0, 90.001, 15.0)


def good_ies(tmp_path, **kwargs):
    h = G.horizontal_angles("quadrant", 45.0)
    return G.write_ies(tmp_path / "bad.ies", GAMMA, h, np.full((h.size, GAMMA.size), 7.0),
                       newline="\n", **kwargs)


def numbers_of(path):
    head, numbers = path.read_text("latin-1").split("TILT=NONE\n")
    return head + "TILT=NONE\n", numbers.split()


def assert_error(path, *words):
    with pytest.raises((FileFormatError, FileAccessError)) as info:
        read_photometry(path)
    message = str(info.value)
    assert "\n" not in message
    assert str(path) in message
    for word in words:
        assert word in message, message


def test_truncated_ies(tmp_path):
    """A file cut inside the candela table says it ends early, naming the candela values."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    path.write_text(head + " ".join(nums[:-5]))
    assert_error(path, "candela values", "truncated")


def test_wrong_counts(tmp_path):
    """More numbers than the header's counts call for: 'wrong counts'."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    path.write_text(head + " ".join(nums + ["7", "7"]))
    assert_error(path, "wrong counts")


def test_negative_candela(tmp_path):
    """A negative intensity is named with its angles."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    nums[-1] = "-3"
    path.write_text(head + " ".join(nums))
    assert_error(path, "negative", "vertical angle 90")


def test_non_numeric_value(tmp_path):
    """A word among the numbers is named with the field it stands in."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    nums[3] = "twelve"  # number of vertical angles
    path.write_text(head + " ".join(nums))
    assert_error(path, "number of vertical angles", "'twelve' is not a number")


def test_type_a_is_refused(tmp_path):
    """Photometric type 3 (Type A, automotive) is refused by name."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    nums[5] = "3"
    path.write_text(head + " ".join(nums))
    assert_error(path, "photometric type", "Type A")


def test_missing_tilt_file(tmp_path):
    """TILT=<file> naming a file that does not exist beside the IES file."""
    path = good_ies(tmp_path)
    path.write_text(path.read_text().replace("TILT=NONE", "TILT=nowhere.tlt"))
    assert_error(path, "TILT", "nowhere.tlt")


def test_unknown_format(tmp_path):
    """An IES header of an unknown edition, and a file that is neither IES nor EULUMDAT."""
    path = good_ies(tmp_path)
    path.write_text(path.read_text().replace("IESNA:LM-63-2002", "IESNA:LM-63-2030"))
    assert_error(path, "unknown IES version")
    other = tmp_path / "notes.txt"
    other.write_text("hello\n1 2 3\n")
    assert_error(other, "unknown format")
    assert_error(tmp_path / "absent.ies", "cannot read")


def test_bad_horizontal_range(tmp_path):
    """Type C horizontal angles 0..120 are no LM-63 symmetry."""
    path = G.write_ies(tmp_path / "h.ies", GAMMA, [0, 60, 120], np.ones((3, GAMMA.size)))
    assert_error(path, "horizontal angles", "0..120")


def test_ldt_errors(tmp_path):
    """EULUMDAT: a cut file, an unknown symmetry indicator, and a non-numeric intensity."""
    path = G.write_ldt(tmp_path / "bad.ldt", G.cos_power(100.0, 2), isym=1,
                       gamma_angles=GAMMA)
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-2]))
    assert_error(path, "intensities", "truncated")
    path.write_text("\n".join([lines[0], lines[1], "7", *lines[3:]]))
    assert_error(path, "line 3", "Isym")
    path.write_text("\n".join([*lines[:-1], "lots"]))
    assert_error(path, "'lots' is not a number")


@pytest.mark.parametrize("count", ["1e12", "1e300"])
def test_absurd_angle_count_is_truncation_not_a_crash(tmp_path, count):
    """A corrupt count of vertical angles (10^12, 10^300) is reported as a file that ends
    early, before any array of that size is allocated (it raised MemoryError/ValueError)."""
    path = good_ies(tmp_path)
    head, nums = numbers_of(path)
    nums[3] = count  # number of vertical angles
    path.write_text(head + " ".join(nums))
    assert_error(path, "vertical angles", "truncated", "about 10^")


def test_ldt_absurd_plane_count_is_truncation_not_a_crash(tmp_path):
    """EULUMDAT without symmetry (Isym 0, every plane stored) and Mc = 10^12: the count is
    checked against the numbers present before the planes are listed."""
    path = G.write_ldt(tmp_path / "big.ldt", G.cos_power(100.0, 2), isym=0,
                       gamma_angles=GAMMA)
    lines = path.read_text().splitlines()
    lines[3] = "1000000000000"  # line 4: Mc
    path.write_text("\n".join(lines))
    assert_error(path, "intensities", "truncated", "about 10^12 C-angles")


def test_factors_that_overflow_are_refused(tmp_path):
    """Candela multiplier 1e300 times 1e300 cd is not a finite intensity: refused (it gave
    a flux of inf lm and a downward share of nan %)."""
    h = np.array([0.0])
    path = G.write_ies(tmp_path / "big.ies", GAMMA, h, np.full((1, GAMMA.size), 1e300),
                       multiplier=1e300, newline="\n")
    assert_error(path, "candela values", "overflow")
    ldt = G.write_ldt(tmp_path / "big.ldt", G.cos_power(100.0, 2), isym=1,
                      gamma_angles=GAMMA)
    lines = ldt.read_text().splitlines()
    lines[23] = lines[28] = "1e300"  # line 24: conversion factor, 29: flux of lamp set 1
    ldt.write_text("\n".join(lines))
    assert_error(ldt, "candela values", "overflow")


def test_absurd_but_finite_intensities_are_refused(tmp_path):
    """Candela multiplier 1e300 on a 100 cd table is finite (1e302 cd) but no luminaire: it
    was accepted and printed a 300-digit flux; now refused with the value and the bound."""
    h = np.array([0.0])
    path = G.write_ies(tmp_path / "huge.ies", GAMMA, h, np.full((1, GAMMA.size), 100.0),
                       multiplier=1e300, newline="\n")
    assert_error(path, "candela values", "1e+302 cd", "beyond any luminaire")
    ok = G.write_ies(tmp_path / "bright.ies", GAMMA, h, np.full((1, GAMMA.size), 1e9))
    assert read_photometry(ok).max_candela == 1e9  # a searchlight's billion candela reads


def test_ldt_with_doubled_carriage_returns_reads(tmp_path):
    """A EULUMDAT file whose CRLF line ends were converted once more ("\\r\\r\\n", a
    text-mode transfer) reads as the original, not as blank lines between the fields."""
    path = G.write_ldt(tmp_path / "ok.ldt", G.cos_power(100.0, 2), isym=1,
                       gamma_angles=GAMMA)
    doubled = tmp_path / "doubled.ldt"
    doubled.write_bytes(path.read_bytes().replace(b"\r\n", b"\n").replace(b"\n", b"\r\r\n"))
    np.testing.assert_array_equal(read_photometry(doubled).candela,
                                  read_photometry(path).candela)


def test_devices_and_fifos_are_refused_without_reading(tmp_path):
    """A FIFO (reading it would block until a writer comes) and /dev/zero (endless), as
    the file or as its TILT file, are refused as 'not a regular file'."""
    import os

    fifo = tmp_path / "pipe.ies"
    os.mkfifo(fifo)
    assert_error(fifo, "not a regular file")
    path = good_ies(tmp_path)
    path.write_text(path.read_text().replace("TILT=NONE", "TILT=/dev/zero"))
    assert_error(path, "TILT", "not a regular file")
