"""Write IES LM-63 and EULUMDAT files from an analytic or tabulated intensity distribution.

Used by the tests (files whose flux and angles are known in closed form) and by
``scenes/luminaires/make_luminaires.py`` (the example luminaires). A distribution is a
function ``I(gamma, c)`` of Type C angles in degrees (numpy broadcast) returning cd; for
Type B files it is still given in Type C angles and sampled at the converted (H, V).

* :func:`tabulate`: sample a function on a file's angles.
* :func:`horizontal_angles`: the horizontal angles that LM-63 uses for a symmetry.
* :func:`write_ies`: any LM-63 version, symmetry, photometric type (C or B), TILT=NONE,
  INCLUDE or a separate file, factors, keywords, number layout (values per line,
  separators); Latin-1 bytes.
* :func:`write_ldt`: EULUMDAT with Isym 0-4 from a function.
* :func:`cos_power`, :func:`isotropic`, :func:`wall_washer`: analytic profiles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spectrace.errors import ParameterError

from .eulumdat import stored_planes
from .model import Photometry, type_b_to_c, type_c_to_b

#: first line of each LM-63 version (1986 has none)
HEADER_LINES = {
    "LM-63-1986": None,
    "LM-63-1991": "IESNA91",
    "LM-63-1995": "IESNA:LM-63-1995",
    "LM-63-2002": "IESNA:LM-63-2002",
    "LM-63-2019": "IES:LM-63-2019",
}
_TYPE_CODES = {"C": 1, "B": 2, "A": 3}
#: EULUMDAT symmetry indicator -> symmetry name
LDT_SYMMETRY = {0: "none", 1: "rotational", 2: "bilateral_0_180",
                3: "bilateral_90_270", 4: "quadrant"}


# ------------------------------------------------------------------ analytic profiles
def cos_power(I0: float, n: float):
    """I = I0 cos^n(gamma) for gamma < 90, 0 below the horizon: flux 2 pi I0 / (n + 1),
    beam angle 2 arccos(0.5^(1/n)), field angle 2 arccos(0.1^(1/n))."""

    def intensity(gamma, c):
        g = np.radians(np.asarray(gamma, np.float64))
        return I0 * np.where(g < np.pi / 2, np.abs(np.cos(g)) ** n, 0.0) + 0.0 * np.asarray(c)

    return intensity


def isotropic(I: float):
    """I everywhere: flux 4 pi I."""

    def intensity(gamma, c):
        return np.full(np.broadcast(np.asarray(gamma), np.asarray(c)).shape, float(I))

    return intensity


def wall_washer(I0: float, tilt_deg: float = 40.0, n: float = 6.0, downlight: float = 0.1):
    """An asymmetric lobe: I0 max(0, d.a)^n with the axis a tilted ``tilt_deg`` from nadir
    towards C = 0, plus ``downlight`` I0 cos(gamma) below the horizon. Mirror-symmetric
    about the C0-C180 plane, much brighter towards C = 0 than C = 180."""
    t = np.radians(tilt_deg)
    a = np.array([np.sin(t), 0.0, np.cos(t)])  # components along C0, C90, nadir

    def intensity(gamma, c):
        g, cc = np.radians(np.asarray(gamma, np.float64)), np.radians(np.asarray(c, np.float64))
        d = (np.sin(g) * np.cos(cc), np.sin(g) * np.sin(cc), np.cos(g))
        lobe = np.maximum(0.0, d[0] * a[0] + d[1] * a[1] + d[2] * a[2]) ** n
        return I0 * (lobe + downlight * np.maximum(0.0, d[2]))

    return intensity


# ------------------------------------------------------------------ tables
def horizontal_angles(symmetry: str, step: float = 15.0) -> np.ndarray:
    """LM-63 Type C horizontal angles for a symmetry, every ``step`` degrees."""
    ranges = {"rotational": (0, 0), "quadrant": (0, 90), "bilateral_0_180": (0, 180),
              "bilateral_90_270": (90, 270), "none": (0, 360)}
    lo, hi = ranges[symmetry]
    if lo == hi:
        return np.array([0.0])
    return np.linspace(lo, hi, int(round((hi - lo) / step)) + 1)


def tabulate(func, vertical_angles, horizontal_angles, photometric_type: str = "C"):
    """Candela table (n_horizontal, n_vertical) of ``func(gamma, c)`` at a file's angles.

    Type C: the file angles are (gamma, C). Type B: they are (V, H) and ``func`` is
    evaluated at the Type C direction of each (H, V).
    """
    v = np.asarray(vertical_angles, np.float64)[None, :]
    h = np.asarray(horizontal_angles, np.float64)[:, None]
    if photometric_type == "C":
        return np.asarray(func(v + 0 * h, h + 0 * v), np.float64)
    gamma, c = type_b_to_c(h + 0 * v, v + 0 * h)
    return np.asarray(func(gamma, c), np.float64)


def _fmt(x: float) -> str:
    return f"{x:.9g}"


def _atomic_write(path: Path, data: bytes) -> Path:
    """``data`` written to ``path`` (its folder made if needed) atomically."""
    from spectrace.images import atomic_path

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        Path(tmp).write_bytes(data)
    return path


def write_ies(
    path,
    vertical_angles,
    horizontal_angles,
    candela,
    *,
    version: str = "LM-63-2002",
    photometric_type: str = "C",
    keywords: dict[str, str] | list[tuple[str, str]] | None = None,
    n_lamps: int = 1,
    lumens_per_lamp: float = -1.0,
    multiplier: float = 1.0,
    ballast_factor: float = 1.0,
    ballast_lamp_factor: float = 1.0,
    input_watts: float = 10.0,
    units: int = 2,
    opening: tuple[float, float, float] = (0.0, 0.0, 0.0),
    tilt: tuple | None = None,
    tilt_file: str | None = None,
    values_per_line: int = 10,
    separator: str = " ",
    newline: str = "\r\n",
) -> Path:
    """Write an LM-63 file; the numbers are written as given (``candela`` is divided by
    nothing: the file's candela times ``multiplier`` * ``ballast_factor`` (*
    ``ballast_lamp_factor`` for 1986/1991) is what a reader returns).

    ``keywords``: a dict or (name, text) pairs, text lines after the first become
    ``[MORE]`` lines; for 1986 a keyword named "TEXT" is written as plain lines.
    ``tilt``: None (TILT=NONE), or (geometry, angles, factors) written INCLUDE, or to
    ``tilt_file`` (a name beside ``path``) when that is given. ``values_per_line`` and
    ``separator`` (" " or ", ") lay out the numbers. Latin-1 encoded.
    """
    if version not in HEADER_LINES:
        raise ParameterError(f"write_ies: unknown version {version!r}")
    vertical = np.asarray(vertical_angles, np.float64)
    horizontal = np.asarray(horizontal_angles, np.float64)
    table = np.asarray(candela, np.float64).reshape(horizontal.size, vertical.size)
    out: list[str] = []
    if HEADER_LINES[version]:
        out.append(HEADER_LINES[version])
    items = list(keywords.items()) if isinstance(keywords, dict) else list(keywords or [])
    for name, text in items:
        text_lines = str(text).split("\n")
        if name == "TEXT":
            out.extend(text_lines)
            continue
        out.append(f"[{name}] {text_lines[0]}".rstrip())
        out.extend(f"[MORE] {more}".rstrip() for more in text_lines[1:])

    def numbers(values) -> list[str]:
        values = [v if isinstance(v, str) else _fmt(v) for v in values]
        return [separator.join(values[k : k + values_per_line])
                for k in range(0, len(values), values_per_line)] or [""]

    if tilt is None:
        out.append("TILT=NONE")
    else:
        geometry, angles, factors = tilt
        tilt_lines = [str(int(geometry)), str(len(angles)), *numbers(angles), *numbers(factors)]
        if tilt_file:
            _atomic_write(Path(path).parent / tilt_file,
                          newline.join(tilt_lines).encode("latin-1") + newline.encode())
            out.append(f"TILT={tilt_file}")
        else:
            out.append("TILT=INCLUDE")
            out.extend(tilt_lines)
    type_code = _TYPE_CODES[photometric_type]
    out.append(" ".join([str(n_lamps), _fmt(lumens_per_lamp), _fmt(multiplier),
                         str(vertical.size), str(horizontal.size), str(type_code), str(units),
                         *(_fmt(x) for x in opening)]))
    out.append(" ".join([_fmt(ballast_factor), _fmt(ballast_lamp_factor), _fmt(input_watts)]))
    out.extend(numbers(vertical))
    out.extend(numbers(horizontal))
    for row in table:
        out.extend(numbers(row))
    return _atomic_write(Path(path), (newline.join(out) + newline).encode("latin-1"))


def write_ies_function(path, func, *, symmetry: str = "rotational",
                       vertical_angles=None, c_step: float = 15.0, **kwargs) -> Path:
    """Tabulate ``func`` at the Type C angles of ``symmetry`` and write it (see
    :func:`write_ies`; vertical angles default to 0..180 every 2.5 degrees)."""
    v = np.arange(0.0, 180.001, 2.5) if vertical_angles is None else np.asarray(vertical_angles)
    h = horizontal_angles(symmetry, c_step)
    return write_ies(path, v, h, tabulate(func, v, h), **kwargs)


def ldt_stored_planes(isym: int, mc: int) -> np.ndarray:
    """Indices (0-based) into the Mc C-angles of the planes an EULUMDAT file stores, in the
    file's order: Mc1..Mc2 of the EULUMDAT description (Isym 3: from C270 through C0 to
    C90, wrapping past the last index)."""
    if isym not in LDT_SYMMETRY:
        raise ParameterError(f"ldt_stored_planes: Isym must be 0..4 (got {isym})")
    return stored_planes(isym, mc)


def write_ldt(
    path,
    func,
    *,
    isym: int = 1,
    mc: int = 24,
    gamma_angles=None,
    lamp_flux: float = 1000.0,
    n_lamps: int = 1,
    conversion_factor: float = 1.0,
    company: str = "spectrace examples",
    luminaire: str = "",
    luminaire_number: str = "",
    report: str = "",
    lamp_type: str = "LED",
    colour: str = "3000K",
    cri: str = "80",
    watts: float = 10.0,
    dimensions_mm: tuple = (100.0, 0.0, 50.0),
    luminous_area_mm: tuple | None = None,
    comma_decimal: bool = False,
) -> Path:
    """Write a EULUMDAT file of ``func(gamma, c)`` (cd) with symmetry indicator ``isym``.

    The file holds cd/klm: I / (lamp_flux / 1000) / conversion_factor, for the planes that
    ``isym`` stores (:func:`ldt_stored_planes`) at Mc C-angles 0, 360/mc, ... and the
    gamma angles (default 0..180 every 2.5 degrees). ``dimensions_mm``: the luminaire's
    length, width, height (lines 13-15); ``luminous_area_mm``: the luminous area's length
    or diameter, width and heights at C0, C90, C180, C270 (lines 16-21; default the
    luminaire's length and width, heights 0). ``comma_decimal`` writes "0,5" as some
    European tools do.
    """
    g = np.arange(0.0, 180.001, 2.5) if gamma_angles is None else np.asarray(gamma_angles)
    c_all = np.arange(mc) * (360.0 / mc)
    planes = c_all[ldt_stored_planes(isym, mc)]
    table = tabulate(func, g, planes) / (lamp_flux / 1000.0) / conversion_factor

    def num(x) -> str:
        s = _fmt(float(x))
        return s.replace(".", ",") if comma_decimal else s

    record = Photometry(path=Path(path), format="EULUMDAT", photometric_type="C",
                        vertical_angles=g, horizontal_angles=_canonical(isym, planes),
                        candela=_canonical_rows(isym, planes, table), symmetry=LDT_SYMMETRY[isym])
    flux = record.flux * lamp_flux / 1000.0 * conversion_factor
    lorl = 100.0 * flux / lamp_flux
    dff = 100.0 * record.flux_between(0.0, 90.0) / record.flux if record.flux > 0 else 100.0
    length, width, height = dimensions_mm
    area = (length, width, 0, 0, 0, 0) if luminous_area_mm is None else luminous_area_mm
    lines = [
        company, "1" if isym == 1 else "3", str(isym), str(mc), num(360.0 / mc), str(g.size),
        num(g[1] - g[0]) if np.allclose(np.diff(g), g[1] - g[0]) else "0",
        report, luminaire, luminaire_number, Path(path).name, "spectrace generate",
        num(length), num(width), num(height), *(num(x) for x in area),
        num(round(dff, 2)), num(round(lorl, 2)), num(conversion_factor), "0",
        "1", str(n_lamps), lamp_type, num(lamp_flux), colour, cri, num(watts),
        *(["0"] * 10),
        *(num(x) for x in c_all), *(num(x) for x in g), *(num(x) for x in table.ravel()),
    ]
    return _atomic_write(Path(path), ("\r\n".join(lines) + "\r\n").encode("latin-1"))


def _canonical(isym: int, planes: np.ndarray) -> np.ndarray:
    """The stored planes as the record holds them (Isym 1: [0]; Isym 3: mirrored, sorted)."""
    if isym == 1:
        return np.array([0.0])
    if isym == 3:
        return np.sort(np.mod(180.0 - planes, 360.0))
    return planes


def _canonical_rows(isym: int, planes: np.ndarray, table: np.ndarray) -> np.ndarray:
    if isym == 3:
        return table[np.argsort(np.mod(180.0 - planes, 360.0))]
    return table


__all__ = [
    "HEADER_LINES", "LDT_SYMMETRY", "cos_power", "horizontal_angles",
    "isotropic", "ldt_stored_planes", "tabulate", "type_b_to_c", "type_c_to_b", "wall_washer",
    "write_ies", "write_ies_function", "write_ldt",
]
