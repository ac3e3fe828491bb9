"""Reader for IES LM-63 photometric files: 1986, 1991 (``IESNA91``), 1995, 2002, 2019.

The first line names the version (``IESNA91``, ``IESNA:LM-63-1995``, ``IESNA:LM-63-2002``,
``IES:LM-63-2019``); a file without such a line is LM-63-1986. Then come keyword lines
``[KEYWORD] text`` (``[MORE]`` continues the previous keyword's text on a new line; lines
that are not keywords, as in LM-63-1986, are kept under ``"TEXT"``), then ``TILT=``, then
numbers separated by blanks, commas or line ends, split over lines in any way:

    TILT data (only for TILT=INCLUDE; from the named file for TILT=<file>)
    #lamps  lumens/lamp (-1: absolute)  candela-multiplier  #vertical  #horizontal
    photometric-type (1 C, 2 B, 3 A)  units (1 feet, 2 metres)  width  length  height
    ballast-factor  ballast-lamp-photometric-factor (1986, 1991; "future use" in 1995
    and 2002; file-generation-type in 2019)  input-watts
    vertical angles, horizontal angles, candela (for each horizontal angle, one value
    per vertical angle)

The bytes are decoded as UTF-8 when they are valid UTF-8, as Latin-1 otherwise.

Factors: the candela values are multiplied by the candela multiplier, the ballast factor,
the ballast-lamp photometric factor (LM-63-1986 and -1991 only; the field is reserved in
1995/2002 and a file-generation code in 2019, so it is not applied there) and the tilt
factor. TILT: the tilt table (``TILT=INCLUDE``, or ``TILT=<file>`` read relative to the IES
file's folder) gives multiplying factors against the luminaire's tilt from the orientation
in which it was photometered. The record describes the luminaire in that measured
orientation, a tilt of 0 degrees, so the factor applied is the table's value at 0 degrees
(linear between entries, clamped to the first or last entry when 0 is outside the table;
it is 1 in practice). The table is kept in ``Photometry.tilt`` for other tilts.

Type A photometry (automotive) is refused.

Horizontal angles of Type C files: one angle (rotational symmetry), 0-90 (quadrant),
0-180 (bilateral about the C0-C180 plane), 90-270 (bilateral about the C90-C270 plane),
0 to more than 180 (no symmetry; a last angle below 360 wraps to 0). Vertical angles: any
increasing range in [0, 180] (0-90, 90-180, 0-180); the intensity is 0 outside it. Type B:
horizontal angles 0-90 (laterally symmetric) or from below 0 (-90-90), vertical angles
0-90 (symmetric about the horizontal plane) or from below 0, within [-180, 180] (the
convention is in :mod:`spectrace.photometry.model`).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from spectrace.errors import FileFormatError

from .model import Photometry, Tilt

_VERSIONS = {
    "IESNA91": "LM-63-1991",
    "IESNA:LM-63-1991": "LM-63-1991",
    "IESNA:LM-63-1995": "LM-63-1995",
    "IESNA:LM-63-2002": "LM-63-2002",
    "IES:LM-63-2019": "LM-63-2019",
    "IESNA:LM-63-2019": "LM-63-2019",
}
#: a first line that claims an LM-63 edition (an unknown one is refused, not read as 1986)
_VERSION_LIKE = re.compile(r"^\s*(IES(NA)?\s*:\s*LM-63|IESNA\s*\d)", re.IGNORECASE)
_KEYWORD = re.compile(r"^\s*\[([^\]]*)\]\s?(.*)$")
_SEPARATORS = re.compile(r"[\s,]+")
_TYPES = {1: "C", 2: "B", 3: "A"}
FEET_TO_M = 0.3048


#: The largest photometric or tilt file read (bytes): real ones have a few kB to a few MB.
MAX_FILE_BYTES = 64 * 2**20


def read_file(path: Path) -> bytes:
    """The bytes of a regular file of at most :data:`MAX_FILE_BYTES`; OSError otherwise (a
    device such as /dev/zero or a FIFO would never end, or block)."""
    import errno
    import os
    import stat

    # O_NONBLOCK: opening a FIFO does not wait for a writer (no effect on regular files)
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(fd, "rb") as f:  # a missing file: OSError above; a folder: at read
        info = os.fstat(f.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise OSError(errno.EINVAL, "not a regular file")
        if info.st_size > MAX_FILE_BYTES:
            raise OSError(errno.EFBIG, f"too large for a photometric file "
                                       f"({info.st_size} bytes, at most {MAX_FILE_BYTES})")
        return f.read(MAX_FILE_BYTES + 1)


def decode(data: bytes) -> str:
    """UTF-8 if the bytes are valid UTF-8, else Latin-1 (which takes any byte)."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return text.lstrip("\ufeff").replace("\x1a", "")  # BOM, DOS end-of-file mark


