"""Reading LM-63 and EULUMDAT files: versions, layout freedom, factors, symmetry, Type B.

Every file is written here (by spectrace.photometry.generate or by hand) from known
numbers; the checks compare what the reader returns with those numbers.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from spectrace.photometry import generate as G
from spectrace.photometry import read_photometry, type_b_to_c, type_c_to_b

EXACT_RTOL = 1e-8  # numbers written with 9 significant digits (relative rounding <= 5e-9)
INTERP_RTOL = 1e-9  # the same bilinear interpolation on the same nodes
ANGLE_ATOL = 1e-9
GAMMA = np.arange(0.0, 180.001, 5.0)

KEYWORDS = {"TEST": "T-001", "TESTLAB": "spectrace lab", "ISSUEDATE": "2026-12-01",
            "MANUFAC": "spectrace examples", "LUMINAIRE": "Downlight\nwith a long name"}


def quadrant_symmetric(gamma, c):
    """A profile with the symmetries of a rectangle: I(C) = I(-C) = I(180 - C)."""
    g, cc = np.radians(gamma), np.radians(c)
    return 100.0 * (1.2 + np.cos(g)) * (1.0 + 0.5 * np.cos(2 * cc))


def rng_points(rng, n=2000):
    return rng.uniform(-30.0, 200.0, n), rng.uniform(-400.0, 800.0, n)


@pytest.mark.parametrize("version", list(G.HEADER_LINES))
def test_each_lm63_version_parses(tmp_path, version):
    """Each LM-63 edition's header line is recognised, its keywords kept, its numbers read."""
    h = G.horizontal_angles("quadrant", 30.0)
    table = G.tabulate(quadrant_symmetric, GAMMA, h)
    kw = dict(KEYWORDS) if version != "LM-63-1986" else {"TEXT": "a 1986 label line"}
    path = G.write_ies(tmp_path / "v.ies", GAMMA, h, table, version=version, keywords=kw)
    ph = read_photometry(path)
    assert ph.format == version
    assert ph.photometric_type == "C" and ph.symmetry == "quadrant"
    np.testing.assert_allclose(ph.candela, table, rtol=EXACT_RTOL)
    np.testing.assert_array_equal(ph.vertical_angles, GAMMA)
    if version == "LM-63-1986":
        assert ph.keywords["TEXT"] == "a 1986 label line"
    else:
        assert ph.keywords["MANUFAC"] == "spectrace examples"
        assert ph.keywords["LUMINAIRE"] == "Downlight\nwith a long name"  # [MORE]


def test_latin1_commas_and_numbers_split_anyhow(tmp_path, rng):
    """Latin-1 keyword text, comma separators and numbers broken over lines at random
    positions read the same table as a plain file."""
    h = G.horizontal_angles("bilateral_0_180", 22.5)
    table = G.tabulate(quadrant_symmetric, GAMMA, h)
    plain = read_photometry(G.write_ies(tmp_path / "plain.ies", GAMMA, h, table))
    path = G.write_ies(tmp_path / "odd.ies", GAMMA, h, table, separator=",",
                       keywords={"MANUFAC": "Lumière Génerale", "LAMP": "LED 3000 K"},
                       values_per_line=7, newline="\n")
    text = path.read_bytes().decode("latin-1")
    head, numbers = text.split("TILT=NONE\n")
    tokens = re.split(r"[\s,]+", numbers.strip())
    pieces = []
    for t in tokens:  # a line break, a comma, a comma and spaces, or blanks: at random
        pieces.append(t)
        pieces.append(rng.choice(["\n", ",", " , ", "   ", "\t", ",\n"]))
    path.write_bytes((head + "TILT=NONE\n" + "".join(pieces)).encode("latin-1"))
    assert "Lumière".encode("latin-1") in path.read_bytes()
    ph = read_photometry(path)
    assert ph.keywords["MANUFAC"] == "Lumière Génerale"
    np.testing.assert_allclose(ph.candela, plain.candela, rtol=EXACT_RTOL)


