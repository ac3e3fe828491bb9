"""The Markdown report of a lighting study: ``spectrace lux ... --report OUT.md``.

One file a lighting designer can send: the luminaires (file, manufacturer, luminous flux,
count, maintenance factor), each calculation grid's results (E_m, E_min, E_max, U0,
E_min / E_max) with pass / fail against the task's requirements of EN 12464-1, the
plan-view figure, the luminance picture and the UGR. The figures are the PNG files
written beside the report (linked by relative paths).
"""

from __future__ import annotations

import os
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["Luminaire", "Study", "luminaires", "write_report"]


@dataclass(frozen=True)
class Luminaire:
    """One kind of light in the scene: its file (or plugin), manufacturer and flux (lm)."""

    source: str
    manufacturer: str
    flux: float | None  # lm, per light; None when the light has no photometric file


@dataclass
class Study:
    """What a report shows; any part may be missing."""

    scene: str
    variant: str
    luminaires: Counter = field(default_factory=Counter)  # Luminaire -> count
    maintenance_factor: float = 1.0
    grid: object = None  # grids.GridResult
    task: object = None  # grids.Task
    plan_png: Path | None = None
    luminance_png: Path | None = None
    glare: object = None  # glare.GlareResult
    points: tuple | None = None  # (count, csv path)
    glare_note: str | None = None


def luminaires(scene) -> Counter:
    """The scene's lights grouped: photometric files (``ieslight``) with their
    manufacturer keyword and flux as emitted (the file's, scaled), other lights by
    plugin."""
    found = Counter()
    for emitter in scene.emitters():
        photometry = getattr(emitter, "photometry", None)
        if photometry is not None:
            keywords = getattr(photometry, "keywords", {}) or {}
            flux = getattr(emitter, "luminous_flux", None)
            if flux is None:
                flux = float(photometry.flux) * float(emitter.scale_value[0])
            else:
                flux = float(flux[0])
            name = os.path.basename(str(getattr(emitter, "path", emitter.filename)))
            found[Luminaire(name, str(keywords.get("MANUFAC", "")), flux)] += 1
        else:
            name = getattr(emitter, "plugin_name", None) or emitter.class_name()
            found[Luminaire(name, "", None)] += 1
    return found


def _relative(path: Path, report: Path) -> str:
    return os.path.relpath(path, report.parent).replace(os.sep, "/")


def render_report(study: Study, report_path: Path) -> str:
    """The Markdown text of ``study``, with figure links relative to ``report_path``."""
    lines = [f"# Lighting report: {study.scene}", "",
             f"Computed by spectrace ({study.variant}); maintenance factor "
             f"MF = {study.maintenance_factor:g}. Illuminance of delta lights is exact "
             "(no random part); other values carry their standard error.", ""]
    lines += ["## Luminaires", "", "| file | manufacturer | flux (lm) | count | MF |",
              "|---|---|---:|---:|---:|"]
    for lum, count in sorted(study.luminaires.items(), key=lambda kv: kv[0].source):
        flux = "" if lum.flux is None else f"{lum.flux:.0f}"
        lines.append(f"| {lum.source} | {lum.manufacturer} | {flux} | {count} | "
                     f"{study.maintenance_factor:g} |")
    lines.append("")
    if study.grid is not None:
        g = study.grid
        s = g.stats
        rows, cols = g.grid.shape
        lines += ["## Calculation grid", "", g.grid.describe() + ".", "",
                  "| E_m (lx) | E_min (lx) | E_max (lx) | U0 = E_min/E_m | E_min/E_max |",
                  "|---:|---:|---:|---:|---:|",
                  f"| {s['E_m']:.1f} | {s['E_min']:.1f} | {s['E_max']:.1f} | {s['U0']:.2f} | "
                  f"{s['E_min/E_max']:.2f} |", ""]
        if study.task is not None:
            t = study.task
            checks = g.check(t)
            mark = {True: "pass", False: "**fail**"}
            lines += [f"Task: {t.description} (EN 12464-1:2021): E_m >= {t.E_m:g} lx: "
                      f"{mark[checks['E_m']]}; U0 >= {t.U0:.2f}: {mark[checks['U0']]}."]
            if study.glare is not None and study.glare.UGR is not None:
                ok = study.glare.UGR <= t.UGR_L
                lines[-1] += f" UGR <= {t.UGR_L:g}: {mark[ok]}."
            lines.append("")
        if study.plan_png is not None:
            lines += [f"![plan view of the grid]({_relative(study.plan_png, report_path)})",
                      ""]
    if study.points is not None:
        count, path = study.points
        lines += ["## Sensor points", "",
                  f"{count} points: [{path.name}]({_relative(path, report_path)}).", ""]
    if study.luminance_png is not None or study.glare is not None:
        lines += ["## Luminance and glare", ""]
        if study.luminance_png is not None:
            lines += [f"![luminance (cd/m^2)]({_relative(study.luminance_png, report_path)})",
                      ""]
        if study.glare is not None:
            lines += [study.glare.summary() + " (observer at the camera, line of sight "
                      "through the picture's centre).", ""]
            if study.glare_note:
                lines += [f"Note: {study.glare_note}.", ""]
    return "\n".join(lines)


def write_report(path, study: Study) -> None:
    """Write the report of ``study`` to ``path`` (Markdown); atomic."""
    from spectrace.images import atomic_path

    path = Path(path)
    text = render_report(study, path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