def is_ies(text: str) -> bool:
    """Whether the text looks like an LM-63 file (a ``TILT=`` line)."""
    return any(line.strip().upper().startswith("TILT") and "=" in line
               for line in text.splitlines())


def parse_ies(path: str | Path, text: str) -> Photometry:
    """Parse the text of an LM-63 file (``path`` names it in messages and finds TILT files)."""
    path = Path(path)
    lines = text.splitlines()
    first = lines[0].strip() if lines else ""
    fmt = _VERSIONS.get(first.upper().replace(" ", ""))
    start = 1
    if fmt is None:
        if _VERSION_LIKE.match(first):
            raise FileFormatError(
                f"{path}: format line: unknown IES version {first[:40]!r} (known: IESNA91, "
                "IESNA:LM-63-1995, IESNA:LM-63-2002, IES:LM-63-2019, or none for 1986)"
            )
        fmt, start = "LM-63-1986", 0
    tilt_at = next(
        (i for i in range(start, len(lines))
         if lines[i].strip().upper().startswith("TILT") and "=" in lines[i]),
        None,
    )
    if tilt_at is None:
        raise FileFormatError(
            f"{path}: TILT: no 'TILT=' line (not an IES LM-63 file, or truncated)")
    keywords = _keywords(lines[start:tilt_at])
    tilt_spec = lines[tilt_at].split("=", 1)[1].strip()
    tokens = _Tokens(_SEPARATORS.split("\n".join(lines[tilt_at + 1 :])), path)

    tilt = None
    if tilt_spec.upper() == "INCLUDE":
        tilt = _read_tilt(tokens)
    elif tilt_spec.upper() != "NONE":
        tilt_path = path.parent / tilt_spec
        try:
            tilt_text = decode(read_file(tilt_path))
        except OSError as e:
            raise FileFormatError(
                f"{path}: TILT: cannot read tilt file {tilt_spec!r} ({tilt_path}): "
                f"{e.strerror or e}"
            ) from None
        tilt_tokens = _Tokens(_SEPARATORS.split(tilt_text), tilt_path)
        tilt = _read_tilt(tilt_tokens)
        tilt_tokens.expect_end("tilt table")
    tilt_factor = tilt.factor(0.0) if tilt is not None else 1.0

    n_lamps = tokens.integer("number of lamps", minimum=1)
    lumens = tokens.number("lumens per lamp")
    if lumens <= 0 and lumens != -1:
        raise FileFormatError(
            f"{path}: lumens per lamp: must be > 0 or -1 (absolute) (got {lumens:g})")
    multiplier = tokens.number("candela multiplier")
    if not multiplier > 0:
        raise FileFormatError(f"{path}: candela multiplier: must be > 0 (got {multiplier:g})")
    n_v = tokens.integer("number of vertical angles", minimum=2)
    n_h = tokens.integer("number of horizontal angles", minimum=1)
    type_code = tokens.integer("photometric type")
    if type_code not in _TYPES:
        raise FileFormatError(
            f"{path}: photometric type: must be 1 (C), 2 (B) or 3 (A) (got {type_code})"
        )
    ptype = _TYPES[type_code]
    if ptype == "A":
        raise FileFormatError(
            f"{path}: photometric type: Type A (automotive) photometry is not supported"
        )
    units = tokens.integer("units type")
    if units not in (1, 2):
        raise FileFormatError(f"{path}: units type: must be 1 (feet) or 2 (metres) (got {units})")
    scale = FEET_TO_M if units == 1 else 1.0
    opening = tuple(tokens.number(name) * scale for name in ("width", "length", "height"))
    ballast = tokens.number("ballast factor")
    if not ballast > 0:
        raise FileFormatError(f"{path}: ballast factor: must be > 0 (got {ballast:g})")
    blpf_field = tokens.number("ballast-lamp photometric factor")
    blpf = blpf_field if fmt in ("LM-63-1986", "LM-63-1991") else 1.0
    if not blpf > 0:
        raise FileFormatError(
            f"{path}: ballast-lamp photometric factor: must be > 0 (got {blpf:g})")
    watts = tokens.number("input watts")

    vertical = tokens.numbers(n_v, "vertical angles")
    horizontal = tokens.numbers(n_h, "horizontal angles")
    values = tokens.numbers(n_v * n_h, "candela values")
    tokens.expect_end("candela values", f"{n_h} x {n_v}")

    _check_increasing(path, "vertical angles", vertical)
    _check_increasing(path, "horizontal angles", horizontal)
    candela = values.reshape(n_h, n_v)
    bad = np.argwhere(candela < 0)
    if bad.size:
        i, j = bad[0]
        raise FileFormatError(
            f"{path}: candela values: negative value {candela[i, j]:g} at horizontal angle "
            f"{horizontal[i]:g}, vertical angle {vertical[j]:g}"
        )
    symmetry = _symmetry(path, ptype, vertical, horizontal)
    factor = multiplier * ballast * blpf * tilt_factor
    check_finite(path, candela, factor)
    return Photometry(
        path=path,
        format=fmt,
        photometric_type=ptype,
        vertical_angles=vertical,
        horizontal_angles=horizontal,
        candela=candela * factor,
        keywords=keywords,
        symmetry=symmetry,
        lumens_per_lamp=None if lumens == -1 else lumens,
        n_lamps=n_lamps,
        applied_factor=factor,
        multiplier=multiplier,
        ballast_factor=ballast,
        ballast_lamp_factor=blpf,
        tilt=tilt,
        tilt_factor=tilt_factor,
        input_watts=watts,
        opening_m=opening,
    )