def test_multiplier_ballast_and_ballast_lamp_factor(tmp_path):
    """Candela = file value x multiplier x ballast factor, x the ballast-lamp photometric
    factor in LM-63-1991 (the field is reserved in 2002 and not applied)."""
    h = np.array([0.0])
    table = np.linspace(100.0, 0.0, GAMMA.size)[None]
    kwargs = dict(multiplier=2.0, ballast_factor=0.9, ballast_lamp_factor=0.8)
    old = read_photometry(G.write_ies(tmp_path / "a.ies", GAMMA, h, table,
                                      version="LM-63-1991", **kwargs))
    new = read_photometry(G.write_ies(tmp_path / "b.ies", GAMMA, h, table,
                                      version="LM-63-2002", **kwargs))
    np.testing.assert_allclose(old.candela, table * 2.0 * 0.9 * 0.8, rtol=EXACT_RTOL)
    np.testing.assert_allclose(new.candela, table * 2.0 * 0.9, rtol=EXACT_RTOL)


def test_relative_and_absolute_photometry(tmp_path):
    """lumens = -1 is absolute photometry (no lamp lumens); a positive value is kept."""
    h, table = np.array([0.0]), np.full((1, GAMMA.size), 10.0)
    absolute = read_photometry(G.write_ies(tmp_path / "a.ies", GAMMA, h, table))
    relative = read_photometry(G.write_ies(tmp_path / "r.ies", GAMMA, h, table, n_lamps=2,
                                           lumens_per_lamp=1500.0))
    assert absolute.lumens_per_lamp is None
    assert relative.lumens_per_lamp == 1500.0 and relative.n_lamps == 2
    np.testing.assert_allclose(relative.candela, absolute.candela)


def test_tilt_include_and_tilt_file(tmp_path):
    """TILT=INCLUDE and TILT=<file> (relative to the IES file's folder) are read; the record
    is the luminaire as measured, tilt 0, so the candela carry the table's factor at 0."""
    h, table = np.array([0.0]), np.full((1, GAMMA.size), 10.0)
    tilt = (1, [0.0, 45.0, 90.0], [0.95, 0.9, 0.8])
    inc = read_photometry(G.write_ies(tmp_path / "inc.ies", GAMMA, h, table, tilt=tilt))
    (tmp_path / "sub").mkdir()
    sep = read_photometry(G.write_ies(tmp_path / "sub" / "sep.ies", GAMMA, h, table, tilt=tilt,
                                      tilt_file="lamp.tlt"))
    for ph in (inc, sep):
        assert ph.tilt.geometry == 1
        np.testing.assert_array_equal(ph.tilt.angles, [0.0, 45.0, 90.0])
        assert ph.tilt.factor(45.0) == pytest.approx(0.9)
        np.testing.assert_allclose(ph.candela, 0.95 * table, rtol=EXACT_RTOL)
    assert (tmp_path / "sub" / "lamp.tlt").exists()


def test_every_symmetry_gives_the_same_intensity(tmp_path, rng):
    """One distribution written with each LM-63 symmetry (and each EULUMDAT Isym) gives the
    same intensity() everywhere, including angles outside 0..360 and beyond the pole."""
    gamma, c = rng_points(rng)
    full = read_photometry(G.write_ies_function(tmp_path / "none.ies", quadrant_symmetric,
                                                symmetry="none", vertical_angles=GAMMA))
    ref = full.intensity(gamma, c)
    for sym in ("quadrant", "bilateral_0_180", "bilateral_90_270"):
        ph = read_photometry(G.write_ies_function(tmp_path / f"{sym}.ies", quadrant_symmetric,
                                                  symmetry=sym, vertical_angles=GAMMA))
        assert ph.symmetry == sym
        np.testing.assert_allclose(ph.intensity(gamma, c), ref, rtol=INTERP_RTOL)
    for isym in (0, 2, 3, 4):
        ph = read_photometry(G.write_ldt(tmp_path / f"s{isym}.ldt", quadrant_symmetric,
                                         isym=isym, mc=24, gamma_angles=GAMMA))
        np.testing.assert_allclose(ph.intensity(gamma, c), ref, rtol=INTERP_RTOL)
    # rotational: one plane against the full table of a C-independent profile
    func = G.cos_power(300.0, 2)
    one = read_photometry(G.write_ies_function(tmp_path / "rot.ies", func, symmetry="rotational",
                                               vertical_angles=GAMMA))
    all_c = read_photometry(G.write_ies_function(tmp_path / "all.ies", func, symmetry="none",
                                                 vertical_angles=GAMMA))
    ldt = read_photometry(G.write_ldt(tmp_path / "rot.ldt", func, isym=1, gamma_angles=GAMMA))
    np.testing.assert_allclose(one.intensity(gamma, c), all_c.intensity(gamma, c),
                               rtol=INTERP_RTOL, atol=1e-12)
    np.testing.assert_allclose(ldt.intensity(gamma, c), one.intensity(gamma, c),
                               rtol=INTERP_RTOL, atol=1e-12)


