"""The luminous opening of LM-63 files (the signs of width, length and height in each
edition) and EULUMDAT's luminous area (fields 16-21): shape, size in metres, photometric
distance."""

from __future__ import annotations

import pytest
from spectrace.photometry import generate as G
from spectrace.photometry import read_photometry

from spectrace.errors import FileFormatError

#: Sizes are written with 9 significant digits and feet converted exactly (0.3048 m).
SIZE_RTOL = 1e-9

#: (edition, (width, length, height) as written, shape, (width, length, height) in m)
CASES = [
    ("LM-63-1986", (0, 0, 0), "point", (0, 0, 0)),
    ("LM-63-1986", (0.5, 1.2, 0), "rectangle", (0.5, 1.2, 0)),
    ("LM-63-1986", (0.5, 1.2, 0.1), "box", (0.5, 1.2, 0.1)),
    ("LM-63-1986", (-0.3, 0, 0), "disk", (0.3, 0.3, 0)),
    ("LM-63-1991", (-0.3, 0, 0.2), "vertical_cylinder", (0.3, 0.3, 0.2)),
    ("LM-63-1991", (-0.3, 0.6, 0), "ellipse", (0.3, 0.6, 0)),
    ("LM-63-1986", (-0.3, 0.6, 0.2), "ellipsoid", (0.3, 0.6, 0.2)),
    ("LM-63-1995", (-0.3, 0, 0), "disk", (0.3, 0.3, 0)),
    ("LM-63-1995", (-0.3, 0, -0.3), "sphere", (0.3, 0.3, 0.3)),
    ("LM-63-1995", (0, 1.2, -0.1), "horizontal_cylinder_along", (0.1, 1.2, 0.1)),
    ("LM-63-1995", (0.8, 0, -0.1), "horizontal_cylinder_across", (0.8, 0.1, 0.1)),
    ("LM-63-1995", (0.5, -0.6, 0.2), "vertical_elliptical_cylinder", (0.5, 0.6, 0.2)),
    ("LM-63-1995", (-0.5, 0.6, -0.2), "ellipsoid", (0.5, 0.6, 0.2)),
    ("LM-63-2002", (0.6, 0.6, 0), "rectangle", (0.6, 0.6, 0)),
    ("LM-63-2002", (-0.3, -0.3, 0), "disk", (0.3, 0.3, 0)),
    ("LM-63-2002", (-0.3, -0.6, 0), "ellipse", (0.3, 0.6, 0)),
    ("LM-63-2002", (-0.3, -0.3, 0.2), "vertical_cylinder", (0.3, 0.3, 0.2)),
    ("LM-63-2002", (-0.3, -0.6, 0.2), "vertical_elliptical_cylinder", (0.3, 0.6, 0.2)),
    ("LM-63-2002", (-0.3, -0.3, -0.3), "sphere", (0.3, 0.3, 0.3)),
    ("LM-63-2002", (-0.3, -0.4, -0.5), "ellipsoid", (0.3, 0.4, 0.5)),
    ("LM-63-2002", (-0.1, 1.2, -0.1), "horizontal_cylinder_along", (0.1, 1.2, 0.1)),
    ("LM-63-2002", (-0.1, 1.2, -0.2), "horizontal_elliptical_cylinder_along",
     (0.1, 1.2, 0.2)),
    ("LM-63-2002", (0.8, -0.1, -0.1), "horizontal_cylinder_across", (0.8, 0.1, 0.1)),
    ("LM-63-2019", (0, -0.3, -0.3), "vertical_disk", (0, 0.3, 0.3)),
    ("LM-63-2019", (0, -0.3, -0.5), "vertical_ellipse", (0, 0.3, 0.5)),
    ("LM-63-2019", (0.6, 1.2, 0.1), "box", (0.6, 1.2, 0.1)),
]


