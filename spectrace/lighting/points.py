"""Illuminance at sensor points, as ``rtrace -I`` computes it: ``spectrace lux --points``.

:func:`measure_points` evaluates the ``illuminance`` integrator's measurement
(:meth:`Illuminance.measure <spectrace.plugins.integrators.illuminance.Illuminance.measure>`)
directly at the given points with Dr.Jit, no camera: each point is a surface interaction
at its position with its normal, the lights are reached by their ``sample_direction`` and
one ``scene.ray_test`` shadow ray each (the point is where it is measured, not a pixel's
footprint). Delta lights are exact, so a scene of delta lights and ``max_depth`` 1 takes
one sample per point and has standard error 0; otherwise ``spp`` independent samples per
point give the mean and its standard error sqrt(s^2 / n) (s^2 the sample variance).

Kinds (``kind``, see ``spectrace help illuminance``): ``planar`` on a plane of the given
normal (horizontal: 0, 1, 0; vertical: a horizontal normal), ``cylindrical`` E_z (the
normal is not used) and ``semicylindrical`` E_sc facing the horizontal part of the normal.

CSV files (:func:`read_points_csv`, :func:`write_points_csv`): one point a line,
``x,y,z,nx,ny,nz`` in metres (a header line allowed, ``#`` comments skipped), written back
with the columns ``x,y,z,nx,ny,nz,lux,stderr`` (DESIGN.md); luminance points use the same
six columns with a view direction ``dx,dy,dz`` and are written as
``x,y,z,dx,dy,dz,luminance,stderr`` (cd/m^2).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np

from spectrace.errors import FileAccessError, FileFormatError, ParameterError

__all__ = ["INPUT_COLUMNS", "OUTPUT_COLUMNS", "measure_points", "read_points_csv",
           "write_points_csv", "sample_statistics"]

#: The columns of a points file, and those written back.
INPUT_COLUMNS = ("x", "y", "z", "nx", "ny", "nz")
OUTPUT_COLUMNS = INPUT_COLUMNS + ("lux", "stderr")
#: Luminance points: a view direction instead of a normal.
LUMINANCE_COLUMNS = ("x", "y", "z", "dx", "dy", "dz", "luminance", "stderr")
#: At most this many lanes (points x samples) per Dr.Jit evaluation.
MAX_LANES = 1 << 21
#: Significant digits written to CSV files (float32 results).
CSV_DIGITS = 9


def read_points_csv(path) -> tuple[np.ndarray, np.ndarray]:
    """(points (N, 3), vectors (N, 3)) of a points file (see the module docstring).
    FileFormatError naming the file and line when a line has not six finite numbers;
    FileAccessError when it cannot be read."""
    points, vectors, _ = read_points_table(path)
    return points, vectors


def read_points_table(path) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """As :func:`read_points_csv`, with the text of each point's line (comments and
    blanks stripped), which :func:`write_points_csv` can write back as it was."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as e:
        raise FileAccessError(f"cannot read points file {path}: {e.strerror or e}") from None
    plain = _read_plain(text)
    if plain is not None:
        data, rows = plain
        return data[:, :3], data[:, 3:], rows
    lines = text.splitlines()
    first = _first_data_line(lines)
    header = first > 0 and not _is_numeric_row(lines[first - 1])
    try:  # numpy's parser
        with warnings.catch_warnings():  # an empty file: "input contained no data"
            warnings.simplefilter("ignore", UserWarning)
            data = np.loadtxt(lines[first:] if header else lines, delimiter=",",
                              comments="#", ndmin=2, dtype=np.float64)
        fast = data.shape[1] == len(INPUT_COLUMNS) and bool(np.all(np.isfinite(data)))
    except ValueError:
        fast = False
    if not fast:  # find the line at fault
        _check_lines(path, lines, first if header else 0)
    if data.size == 0:
        raise FileFormatError(f"{path}: no points (one line x,y,z,nx,ny,nz per point)")
    body = lines[first if header else 0:]
    rows = [r.replace(" ", "").replace("\t", "")
            for r in (line.split("#", 1)[0].strip() for line in body) if r]
    return data[:, :3], data[:, 3:], rows


