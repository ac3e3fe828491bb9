"""Make the README's gallery: small PNGs of every scene and of the studies' key figures.

``make gallery`` first renders every scene of ``scenes/`` at its default settings with
``spectrace render`` into ``out/gallery/``, then runs this script, which

* shrinks each rendered PNG to ``--width`` pixels (Lanczos, sRGB 8 bits as written by
  ``spectrace render``) into ``OUT/scenes/<scene>.png``; the scenes of :data:`PAIRS` show
  two renders side by side (shadow_acne at bias 0 and 0.01), those of
  :data:`GRID_LABELS` get their rows and columns labelled (phong_vs_energy);
* executes every notebook of ``notebooks/`` at full size (``SPECTRACE_QUICK`` unset) in
  a kernel running this Python, with ``SPECTRACE_GALLERY=OUT/studies``, so that each
  notebook saves its key figures there (``spectrace.studies.save_figure``); the executed
  notebooks themselves are not kept (they are committed without outputs).

Figures are reduced to a 256-colour palette, which keeps them sharp and small; renders
keep their full colour. Usage::

    python docs/make_gallery.py --renders out/gallery --out docs/gallery
    python docs/make_gallery.py --renders out/gallery --out docs/gallery --no-notebooks
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
#: Width of a scene thumbnail (pixels).
SCENE_WIDTH = 320
#: Seconds a notebook cell may run at full size.
CELL_TIMEOUT = 3600
KERNEL_NAME = "spectrace-gallery"


#: Scenes whose thumbnail is two renders side by side: scene -> (the second render's PNG
#: stem, the label of the first, the label of the second). ``make gallery`` renders both.
PAIRS = {"shadow_acne": ("shadow_acne_biased", "shadow_bias = 0", "shadow_bias = 0.01")}
#: Labels of a scene's grid: scene -> (row labels top to bottom, column labels).
GRID_LABELS = {
    "phong_vs_energy": (("phong", "phong norm.", "blinnphong n.", "roughplastic"),
                        ("m=2", "m=8", "m=32", "m=128")),
}
LABEL_PX = 14  # height of a label strip (pixels)


def side_by_side(left: Path, right: Path, target: Path, width: int, labels) -> None:
    """The two renders side by side, each ``width / 2`` wide, a label above each."""
    from PIL import Image, ImageDraw

    half = max(1, width // 2)
    with Image.open(left) as a, Image.open(right) as b:
        a, b = (im.convert("RGB") for im in (a, b))
        height = max(1, round(a.height * half / a.width))
        a, b = (im.resize((half, height), Image.Resampling.LANCZOS) for im in (a, b))
    sheet = Image.new("RGB", (2 * half, height + LABEL_PX), "white")
    draw = ImageDraw.Draw(sheet)
    for i, (image, label) in enumerate(zip((a, b), labels, strict=True)):
        sheet.paste(image, (i * half, LABEL_PX))
        draw.text((i * half + 4, 1), label, fill="black")
    sheet.save(target, optimize=True)


def label_grid(target: Path, rows, columns) -> None:
    """Label a thumbnail of an evenly spaced grid in place: columns above, rows on the left."""
    from PIL import Image, ImageDraw

    margin = 6 * max(len(r) for r in rows) + 6
    with Image.open(target) as image:
        image = image.convert("RGB")
    sheet = Image.new("RGB", (image.width + margin, image.height + LABEL_PX), "white")
    sheet.paste(image, (margin, LABEL_PX))
    draw = ImageDraw.Draw(sheet)
    for j, label in enumerate(columns):
        draw.text((margin + (j + 0.3) * image.width / len(columns), 1), label, fill="black")
    for i, label in enumerate(rows):
        draw.text((2, LABEL_PX + (i + 0.45) * image.height / len(rows)), label, fill="black")
    sheet.save(target, optimize=True)


def shrink(source: Path, target: Path, width: int) -> None:
    """Write ``source`` scaled to ``width`` pixels wide (aspect kept) as an optimized PNG."""
    from PIL import Image

    with Image.open(source) as image:
        image = image.convert("RGB")
        if image.width > width:
            height = max(1, round(image.height * width / image.width))
            image = image.resize((width, height), Image.Resampling.LANCZOS)
        image.save(target, optimize=True)


def palette(path: Path) -> None:
    """Reduce a figure PNG to 256 colours in place (plots have few colours)."""
    from PIL import Image

    with Image.open(path) as image:
        reduced = image.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    reduced.save(path, optimize=True)


def run_notebook(path: Path, figures: Path) -> None:
    """Execute ``path`` at full size in a kernel of this Python; figures go to ``figures``."""
    import nbclient
    import nbformat
    from jupyter_client.kernelspec import KernelSpecManager
    from jupyter_client.manager import KernelManager

    with tempfile.TemporaryDirectory() as tmp:
        spec_dir = Path(tmp) / "kernels" / KERNEL_NAME
        spec_dir.mkdir(parents=True)
        (spec_dir / "kernel.json").write_text(json.dumps({
            "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            "display_name": "spectrace gallery kernel",
            "language": "python",
        }))
        env = {"SPECTRACE_GALLERY": str(figures.resolve()),
               "MPLBACKEND": "module://matplotlib_inline.backend_inline",
               "JUPYTER_RUNTIME_DIR": str(Path(tmp) / "runtime"),
               "IPYTHONDIR": str(Path(tmp) / "ipython")}
        saved = {k: os.environ.get(k) for k in [*env, "SPECTRACE_QUICK"]}
        os.environ.update(env)
        os.environ.pop("SPECTRACE_QUICK", None)  # full size
        try:
            ksm = KernelSpecManager(kernel_dirs=[str(Path(tmp) / "kernels")],
                                    ensure_native_kernel=False)
            km = KernelManager(kernel_name=KERNEL_NAME, kernel_spec_manager=ksm)
            nb = nbformat.read(path, as_version=4)
            nbclient.NotebookClient(nb, km=km, timeout=CELL_TIMEOUT,
                                    resources={"metadata": {"path": str(path.parent)}}).execute()
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--renders", type=Path, default=ROOT / "out" / "gallery",
                        help="folder of the PNGs written by spectrace render")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "gallery")
    parser.add_argument("--width", type=int, default=SCENE_WIDTH,
                        help=f"scene thumbnail width in pixels (default {SCENE_WIDTH})")
    parser.add_argument("--no-notebooks", action="store_true",
                        help="only the scene thumbnails")
    args = parser.parse_args(argv)

    scenes_out, figures_out = args.out / "scenes", args.out / "studies"
    scenes_out.mkdir(parents=True, exist_ok=True)
    figures_out.mkdir(parents=True, exist_ok=True)
    renders = sorted(args.renders.glob("*.png"))
    if not renders:
        print(f"error: no PNG in {args.renders} (run `make gallery`)", file=sys.stderr)
        return 2
    seconds = {second for second, _, _ in PAIRS.values()}
    for png in renders:
        if png.stem in seconds:
            continue  # shown beside its first render
        target = scenes_out / png.name
        pair = PAIRS.get(png.stem)
        if pair is not None and (png.parent / f"{pair[0]}.png").is_file():
            side_by_side(png, png.parent / f"{pair[0]}.png", target, args.width, pair[1:])
        else:
            shrink(png, target, args.width)
        if png.stem in GRID_LABELS:
            label_grid(target, *GRID_LABELS[png.stem])
        print(f"{target}")
    if not args.no_notebooks:
        for notebook in sorted(NOTEBOOKS.glob("*.ipynb")):
            print(f"running {notebook.name} at full size ...", flush=True)
            run_notebook(notebook, figures_out)
        for figure in sorted(figures_out.glob("*.png")):
            palette(figure)
            print(f"{figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