def test_mirror_planes_are_where_the_symmetry_says(tmp_path):
    """bilateral_0_180: I(C) = I(360 - C); bilateral_90_270: I(C) = I(180 - C); an
    asymmetric C-dependence tabulated on the stored half shows it at the mirror angles."""
    def skew(gamma, c):
        return 10.0 + np.radians(np.mod(c, 360.0)) + 0 * gamma  # rises with C

    a = read_photometry(G.write_ies(tmp_path / "a.ies", GAMMA, [0, 90, 180],
                                    G.tabulate(skew, GAMMA, [0, 90, 180])))
    assert a.intensity(30.0, 270.0) == pytest.approx(a.intensity(30.0, 90.0))
    assert a.intensity(30.0, 300.0) == pytest.approx(a.intensity(30.0, 60.0))
    b = read_photometry(G.write_ies(tmp_path / "b.ies", GAMMA, [90, 180, 270],
                                    G.tabulate(skew, GAMMA, [90, 180, 270])))
    assert b.symmetry == "bilateral_90_270"
    assert b.intensity(30.0, 0.0) == pytest.approx(skew(30.0, 180.0))
    assert b.intensity(30.0, 45.0) == pytest.approx(b.intensity(30.0, 135.0))
    assert b.intensity(30.0, 315.0) == pytest.approx(b.intensity(30.0, 225.0))


def test_ldt_and_ies_of_one_distribution_agree(tmp_path, rng):
    """A EULUMDAT file (cd/klm, 1500 lm lamp, conversion factor 1.2) and an IES file of the
    same wall-washer table agree in intensity, flux and peak."""
    func = G.wall_washer(900.0)
    ies = read_photometry(G.write_ies_function(tmp_path / "w.ies", func, symmetry="none",
                                               c_step=15.0, vertical_angles=GAMMA))
    ldt = read_photometry(G.write_ldt(tmp_path / "w.ldt", func, isym=0, mc=24,
                                      gamma_angles=GAMMA, lamp_flux=1500.0,
                                      conversion_factor=1.2, comma_decimal=True))
    gamma, c = rng_points(rng)
    np.testing.assert_allclose(ldt.intensity(gamma, c), ies.intensity(gamma, c), rtol=1e-7,
                               atol=1e-9)
    assert ldt.flux == pytest.approx(ies.flux, rel=1e-7)
    assert ldt.peak_direction == ies.peak_direction
    assert ldt.keywords["MANUFAC"] == "spectrace examples"


def test_intensity_is_zero_outside_the_measured_range(tmp_path):
    """A 0-90 file is dark above the horizon, a 90-180 file below it."""
    down = read_photometry(G.write_ies(tmp_path / "d.ies", [0, 45, 90], [0], [[5, 4, 3]]))
    up = read_photometry(G.write_ies(tmp_path / "u.ies", [90, 135, 180], [0], [[3, 4, 5]]))
    assert down.intensity(90.0, 10.0) == 3 and down.intensity(90.5, 10.0) == 0
    assert up.intensity(89.5, 10.0) == 0 and up.intensity(180.0, 10.0) == 5
    assert down.intensity(22.5, 0.0) == pytest.approx(4.5)  # bilinear


def test_type_c_grid_reproduces_intensity(tmp_path, rng):
    """Bilinear interpolation on type_c_grid() (gamma 0..180, C 0..360) gives intensity()
    for a 0-90 bilateral file, including the dark upper hemisphere."""
    func = G.wall_washer(700.0)
    ph = read_photometry(G.write_ies_function(tmp_path / "g.ies", func,
                                              symmetry="bilateral_0_180", c_step=10.0,
                                              vertical_angles=np.arange(0.0, 90.001, 5.0)))
    g, c, table = ph.type_c_grid()
    assert g[0] == 0 and g[-1] == 180 and c[0] == 0 and c[-1] == 360
    assert table.shape == (c.size, g.size)
    gamma, cc = rng.uniform(0, 180, 3000), rng.uniform(0, 360, 3000)
    gamma = gamma[np.abs(gamma - 90) > 0.01]  # away from the step to zero
    cc = cc[: gamma.size]
    i = np.clip(np.searchsorted(c, cc, "right") - 1, 0, c.size - 2)
    j = np.clip(np.searchsorted(g, gamma, "right") - 1, 0, g.size - 2)
    tc, tg = (cc - c[i]) / (c[i + 1] - c[i]), (gamma - g[j]) / (g[j + 1] - g[j])
    bilinear = (table[i, j] * (1 - tc) * (1 - tg) + table[i + 1, j] * tc * (1 - tg)
                + table[i, j + 1] * (1 - tc) * tg + table[i + 1, j + 1] * tc * tg)
    np.testing.assert_allclose(bilinear, ph.intensity(gamma, cc), rtol=1e-9, atol=1e-9)


