"""The contact sheet of a sweep (``sheet.png``): xarray's faceted ``imshow`` of the images.

A column per value of the grid's last dimension, a row per combination of the others
(several leading dimensions share the row axis, labelled ``a, b = 1, x``), each labelled by
xarray's facet titles. Images are shown sRGB-encoded, fitted into cells of about
:data:`SHEET_CELL` pixels (sizes may differ between images: a ``res`` sweep); a failed or
missing image is a grey cell marked "failed" or "-".
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from spectrace.sweeps.grid import Grid, Outcome

#: Size in pixels of an image's cell in the contact sheet.
SHEET_CELL = 160
_DPI = 100
_GREY = 0.78
_FONT_SIZE = 7


def thumbnail(rgb: np.ndarray, size: int = SHEET_CELL) -> np.ndarray:
    """Every k-th pixel of ``rgb``: at most about ``size`` pixels on its longer side."""
    step = max(1, max(rgb.shape[:2]) // size)
    return rgb[::step, ::step]


def _fit(encoded: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``encoded`` (H, W, 3) scaled (nearest pixel) to fit ``shape``, centred on grey."""
    h, w = encoded.shape[:2]
    scale = min(shape[0] / h, shape[1] / w)
    fh, fw = max(1, round(h * scale)), max(1, round(w * scale))
    rows = np.minimum((np.arange(fh) / scale).astype(int), h - 1)
    cols = np.minimum((np.arange(fw) / scale).astype(int), w - 1)
    cell = np.full((*shape, 3), _GREY, np.float32)
    top, left = (shape[0] - fh) // 2, (shape[1] - fw) // 2
    cell[top:top + fh, left:left + fw] = encoded[rows][:, cols]
    return cell


def sheet_array(grid: Grid, outcomes: Sequence[Outcome]):
    """The images as one DataArray of encoded sRGB cells of equal size on the grid's
    coordinates (NaN where there is no image)."""
    import xarray as xr

    from spectrace.images import encode_srgb_8bit

    shapes = [o.image.shape[:2] for o in outcomes if o.image is not None] or [(1, 1)]
    h, w = max(s[0] for s in shapes), max(s[1] for s in shapes)
    scale = SHEET_CELL / max(h, w)
    shape = (max(1, round(h * scale)), max(1, round(w * scale)))
    cells = np.full((len(outcomes), *shape, 3), np.nan, np.float32)
    for i, o in enumerate(outcomes):
        if o.image is not None:
            cells[i] = _fit(encode_srgb_8bit(o.image) / 255.0, shape)
    return xr.DataArray(cells.reshape(*grid.shape, *shape, 3),
                        dims=[*grid.dims, "y", "x", "channel"], coords=grid.coords())


def _mark(o: Outcome) -> str:
    if o.image is not None:
        return ""
    return "failed" if o.status == "failed" else "-"


def _rows_as_one(da, dims: list[str]):
    """``da`` with ``dims`` stacked into one dimension named ``"a, b"`` whose labels are
    ``"1, x"`` (faceting takes one row dimension)."""
    name = ", ".join(dims)
    stacked = da.stack({name: dims})
    labels = [", ".join(str(v) for v in key) for key in stacked.indexes[name]]
    return stacked.drop_vars([name, *dims]).assign_coords({name: labels})


def write_sheet(path, grid: Grid, outcomes: Sequence[Outcome]) -> Path:
    """Write the contact sheet PNG (atomically); see the module docstring."""
    import sys

    import matplotlib

    if "matplotlib.pyplot" not in sys.modules:  # a notebook keeps its backend
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import xarray as xr

    from spectrace.images import atomic_path

    da = sheet_array(grid, outcomes).fillna(_GREY)
    marks = xr.DataArray(grid.array([_mark(o) for o in outcomes]), dims=grid.dims,
                         coords=grid.coords())
    dims = grid.dims
    facets = {"col": dims[-1]} if dims else {}
    if len(dims) == 2:
        facets["row"] = dims[0]
    elif len(dims) > 2:
        da, marks = (_rows_as_one(a, dims[:-1]) for a in (da, marks))
        facets["row"] = ", ".join(dims[:-1])
    cell_h, cell_w = da.sizes["y"], da.sizes["x"]
    style = {"rgb": "channel", "interpolation": "nearest", "add_labels": False}
    with plt.rc_context({"font.size": _FONT_SIZE, "axes.titlesize": _FONT_SIZE}):
        if facets:
            g = da.plot.imshow(size=cell_h / _DPI + 0.3, aspect=cell_w / cell_h, **facets,
                               **style)
            fig, cells = g.fig, zip(g.axs.flat, g.name_dicts.flat, strict=True)
        else:
            fig, ax = plt.subplots(figsize=(cell_w / _DPI + 0.3, cell_h / _DPI + 0.5))
            da.plot.imshow(ax=ax, **style)
            ax.set_title(outcomes[0].combo.label() if outcomes else "")
            cells = [(ax, {})]
        for ax, names in cells:
            ax.set(xticks=[], yticks=[], xlabel="", ylabel="")
            mark = marks.sel(names).item() if names is not None else ""
            if mark:
                ax.text(0.5, 0.5, mark, color=(0.7, 0, 0), ha="center", va="center",
                        transform=ax.transAxes)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=_DPI)
        plt.close(fig)
    return Path(path)
