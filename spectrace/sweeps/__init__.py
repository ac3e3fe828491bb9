"""Parameter sweeps: the Cartesian product of a scene's ``<default>`` values, on Dask.

* :mod:`~spectrace.sweeps.grid`: the grid (its axes are the xarray coordinates) and its
  combinations;
* :mod:`~spectrace.sweeps.files`: file names, the EXR + PNG of an image, resuming;
* :mod:`~spectrace.sweeps.run`: one Dask task per image (:func:`run`);
* :mod:`~spectrace.sweeps.dimming`: a sweep of light intensities relit from one render;
* :mod:`~spectrace.sweeps.results`: the images and ``results.csv`` as xarray objects;
* :mod:`~spectrace.sweeps.sheet`: the contact sheet, xarray's faceted ``imshow``.

``spectrace.sweep(scene, params={...})`` is :func:`sweep`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from spectrace.sweeps.dimming import dimming_plan
from spectrace.sweeps.files import RESULTS, SHEET, check_outdir, plan, stem
from spectrace.sweeps.grid import Combination, Grid, Outcome
from spectrace.sweeps.results import results_table, to_dataarray, to_dataset, write_results
from spectrace.sweeps.run import run
from spectrace.sweeps.sheet import write_sheet

__all__ = ["RESULTS", "SHEET", "Combination", "Grid", "Outcome", "check_outdir", "dimming_plan",
           "plan",
           "results_table", "run", "stem", "sweep", "to_dataarray", "to_dataset",
           "write_results", "write_sheet"]


def sweep(scene, params: Mapping[str, Sequence | str | float], variants=None, seeds=None,
          spp: int | None = None, client=None, *, outdir=None, spp_per_pass: int | None = None,
          workers: int | None = None, scheduler: str | None = None):
    """Render the Cartesian product of ``params`` (``<default>`` name -> values) of ``scene``.

    Returns an ``xarray.DataArray`` (see :func:`to_dataarray`): dims the axes of several
    values among the swept parameters, ``variant`` and ``seed`` (in that order), then y, x,
    channel (linear sRGB); an axis of one value is a scalar coordinate. Coordinates keep
    the values' types (``da.sel(max_depth=4)``). ``client``: a ``distributed.Client`` to
    use; None starts a LocalCluster of ``workers`` processes (or joins ``scheduler``) for
    this call. ``outdir``: also keep the files of ``spectrace sweep`` there (resumable);
    default a temporary folder. A failed combination is NaN, its label and error in
    ``attrs["failed"]``.
    """
    import contextlib
    import tempfile

    from spectrace.cluster import connect

    grid = Grid.make(scene, params, variants, seeds, spp, spp_per_pass)
    with contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(connect(workers, scheduler, variant=grid.variants[0]))
        if outdir is None:
            outdir = stack.enter_context(tempfile.TemporaryDirectory(prefix="spectrace-sweep-"))
        outcomes = run(grid, client, outdir)
    return to_dataarray(grid, outcomes)
