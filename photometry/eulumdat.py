"""Reader for EULUMDAT (.ldt) photometric files (A. Stockmar, 1990).

Line-oriented: 1 company, 2 type indicator Ityp, 3 symmetry indicator Isym (0 none,
1 about the vertical axis, 2 about the C0-C180 plane, 3 about the C90-C270 plane, 4 about
both), 4 Mc (number of C-planes in 0..360), 5 Dc, 6 Ng (intensities per plane), 7 Dg,
8 measurement report, 9 luminaire name, 10 luminaire number, 11 file name, 12 date/user,
13-15 luminaire length/diameter, width, height (mm; the outer dimensions, not kept),
16-17 luminous area length or diameter and width (0: circular), 18-21 its heights at C0,
C90, C180, C270 (mm; ``Photometry.opening``: length along C0-C180, width along
C90-C270), 22 downward flux fraction (%), 23 light output ratio (%),
24 conversion factor for the intensities, 25 tilt during measurement, 26 number n of lamp
sets, then per set: number of lamps, lamp type, total luminous flux of the set (lm),
colour, colour rendering, wattage; then 10 direct ratios, the Mc C-angles, the Ng gamma
angles and the intensities in cd/klm for the stored planes Mc1..Mc2, Ng values each.

Stored planes (indices into the C-angles, 1-based, as in the EULUMDAT description):
Isym 0: 1..Mc; 1: 1; 2: 1..Mc/2+1 (C0-C180); 3: 3Mc/4+1..3Mc/4+1+Mc/2, wrapping past Mc
(C270 through C0 to C90); 4: 1..Mc/4+1 (C0-C90). For Isym 3 the stored half is mirrored
(I(C) = I(180 - C)) onto C90-C270 so that the record's horizontal angles increase.

Intensities: cd = value * (flux of lamp set 1) / 1000 * conversion factor. The set's
field is its total luminous flux (all its lamps), so the number of lamps is not multiplied
in again; a negative number of lamps (used by some tools for absolute photometry) is read
as its absolute value. Decimal commas ("0,5") are accepted in numbers.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from spectrace.errors import FileFormatError

from .ies import check_finite, count_text
from .model import Photometry

_SYMMETRY = {0: "none", 1: "rotational", 2: "bilateral_0_180", 3: "bilateral_90_270",
             4: "quadrant"}
MM_TO_M = 1e-3


def parse_ldt(path: str | Path, text: str) -> Photometry:
    """Parse the text of a EULUMDAT file (``path`` names it in messages)."""
    path = Path(path)
    # "\r\r\n": CRLF converted to CRLF once more (a text-mode transfer) is one line end
    lines = re.sub(r"\r+\n", "\n", text).splitlines()
    reader = _Lines(lines, path)
    company = reader.text(1, "company identification")
    reader.integer(2, "type indicator Ityp", choices=(0, 1, 2, 3))
    isym = reader.integer(3, "symmetry indicator Isym", choices=(0, 1, 2, 3, 4))
    mc = reader.integer(4, "number of C-planes Mc", minimum=1)
    reader.number(5, "distance between C-planes Dc")
    ng = reader.integer(6, "number of intensities per C-plane Ng", minimum=2)
    reader.number(7, "distance between intensities Dg")
    report = reader.text(8, "measurement report number")
    luminaire = reader.text(9, "luminaire name")
    number = reader.text(10, "luminaire number")
    file_name = reader.text(11, "file name")
    date = reader.text(12, "date/user")
    for k, name in ((13, "luminaire length"), (14, "luminaire width"),
                    (15, "luminaire height")):
        reader.number(k, name)  # the outer dimensions: checked, not the luminous opening
    area = [reader.number(k, name) * MM_TO_M for k, name in (
        (16, "length or diameter of luminous area"), (17, "width of luminous area"),
        (18, "height of luminous area C0"), (19, "height of luminous area C90"),
        (20, "height of luminous area C180"), (21, "height of luminous area C270"))]
    dff = reader.number(22, "downward flux fraction DFF")
    lorl = reader.number(23, "light output ratio LORL")
    conversion = reader.number(24, "conversion factor for luminous intensities")
    if not conversion > 0:
        raise FileFormatError(
            f"{path}: line 24 (conversion factor for luminous intensities): must be "
            f"> 0 (got {conversion:g})")
    reader.number(25, "tilt of luminaire during measurement")
    n_sets = reader.integer(26, "number of standard sets of lamps", minimum=1)
    sets = []
    for s in range(n_sets):
        base = 27 + 6 * s
        sets.append({
            "n": abs(reader.integer(base, f"lamp set {s + 1}: number of lamps")),
            "type": reader.text(base + 1, f"lamp set {s + 1}: type of lamps"),
            "flux": reader.number(base + 2, f"lamp set {s + 1}: total luminous flux"),
            "colour": reader.text(base + 3, f"lamp set {s + 1}: colour"),
            "cri": reader.text(base + 4, f"lamp set {s + 1}: colour rendering"),
            "watts": reader.number(base + 5, f"lamp set {s + 1}: wattage"),
        })
    if not sets[0]["flux"] > 0:
        raise FileFormatError(f"{path}: lamp set 1: total luminous flux: must be > 0 "
                              f"(got {sets[0]['flux']:g})")
    if isym in (2,) and mc % 2 or isym in (3, 4) and mc % 4:
        raise FileFormatError(f"{path}: line 4 (number of C-planes Mc): {mc} does not divide for "
                              f"symmetry indicator Isym {isym}")
    n_stored = stored_plane_count(isym, mc)
    rest = 27 + 6 * n_sets  # first line after the lamp sets
    tokens = [t for line in lines[rest - 1 :] for t in line.split()]
    need = 10 + mc + ng + n_stored * ng
    if len(tokens) < need:  # before allocating: a corrupt count may be astronomically large
        raise FileFormatError(
            f"{path}: intensities: the file ends early (truncated: {count_text(need)} numbers "
            f"expected after the lamp sets - 10 direct ratios, {count_text(mc)} C-angles, "
            f"{count_text(ng)} gamma angles, {count_text(n_stored)} x {count_text(ng)} "
            f"intensities - {len(tokens)} found)"
        )
    stored = stored_planes(isym, mc)
    if len(tokens) > need:
        raise FileFormatError(
            f"{path}: intensities: wrong counts: Mc = {mc}, Ng = {ng}, Isym = {isym} call for "
            f"{need} numbers after the lamp sets but {len(tokens)} follow"
        )
    values = np.array([_number(path, t, "numbers after the lamp sets") for t in tokens])
    c_all = values[10 : 10 + mc]
    gamma = values[10 + mc : 10 + mc + ng]
    table = values[10 + mc + ng :].reshape(stored.size, ng)
    _increasing(path, "C-angles", c_all)
    _increasing(path, "gamma angles", gamma)
    if gamma[0] < 0 or gamma[-1] > 180:
        raise FileFormatError(f"{path}: gamma angles: must lie in 0..180 "
                              f"(got {gamma[0]:g}..{gamma[-1]:g})")
    if np.any(table < 0):
        k, j = np.argwhere(table < 0)[0]
        raise FileFormatError(f"{path}: intensities: negative value {table[k, j]:g} at C = "
                              f"{c_all[stored[k]]:g}, gamma = {gamma[j]:g}")
    horizontal = _canonical_planes(path, isym, c_all, stored)
    if isym == 3:
        order = np.argsort(horizontal)
        horizontal, table = horizontal[order], table[order]
    factor = sets[0]["flux"] / 1000.0 * conversion
    check_finite(path, table, factor)
    keywords = {
        "MANUFAC": company, "TEST": report, "LUMINAIRE": luminaire, "LUMCAT": number,
        "FILENAME": file_name, "ISSUEDATE": date, "LAMP": sets[0]["type"],
        "LAMPS": str(sets[0]["n"]), "COLOUR": sets[0]["colour"], "CRI": sets[0]["cri"],
        "DFF": f"{dff:g}", "LORL": f"{lorl:g}",
    }
    return Photometry(
        path=path,
        format="EULUMDAT",
        photometric_type="C",
        vertical_angles=gamma,
        horizontal_angles=horizontal,
        candela=table * factor,
        keywords={k: v for k, v in keywords.items() if v},
        symmetry=_SYMMETRY[isym],
        lumens_per_lamp=sets[0]["flux"] / max(sets[0]["n"], 1),
        n_lamps=sets[0]["n"],
        applied_factor=factor,
        multiplier=conversion,
        input_watts=sets[0]["watts"],
        opening_m=(area[1], area[0], max(area[2:])),
        opening_side_heights=tuple(area[2:]),
    )


def stored_plane_count(isym: int, mc: int) -> int:
    """How many C-planes a file with symmetry ``isym`` and ``mc`` planes stores."""
    return {0: mc, 1: 1, 2: mc // 2 + 1, 3: mc // 2 + 1, 4: mc // 4 + 1}[isym]


def stored_planes(isym: int, mc: int) -> np.ndarray:
    """Indices (0-based) into the Mc C-angles of the planes stored for ``isym``, in the
    file's order (Mc1..Mc2 of the EULUMDAT description, wrapping past the last for Isym 3)."""
    if isym == 0:
        return np.arange(mc)
    if isym == 1:
        return np.array([0])
    if isym == 2:
        return np.arange(mc // 2 + 1)
    if isym == 3:
        return (3 * mc // 4 + np.arange(mc // 2 + 1)) % mc
    return np.arange(mc // 4 + 1)


def _canonical_planes(path, isym, c_all, stored) -> np.ndarray:
    c = c_all[stored]
    expect = {2: (0.0, 180.0), 4: (0.0, 90.0), 3: (270.0, 90.0)}
    if isym == 1:
        return np.array([0.0])
    if c_all[0] != 0:
        raise FileFormatError(f"{path}: C-angles: must start at 0 (got {c_all[0]:g})")
    if isym == 0:
        if c_all[-1] >= 360:
            raise FileFormatError(f"{path}: C-angles: must lie below 360 (got {c_all[-1]:g})")
        return c
    lo, hi = expect[isym]
    if not (np.isclose(c[0], lo) and np.isclose(c[-1], hi)):
        raise FileFormatError(
            f"{path}: C-angles: Isym {isym} stores C{lo:g}..C{hi:g} but the planes "
            f"there are C{c[0]:g}..C{c[-1]:g}")
    if isym == 3:
        return np.mod(180.0 - c, 360.0)
    return c


def _number(path, token: str, field: str) -> float:
    try:
        value = float(token.replace(",", "."))
    except ValueError:
        raise FileFormatError(f"{path}: {field}: {token[:30]!r} is not a number") from None
    if not np.isfinite(value):
        raise FileFormatError(f"{path}: {field}: {token!r} is not a finite number")
    return value


def _increasing(path, field, values) -> None:
    if values.size > 1 and np.any(np.diff(values) <= 0):
        raise FileFormatError(f"{path}: {field}: must increase")


class _Lines:
    """Header lines by their 1-based EULUMDAT line number, with messages naming them."""

    def __init__(self, lines: list[str], path: Path):
        self.lines, self.path = lines, path

    def text(self, k: int, field: str) -> str:
        if k > len(self.lines):
            raise FileFormatError(
                f"{self.path}: line {k} ({field}): the file ends early (truncated)")
        return self.lines[k - 1].strip()

    def number(self, k: int, field: str) -> float:
        token = self.text(k, field)
        if not token:
            raise FileFormatError(f"{self.path}: line {k} ({field}): empty, a number is expected")
        return _number(self.path, token.split()[0], f"line {k} ({field})")

    def integer(self, k: int, field: str, minimum: int | None = None, choices=None) -> int:
        value = self.number(k, field)
        if value != int(value):
            raise FileFormatError(f"{self.path}: line {k} ({field}): must be a whole number "
                                  f"(got {value:g})")
        value = int(value)
        if minimum is not None and value < minimum:
            raise FileFormatError(f"{self.path}: line {k} ({field}): must be >= {minimum} "
                                  f"(got {value})")
        if choices is not None and value not in choices:
            raise FileFormatError(f"{self.path}: line {k} ({field}): must be one of "
                                  f"{', '.join(map(str, choices))} (got {value})")
        return value