def count_text(n: int) -> str:
    """A count for a message: its digits, or its order of magnitude when absurdly long."""
    digits = str(n)
    return digits if len(digits) <= 12 else f"about 10^{len(digits) - 1}"


#: The largest intensity (cd) a file may give once its factors are applied: the brightest
#: searchlights reach about 1e9 cd; a table beyond this comes from a wrong multiplier, and
#: its watts per steradian (I / 683 / 107 nm, then 1/r^2) would approach the renderer's
#: single-precision limit (3.4e38).
MAX_CANDELA = 1e20


def check_finite(path: Path, values: np.ndarray, factor: float) -> None:
    """FileFormatError unless ``values * factor`` (the candela table with the file's factors
    applied) is finite and at most :data:`MAX_CANDELA`: huge factors or values must not make
    infinite or absurd intensities."""
    with np.errstate(over="ignore", invalid="ignore"):
        candela = values * factor
        ok = np.isfinite(factor) and bool(np.all(np.isfinite(candela)))
    if not ok:
        raise FileFormatError(
            f"{path}: candela values: the intensities times the file's factors ({factor:g}) "
            "overflow (not finite numbers)"
        )
    peak = float(np.max(candela, initial=0.0))
    if peak > MAX_CANDELA:
        raise FileFormatError(
            f"{path}: candela values: the intensities times the file's factors ({factor:g}) "
            f"reach {peak:.3g} cd, beyond any luminaire (at most {MAX_CANDELA:g} cd; a wrong "
            "candela multiplier?)"
        )


def _keywords(lines: list[str]) -> dict[str, str]:
    keywords: dict[str, str] = {}
    last = None
    for line in lines:
        m = _KEYWORD.match(line)
        if m is None:
            if line.strip():
                keywords["TEXT"] = _join(keywords.get("TEXT"), line.strip())
            continue
        name, value = m.group(1).strip().upper(), m.group(2).rstrip()
        if name == "MORE" and last is not None:
            keywords[last] = _join(keywords[last], value)
            continue
        keywords[name] = _join(keywords.get(name), value)
        last = name
    return keywords


def _join(old: str | None, new: str) -> str:
    return new if old is None else f"{old}\n{new}"


