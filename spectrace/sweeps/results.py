"""A sweep's results as xarray objects on the grid's coordinates, and ``results.csv``.

:func:`to_dataset` holds a row per image (``spp``, ``file``, ``seconds``,
``mean_luminance``) on the grid's coordinates; ``results.csv`` is its
``to_dataframe()`` (a column per swept parameter, ``variant``, ``seed``, then those four),
a row per finished image in grid order. :func:`to_dataarray` holds the images themselves.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from spectrace.errors import ParameterError
from spectrace.sweeps.files import RESULTS
from spectrace.sweeps.grid import COLUMNS, Grid, Outcome


def mean_luminance(rgb: np.ndarray) -> float:
    """Mean of Y = 0.2126 R + 0.7152 G + 0.0722 B over the image (linear sRGB)."""
    from spectrace.comparison import LUMINANCE_WEIGHTS

    return float(np.mean(np.asarray(rgb[..., :3], np.float64) @ LUMINANCE_WEIGHTS))


def to_dataset(grid: Grid, outcomes: Sequence[Outcome]):
    """The per-image values on the grid's coordinates: ``spp``, ``file``, ``seconds``,
    ``mean_luminance`` (NaN, or None for ``file``, where no image was finished)."""
    import xarray as xr

    def column(get, dtype, missing):
        values = [get(o) if o.done else missing for o in outcomes]
        return grid.dims, grid.array(values, dtype)

    nan = float("nan")
    return xr.Dataset(
        {"spp": column(lambda o: o.spp, float, nan),
         "file": column(lambda o: o.file, object, None),
         "seconds": column(lambda o: o.seconds, float, nan),
         "mean_luminance": column(lambda o: o.mean_luminance, float, nan)},
        coords=grid.coords())


def results_table(grid: Grid, outcomes: Sequence[Outcome]):
    """``results.csv`` as a pandas DataFrame: a row per finished image, in grid order."""
    ds = to_dataset(grid, outcomes)
    frame = (ds if ds.sizes else ds.expand_dims("image")).to_dataframe().reset_index()
    frame = frame[[*grid.axes, *COLUMNS]]
    frame = frame[frame["file"].notna()].astype({"spp": int})
    return frame.reset_index(drop=True)


def write_results(outdir, grid: Grid, outcomes: Sequence[Outcome]) -> Path:
    """Write ``OUTDIR/results.csv`` (atomically): seconds to 0.1 ms, luminance to 6 digits."""
    from spectrace.images import atomic_path

    frame = results_table(grid, outcomes)
    frame["seconds"] = frame["seconds"].map("{:.4f}".format)
    frame["mean_luminance"] = frame["mean_luminance"].map("{:.6g}".format)
    path = Path(outdir) / RESULTS
    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False, lineterminator="\n")
    return path


def to_dataarray(grid: Grid, outcomes: Sequence[Outcome]):
    """The images as an ``xarray.DataArray``: dims :attr:`Grid.dims` + y, x, channel;
    an axis of one value (parameter, variant or seed) is a scalar coordinate.

    Attributes: ``spp`` (one value, or a list per image in grid order), ``scene``,
    ``failed`` (labels and errors of failed images, which are NaN).
    """
    import xarray as xr

    images = [o.image for o in outcomes if o.image is not None]
    if not images:
        raise ParameterError("sweep: no image was rendered: "
                             + "; ".join(f"{o.combo.label()}: {o.error}" for o in outcomes))
    h, w, c = images[0].shape
    data = np.full((len(outcomes), h, w, c), np.nan, np.float32)
    for i, o in enumerate(outcomes):
        if o.image is not None:
            if o.image.shape != (h, w, c):
                raise ParameterError(
                    f"sweep: image {o.combo.label()} is {o.image.shape[1]}x"
                    f"{o.image.shape[0]}, the first was {w}x{h}: a DataArray needs equal "
                    "sizes (give outdir and read the files instead)")
            data[i] = o.image
    spps = sorted({o.spp for o in outcomes if o.spp is not None})
    attrs = {"spp": spps[0] if len(spps) == 1 else [o.spp for o in outcomes],
             "scene": str(grid.scene),
             "failed": [f"{o.combo.label()}: {o.error}" for o in outcomes
                        if o.status == "failed"]}
    return xr.DataArray(data.reshape(*grid.shape, h, w, c),
                        dims=[*grid.dims, "y", "x", "channel"],
                        coords={**grid.coords(), "channel": ["R", "G", "B"][:c]},
                        attrs=attrs, name=grid.scene.stem)