def _read_plain(text: str):
    """The points of a file without comments, tabs or blank lines inside (an optional
    header line, then one ``x,y,z,nx,ny,nz`` line per point), as (an (N, 6) array, the
    text of each line); None for any other file, which the general reader then reads
    (and names the line at fault). The common case in one pass of numpy's parser, with no
    Python loop per line (a 512 x 512 grid: about 0.1 s)."""
    if "#" in text or "\t" in text or "\r" in text:
        return None
    head, _, body = text.partition("\n")
    if not _is_numeric_row(head):
        text = body
    rows = text.replace(" ", "").split("\n")
    if rows and not rows[-1]:
        rows.pop()  # the file's last newline
    if not rows or not all(rows):
        return None
    try:
        data = np.loadtxt(rows, delimiter=",", ndmin=2, dtype=np.float64)
    except ValueError:
        return None
    if data.shape != (len(rows), len(INPUT_COLUMNS)) or not np.all(np.isfinite(data)):
        return None
    return data, rows


def _is_numeric_row(line: str) -> bool:
    try:
        [float(c) for c in line.split("#", 1)[0].split(",")]
    except ValueError:
        return False
    return True


def _check_lines(path, lines: list[str], start: int) -> None:
    """FileFormatError for the first line (after ``start``) without six finite numbers."""
    rows = 0
    for number, line in enumerate(lines[start:], start=start + 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        cells = [c.strip() for c in line.split(",")]
        try:
            values = [float(c) for c in cells]
        except ValueError:
            raise FileFormatError(f"{path}, line {number}: expected six numbers "
                                  f"{','.join(INPUT_COLUMNS)} (got {line!r})") from None
        if len(values) != len(INPUT_COLUMNS) or not all(math.isfinite(v) for v in values):
            raise FileFormatError(f"{path}, line {number}: expected six finite numbers "
                                  f"{','.join(INPUT_COLUMNS)} (got {len(values)}: {line!r})")
        rows += 1
    if rows == 0:
        raise FileFormatError(f"{path}: no points (one line x,y,z,nx,ny,nz per point)")
    raise FileFormatError(f"{path}: cannot read the points (one line x,y,z,nx,ny,nz per "
                          "point)")


def _first_data_line(lines: list[str]) -> int:
    """The number of the first line that is neither empty nor a comment (0: none)."""
    for number, line in enumerate(lines, start=1):
        if line.split("#", 1)[0].strip():
            return number
    return 0


def write_points_csv(path, points, vectors, values, stderr, columns=OUTPUT_COLUMNS,
                     rows: list[str] | None = None) -> None:
    """Write one row per point: the six input columns (the input's own text ``rows``
    when given, from :func:`read_points_table`), the value and its standard error, under
    a header of ``columns``; atomic."""
    from spectrace.images import atomic_path

    if rows is None:
        data = np.column_stack([np.asarray(points, np.float64),
                                np.asarray(vectors, np.float64),
                                np.asarray(values, np.float64), np.asarray(stderr, np.float64)])
        write_csv(path, columns, data)
        return
    if len(rows) != len(values):
        raise ParameterError(f"{len(rows)} rows of text for {len(values)} values")
    fmt = f"%.{CSV_DIGITS}g"
    stderr = np.asarray(stderr, np.float64)
    exact = not np.any(stderr)  # every error 0 (exact lights): written as it reads, 0
    per_row = 2 if exact else 3
    cells = [None] * (per_row * len(rows))  # row, value, [error,] row, ...: one % in all
    cells[0::per_row] = rows
    cells[1::per_row] = np.asarray(values, np.float64).tolist()
    if not exact:
        cells[2::per_row] = stderr.tolist()
    line = f"%s,{fmt},0\n" if exact else f"%s,{fmt},{fmt}\n"
    with atomic_path(path) as tmp, open(tmp, "w") as f:
        f.write(",".join(columns) + "\n")
        f.write((line * len(rows)) % tuple(cells))


def write_csv(path, columns, data: np.ndarray) -> None:
    """A header of ``columns`` and one row per row of ``data`` (CSV_DIGITS significant
    digits); atomic."""
    from spectrace.images import atomic_path

    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, fmt=f"%.{CSV_DIGITS}g", delimiter=",", header=",".join(columns),
                   comments="")


