"""Tests of ``photometry/near_field.py``: the near-field error of the point law on the
axis of an opening that emits L = I / A_proj, against Howell's configuration factors of a
uniform Lambertian disk and rectangle (a cos(gamma) file makes L uniform)."""

from __future__ import annotations

import numpy as np
import pytest

#: The midpoint quadrature against the closed forms, as an absolute tolerance on the
#: relative error (the file's table, linear between its 0.5 degree steps, deviates from
#: cos(gamma) by up to (0.5 deg)^2 / 8 = 1e-5).
ATOL_ERROR = 5e-5
I0 = 100.0


def lambertian(tmp_path, opening):
    from spectrace.photometry import generate, read_photometry

    path = generate.write_ies_function(tmp_path / "lambert.ies", generate.cos_power(I0, 1.0),
                                       opening=opening,
                                       vertical_angles=np.arange(0.0, 180.01, 0.5))
    return read_photometry(path)


@pytest.mark.parametrize("h_over_r", [1.0, 3.0, 10.0])
def test_disk_against_howell(tmp_path, h_over_r):
    """A Lambertian disk of radius r on its axis at h: E / E_point = h^2 / (r^2 + h^2)
    (Howell B-13: F = r^2 / (r^2 + h^2), E = pi L F, L = I0 / (pi r^2))."""
    from spectrace.photometry.near_field import axial_near_field_error

    r = 0.2
    ph = lambertian(tmp_path, (-2 * r, -2 * r, 0.0))
    h = h_over_r * r
    expected = h * h / (r * r + h * h) - 1.0
    assert axial_near_field_error(ph, h) == pytest.approx(expected, abs=ATOL_ERROR)


def test_rectangle_against_howell(tmp_path):
    """A Lambertian a x b rectangle on its axis at c is four a/2 x b/2 rectangles seen
    from under their corner: E = 4 pi L F(a/2, b/2, c) (Howell B-3), L = I0 / (a b); at
    the default distance, 5 times the largest dimension."""
    from spectrace.photometry.near_field import axial_near_field_error

    from spectrace.validation.reference import rectangle_corner_factor

    a, b = 0.6, 0.2
    ph = lambertian(tmp_path, (b, a, 0.0))
    c = 5 * a
    expected = 4 * np.pi * I0 / (a * b) * rectangle_corner_factor(a / 2, b / 2, c) \
        / (I0 / c**2) - 1.0
    assert axial_near_field_error(ph) == pytest.approx(expected, abs=ATOL_ERROR)


def test_point_opening_has_no_error(tmp_path):
    """A file without an opening is a point: no near-field error."""
    from spectrace.photometry.near_field import axial_near_field_error

    assert axial_near_field_error(lambertian(tmp_path, (0.0, 0.0, 0.0))) == 0.0
