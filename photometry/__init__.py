"""Photometric files: IES LM-63 (1986 to 2019) and EULUMDAT (.ldt) luminaire data.

:func:`read_photometry` reads either format into a :class:`Photometry`: the intensity
table in candela (every factor of the file applied), its symmetry, and what follows from
it (``intensity(gamma, c)``, ``flux``, ``max_candela``, ``peak_direction``, ``beam_angle``,
``field_angle``, ``type_c_grid()``). The angle conventions (Type C and Type B) are in
:mod:`spectrace.photometry.model`, the format details in :mod:`spectrace.photometry.ies`
and :mod:`spectrace.photometry.eulumdat`; :mod:`spectrace.photometry.generate` writes
files of either format from an analytic or tabulated distribution.

Why our own reader (numpy only): no library fits. luxpy's IES/LDT reader is GPL-3 (this
project is BSD-3-Clause) and handles neither ``TILT=INCLUDE`` nor Type B photometry;
colour-science has no photometric-file reader.

References: ANSI/IES LM-63-2019 (and its 1986, 1991, 1995, 2002 editions), IES LM-75-19
(goniometer types and photometric coordinates), CIE 121-1996 (photometry of luminaires),
A. Stockmar, "EULUMDAT/2" (1990, the EULUMDAT layout).
"""

from __future__ import annotations

from pathlib import Path

from spectrace.errors import FileAccessError, FileFormatError

from .model import Photometry, Tilt, type_b_to_c, type_c_to_b

__all__ = ["Photometry", "Tilt", "read_photometry", "type_b_to_c", "type_c_to_b"]


def read_photometry(path) -> Photometry:
    """Read an IES LM-63 (.ies) or EULUMDAT (.ldt) file.

    The format is told by the content: an LM-63 file has a ``TILT=`` line; otherwise a
    ``.ldt`` name means EULUMDAT. A missing, unreadable or malformed file raises
    :class:`~spectrace.errors.SpectraceError` with one line naming the file and the field.
    """
    from . import eulumdat, ies

    path = Path(path)
    try:
        data = ies.read_file(path)
    except OSError as e:
        raise FileAccessError(f"{path}: cannot read photometric file: {e.strerror or e}") from None
    text = ies.decode(data)
    if not text.strip():
        raise FileFormatError(f"{path}: empty file (not an IES or EULUMDAT photometric file)")
    if ies.is_ies(text):
        return ies.parse_ies(path, text)
    if path.suffix.lower() == ".ldt":
        return eulumdat.parse_ldt(path, text)
    if path.suffix.lower() == ".ies":
        return ies.parse_ies(path, text)  # names what is missing
    raise FileFormatError(
        f"{path}: unknown format: neither an IES LM-63 file (no TILT= line) nor a .ldt file"
    )