def test_type_b_angles_map_to_type_c_as_documented(tmp_path):
    """Type B (H, V) = (0, 0) is the aim (gamma 0), (0, 30) is (gamma 30, C 0), (30, 0) is
    (30, C 270) (H > 0 clockwise seen from above, LM-63), (-30, 0) is (30, C 90); a file
    bright only at (H, V) = (20, 10) is bright in the Type C direction of that point and
    nowhere far from it."""
    for (h, v), (g, c) in {(0, 30): (30, 0), (30, 0): (30, 270), (-30, 0): (30, 90),
                           (0, -30): (30, 180)}.items():
        assert np.allclose(type_b_to_c(h, v), (g, c), atol=ANGLE_ATOL)
        assert np.allclose(type_c_to_b(g, c), (h, v), atol=ANGLE_ATOL)
    H, V = np.arange(-90.0, 90.001, 10.0), np.arange(-90.0, 90.001, 10.0)
    table = np.zeros((H.size, V.size))
    table[np.searchsorted(H, 20.0), np.searchsorted(V, 10.0)] = 1000.0
    ph = read_photometry(G.write_ies(tmp_path / "b.ies", V, H, table, photometric_type="B"))
    gamma, c = type_b_to_c(20.0, 10.0)
    # independent check of the direction: cos gamma = cos H cos V
    cos_h_cos_v = np.cos(np.radians(20.0)) * np.cos(np.radians(10.0))
    assert np.cos(np.radians(gamma)) == pytest.approx(cos_h_cos_v)
    assert ph.intensity(gamma, c) == pytest.approx(1000.0)
    assert ph.peak_direction == pytest.approx((float(gamma), float(c)))
    assert ph.intensity(gamma, 360.0 - c) == 0.0  # the mirror image (H = -20) is dark
    g2, c2 = ph.type_c_grid(step=1.0)[:2]
    assert g2[-1] == 180 and c2[-1] == 360


def test_type_b_lateral_symmetry(tmp_path):
    """A Type B file with H from 0 is laterally symmetric: I(H, V) = I(-H, V)."""
    H, V = np.arange(0.0, 90.001, 10.0), np.arange(-90.0, 90.001, 10.0)
    table = G.tabulate(G.wall_washer(100.0, tilt_deg=20.0), V, H, "B")
    ph = read_photometry(G.write_ies(tmp_path / "b.ies", V, H, table, photometric_type="B"))
    assert ph.symmetry == "bilateral_0_180"
    g, c = type_b_to_c(30.0, 15.0)
    gm, cm = type_b_to_c(-30.0, 15.0)
    assert ph.intensity(g, c) == pytest.approx(ph.intensity(gm, cm))
    assert ph.intensity(g, c) > 0


def type_b_steps_file(tmp_path, vertical):
    """A strongly asymmetric Type B table: constant on each quadrant of the (H, V) square,
    with steps of a tenth of a degree at H = 0 and V = 0 (I = 100 for H < 0, V < 0; 200
    for H < 0, V > 0; 400 for H > 0, V < 0; 800 for H > 0, V > 0), or, with ``vertical``
    from 0, the V >= 0 half (200 and 800) of it."""
    H = np.array([-90.0, -0.1, 0.1, 90.0])
    V = np.asarray(vertical, float)
    table = np.array([[100.0 if v < 0 else 200.0 for v in V]] * 2
                     + [[400.0 if v < 0 else 800.0 for v in V]] * 2)
    return read_photometry(G.write_ies(tmp_path / "steps.ies", V, H, table,
                                       photometric_type="B"))