class _Tokens:
    """The numbers after TILT=, one field at a time, with messages naming the field."""

    def __init__(self, tokens: list[str], path: Path):
        self.tokens = [t for t in tokens if t]
        self.pos = 0
        self.path = path

    def _take(self, field: str, expected: int) -> str:
        if self.pos >= len(self.tokens):
            raise FileFormatError(
                f"{self.path}: {field}: the file ends early (truncated; {expected} more "
                "number(s) expected)"
            )
        self.pos += 1
        return self.tokens[self.pos - 1]

    def number(self, field: str) -> float:
        token = self._take(field, 1)
        try:
            value = float(token)
        except ValueError:
            raise FileFormatError(f"{self.path}: {field}: {token[:30]!r} is not a number") from None
        if not np.isfinite(value):
            raise FileFormatError(f"{self.path}: {field}: {token!r} is not a finite number")
        return value

    def integer(self, field: str, minimum: int | None = None) -> int:
        value = self.number(field)
        if value != int(value):
            raise FileFormatError(f"{self.path}: {field}: must be a whole number (got {value:g})")
        if minimum is not None and value < minimum:
            raise FileFormatError(f"{self.path}: {field}: must be >= {minimum} (got {value:g})")
        return int(value)

    def numbers(self, n: int, field: str) -> np.ndarray:
        left = len(self.tokens) - self.pos
        if n > left:  # before allocating: a corrupt count may be astronomically large
            raise FileFormatError(
                f"{self.path}: {field}: the file ends early (truncated: {count_text(n)} "
                f"expected, {left} found)"
            )
        out = np.empty(n)
        for k in range(n):
            if self.pos >= len(self.tokens):
                raise FileFormatError(
                    f"{self.path}: {field}: the file ends early (truncated: {n} expected, "
                    f"{k} found)"
                )
            out[k] = self.number(f"{field} (number {k + 1})")
        return out

    def expect_end(self, field: str, counts: str = "") -> None:
        extra = len(self.tokens) - self.pos
        if extra:
            said = f" the header's counts say {counts}," if counts else ""
            raise FileFormatError(
                f"{self.path}: {field}: wrong counts:{said} but {extra} more value(s) follow "
                f"({self.tokens[self.pos][:20]!r}...)"
            )


def _read_tilt(tokens: _Tokens) -> Tilt:
    geometry = tokens.integer("TILT lamp-to-luminaire geometry")
    if geometry not in (1, 2, 3):
        raise FileFormatError(
            f"{tokens.path}: TILT lamp-to-luminaire geometry: must be 1, 2 or 3 (got {geometry})"
        )
    n = tokens.integer("TILT number of angles", minimum=1)
    angles = tokens.numbers(n, "TILT angles")
    factors = tokens.numbers(n, "TILT multiplying factors")
    _check_increasing(tokens.path, "TILT angles", angles)
    if np.any(factors < 0):
        raise FileFormatError(f"{tokens.path}: TILT multiplying factors: negative factor")
    return Tilt(geometry, angles, factors)


def _check_increasing(path: Path, field: str, values: np.ndarray) -> None:
    if values.size > 1 and np.any(np.diff(values) <= 0):
        k = int(np.nonzero(np.diff(values) <= 0)[0][0])
        raise FileFormatError(
            f"{path}: {field}: must increase ({values[k]:g} then {values[k + 1]:g})"
        )


def _symmetry(path: Path, ptype: str, vertical: np.ndarray, horizontal: np.ndarray) -> str:
    first, last = horizontal[0], horizontal[-1]
    if ptype == "C":
        if vertical[0] < 0 or vertical[-1] > 180:
            raise FileFormatError(
                f"{path}: vertical angles: Type C angles must lie in 0..180 "
                f"(got {vertical[0]:g}..{vertical[-1]:g})"
            )
        if horizontal.size == 1:
            if first != 0:
                raise FileFormatError(
                    f"{path}: horizontal angles: a single angle must be 0 (got {first:g})"
                )
            return "rotational"
        if first == 0 and last == 90:
            return "quadrant"
        if first == 0 and last == 180:
            return "bilateral_0_180"
        if first == 90 and last == 270:
            return "bilateral_90_270"
        if first == 0 and 180 < last <= 360:
            return "none"
        raise FileFormatError(
            f"{path}: horizontal angles: Type C range {first:g}..{last:g} is none of 0 (one "
            "angle), 0-90, 0-180, 90-270, 0-360"
        )
    # Type B
    if vertical[0] < -180 or vertical[-1] > 180:
        raise FileFormatError(
            f"{path}: vertical angles: Type B angles must lie in -180..180 "
            f"(got {vertical[0]:g}..{vertical[-1]:g})"
        )
    if horizontal.size < 2 or first < -90 or last > 90 or first > 0:
        raise FileFormatError(
            f"{path}: horizontal angles: Type B needs at least two angles, from 0 or below "
            f"to at most 90 within -90..90 (got {first:g}..{last:g})"
        )
    mirror_h, mirror_v = first == 0, vertical[0] == 0
    return {(True, True): "quadrant", (True, False): "bilateral_0_180",
            (False, True): "bilateral_90_270", (False, False): "none"}[mirror_h, mirror_v]