def check_vectors(vectors: np.ndarray, kind: str, what: str = "normals") -> np.ndarray:
    """Unit vectors of ``vectors`` (N, 3); ParameterError when one is zero (or, for
    ``semicylindrical``, vertical: it has no horizontal facing direction)."""
    from spectrace.plugins.integrators.illuminance import ILLUMINANCE_KINDS, UP

    if kind not in ILLUMINANCE_KINDS:
        raise ParameterError(f"kind {kind!r}: expected one of {', '.join(ILLUMINANCE_KINDS)}")
    v = np.asarray(vectors, dtype=np.float64)
    length = np.linalg.norm(v, axis=-1)
    if kind == "planar" and not np.all(length > 0.0):
        i = int(np.argmin(length))
        raise ParameterError(f"{what}: point {i + 1} has a zero normal")
    if kind == "semicylindrical":
        horizontal = v - np.outer(v @ np.asarray(UP), UP)
        if not np.all(np.linalg.norm(horizontal, axis=-1) > 1e-6 * np.maximum(length, 1e-30)):
            raise ParameterError(f"{what}: semicylindrical illuminance needs a horizontal "
                                 "facing direction at every point (a vertical one has none)")
    return v / np.where(length > 0.0, length, 1.0)[:, None]


def sample_statistics(total, total_sq, n: int, exact: bool):
    """(mean, standard error of the mean) from sums over n samples; the error is 0 when
    ``exact``, NaN with one random sample."""
    mean = total / n
    if exact:
        return mean, np.zeros_like(mean)
    if n < 2:
        return mean, np.full_like(mean, np.nan)
    var = np.maximum(total_sq - n * mean**2, 0.0) / (n - 1)
    return mean, np.sqrt(var / n)


def pass_seed(seed: int, index: int) -> int:
    """The sampler seed of pass ``index`` of a measurement of ``seed``."""
    return (int(seed) * 1_000_003 + index) & 0xFFFFFFFF


def measure_points(scene, points, normals, *, kind: str = "planar", spp: int = 64,
                   seed: int = 0, max_depth: int = 1, shadows: bool = True,
                   integrator=None):
    """Illuminance (lux) at ``points`` (N, 3) with ``normals`` (N, 3) (facing directions
    for ``semicylindrical``; ignored for ``cylindrical``) in the loaded ``scene``.

    Returns (lux, stderr, samples): arrays (N,) and the samples per point taken: 1 when
    the measurement is exact (every light exact, ``max_depth`` 1), else ``spp``.
    ParameterError for a bad ``kind``, ``spp`` or normal.
    """
    import drjit as dr
    import mitsuba as mi

    from spectrace.lux import illuminance_integrator
    from spectrace.plugins.arrays import host_array
    from spectrace.plugins.integrators.illuminance import point_interaction

    if isinstance(spp, bool) or not isinstance(spp, int) or spp < 1:
        raise ParameterError(f"spp must be a positive integer (got {spp!r})")
    if kind != "planar" and max_depth != 1:
        raise ParameterError(f"kind {kind!r} measures direct light only (max_depth 1, got "
                             f"{max_depth})")
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n_vec = check_vectors(np.asarray(normals).reshape(-1, 3), kind)
    if integrator is None:
        integrator = illuminance_integrator(None, max_depth, shadows)
    exact = integrator.is_exact(scene)
    samples = 1 if exact else spp
    count = len(p)
    per_pass = max(1, min(samples, MAX_LANES // max(count, 1)))
    total = np.zeros(count)
    total_sq = np.zeros(count)
    sampler = mi.load_dict({"type": "independent"})
    done = 0
    while done < samples:
        k = min(per_pass, samples - done)
        width = count * k
        sampler.seed(pass_seed(seed, done), width)
        # padded host arrays: Dr.Jit's kernels read whole packets (see host_array)
        pos = mi.Point3f(*(mi.Float(host_array(np.tile(p[:, i], k))) for i in range(3)))
        nrm = mi.Vector3f(*(mi.Float(host_array(np.tile(n_vec[:, i], k))) for i in range(3)))
        active = dr.full(mi.Bool, True, width)
        wavelengths = integrator.wavelengths(sampler, active)
        it = point_interaction(pos, nrm, 0.0, wavelengths if mi.is_spectral else None)
        lux = integrator.measure(scene, sampler, it, nrm, active, kind)
        values = np.asarray(lux, dtype=np.float64).reshape(k, count)
        values = np.where(np.isfinite(values), values, 0.0)
        total += values.sum(axis=0)
        total_sq += (values**2).sum(axis=0)
        done += k
    mean, stderr = sample_statistics(total, total_sq, samples, exact)
    return mean, stderr, samples