def test_type_b_convention_by_hand(tmp_path):
    """Derived by hand from LM-63's definition (H clockwise seen from above the floodlight,
    V up towards the photometric horizontal C = 0, H measured inside the tilted B-plane):
    the unit direction d = (cos H sin V, sin H, cos H cos V) in the frame (C = 0, C = 270,
    gamma = 0). Then gamma 60 at C = 45 is d = (0.6124, -0.6124, 0.5): sin H = -0.6124,
    H = -37.76 < 0, V = atan(0.6124 / 0.5) = 50.77 > 0: 200 cd. At C = 315 the mirror
    image, H > 0, V > 0: 800 cd; at C = 135 (H < 0, V < 0) 100 cd; at C = 225 400 cd.
    The grid values at (H, V) = (40, 50) sit at gamma = acos(cos 40 cos 50) = 60.50 deg and
    C = atan2(-sin 40, cos 40 sin 50) = 312.39 deg. A table whose vertical angles start at
    0 is mirrored about the horizontal plane V = 0: 200 cd at C = 135, 800 cd at C = 225."""
    ph = type_b_steps_file(tmp_path, [-90.0, -0.1, 0.1, 90.0])
    assert ph.symmetry == "none"
    expected = {45.0: 200.0, 315.0: 800.0, 135.0: 100.0, 225.0: 400.0}
    for c, candela in expected.items():
        assert ph.intensity(60.0, c) == pytest.approx(candela, rel=1e-12), c
    h, v = np.radians(40.0), np.radians(50.0)
    gamma = np.degrees(np.arccos(np.cos(h) * np.cos(v)))
    c = np.degrees(np.arctan2(-np.sin(h), np.cos(h) * np.sin(v))) % 360.0
    assert (gamma, c) == pytest.approx((60.50, 312.39), abs=0.01)
    assert ph.intensity(gamma, c) == pytest.approx(800.0)
    assert ph.flux == pytest.approx(2 * np.pi * (100 + 200 + 400 + 800) / 4, rel=2e-3)
    half = type_b_steps_file(tmp_path, [0.0, 90.0])
    assert half.symmetry == "bilateral_90_270"
    for c, candela in {45.0: 200.0, 135.0: 200.0, 225.0: 800.0, 315.0: 800.0}.items():
        assert half.intensity(60.0, c) == pytest.approx(candela, rel=1e-12), c
    assert half.flux == pytest.approx(2 * np.pi * (200 + 800) / 2, rel=1e-12)


HAND_WRITTEN = """IESNA:LM-63-1995\r
[TEST] hand-written\r
[MANUFAC] Acme\r
[MORE] Lighting\r
[LUMINAIRE] two-plane test\r
TILT=INCLUDE\r
1\r
3\r
0 45 90\r
1.0 .8 .5\r
2 1000 0.5 3 2 1 1 1.0 2.0 0.0\r
0.9 1 50\r
0 45 90\r
0 90\r
100 80,\r
40 200 160 80\r
"""


def test_a_hand_written_file(tmp_path):
    """A literal LM-63-1995 file (written by hand, not by the generator): TILT=INCLUDE,
    two planes C0 and C90 (quadrant), multiplier 0.5 and ballast 0.9, widths in feet."""
    path = tmp_path / "hand.ies"
    path.write_bytes(HAND_WRITTEN.encode("ascii"))
    ph = read_photometry(path)
    assert ph.format == "LM-63-1995" and ph.symmetry == "quadrant"
    assert ph.keywords["MANUFAC"] == "Acme\nLighting"
    assert ph.n_lamps == 2 and ph.lumens_per_lamp == 1000
    np.testing.assert_allclose(ph.candela, [[45, 36, 18], [90, 72, 36]])  # x 0.5 x 0.9
    assert ph.opening_m == pytest.approx((0.3048, 0.6096, 0.0))
    assert ph.tilt.factor(0.0) == 1.0 and ph.tilt.factor(67.5) == pytest.approx(0.65)
    assert ph.intensity(45.0, 90.0) == pytest.approx(72.0)
    assert ph.intensity(45.0, 270.0) == pytest.approx(72.0)  # quadrant mirror
    assert ph.intensity(45.0, 180.0) == pytest.approx(36.0)
    assert ph.intensity(45.0, 45.0) == pytest.approx(54.0)  # halfway between the planes
    assert ph.intensity(22.5, 45.0) == pytest.approx((45 + 36 + 90 + 72) / 4)
    assert ph.peak_direction == (0.0, 90.0)