def ies_file(tmp_path, version, opening, units=2):
    return read_photometry(G.write_ies_function(tmp_path / "o.ies", G.cos_power(100.0, 2),
                                                version=version, opening=opening,
                                                units=units))


@pytest.mark.parametrize(("version", "written", "shape", "size"), CASES)
def test_lm63_opening_shapes_by_edition(tmp_path, version, written, shape, size):
    """Each sign pattern of the edition's table gives its shape; sizes are the absolute
    values, a circle's diameter both width and length."""
    o = ies_file(tmp_path, version, written).opening
    assert o.shape == shape
    assert (o.width, o.length, o.height) == pytest.approx(size, rel=SIZE_RTOL)


def test_the_disk_changed_sign_between_editions(tmp_path):
    """A disk is width < 0 with length 0 in 1986-1995 and width = length < 0 in 2002-2019;
    each edition's disk is no shape of the other, and saying so names the file."""
    assert ies_file(tmp_path, "LM-63-1995", (-0.3, 0, 0)).opening.shape == "disk"
    for version, written in (("LM-63-2002", (-0.3, 0, 0)), ("LM-63-1986", (-0.3, -0.3, 0))):
        ph = ies_file(tmp_path, version, written)  # the file reads; its opening does not
        with pytest.raises(FileFormatError, match=f"{ph.path}.*no shape of {version}"):
            _ = ph.opening


def test_feet_are_converted_and_the_photometric_distance(tmp_path):
    """Units 1 (feet): a 2 x 4 x 0.5 ft box is 0.6096 x 1.2192 x 0.1524 m, photometric
    distance 5 x 1.2192 m; a point has distance 0."""
    o = ies_file(tmp_path, "LM-63-2002", (2.0, 4.0, 0.5), units=1).opening
    assert (o.width, o.length, o.height) == pytest.approx((0.6096, 1.2192, 0.1524),
                                                          rel=SIZE_RTOL)
    assert o.photometric_distance == pytest.approx(5 * 1.2192, rel=SIZE_RTOL)
    assert ies_file(tmp_path, "LM-63-2002", (0, 0, 0)).opening.photometric_distance == 0.0


@pytest.mark.parametrize(("area_mm", "shape", "size"), [
    ((0, 0, 0, 0, 0, 0), "point", (0, 0, 0)),
    ((200, 0, 0, 0, 0, 0), "disk", (0.2, 0.2, 0)),
    ((200, 0, 50, 50, 50, 50), "vertical_cylinder", (0.2, 0.2, 0.05)),
    ((1200, 300, 0, 0, 0, 0), "rectangle", (0.3, 1.2, 0)),
    ((1200, 300, 80, 60, 80, 60), "box", (0.3, 1.2, 0.08)),
])
def test_eulumdat_luminous_area(tmp_path, area_mm, shape, size):
    """EULUMDAT fields 16-21 (length or diameter, width, heights at C0/C90/C180/C270, mm),
    not the luminaire's outer dimensions (fields 13-15, here 1500 x 400 x 100 mm)."""
    path = G.write_ldt(tmp_path / "a.ldt", G.cos_power(100.0, 2),
                       dimensions_mm=(1500.0, 400.0, 100.0), luminous_area_mm=area_mm)
    o = read_photometry(path).opening
    assert o.shape == shape
    assert (o.width, o.length, o.height) == pytest.approx(size, rel=SIZE_RTOL)
    assert o.side_heights == pytest.approx([h / 1000 for h in area_mm[2:]])


def test_eulumdat_width_without_length_is_refused_naming_the_file(tmp_path):
    """A luminous width with no length: the file reads, its opening raises one line naming
    the file."""
    path = G.write_ldt(tmp_path / "w.ldt", G.cos_power(100.0, 2),
                       luminous_area_mm=(0, 300, 0, 0, 0, 0))
    ph = read_photometry(path)
    with pytest.raises(FileFormatError, match=f"{path}: luminous area"):
        _ = ph.opening
