"""The validation table (text) and ``report.md`` with a figure per case."""

from __future__ import annotations

import datetime
from pathlib import Path

import numpy as np

from spectrace.validation.cases import FAMILIES, NOISE_SIGMAS, Result

COLUMNS = ("family", "case", "quantity", "points", "reference", "spectrace", "max rel",
           "mean rel", "tolerance", "pass")


def _number(x: float) -> str:
    return f"{x:.4g}"


def rows(results: list[Result]) -> list[tuple[str, ...]]:
    """One row of :data:`COLUMNS` per case; reference and spectrace are means over the
    points; a case that cannot be modelled says why in place of its numbers."""
    out = []
    for r in results:
        family = f"{FAMILIES[r.family].section} {FAMILIES[r.family].name}"
        if not r.modelled:
            out.append((family, r.name, r.quantity, "-", "-", "-", "-", "-", "-",
                        f"not modelled: {r.reason}"))
            continue
        err = r.relative_error
        out.append((family, r.name, r.quantity, str(r.reference.size),
                    _number(r.reference.mean()), _number(r.measured.mean()),
                    f"{100 * err.max():.2f} %", f"{100 * err.mean():.2f} %",
                    f"{100 * r.tolerance:g} % + {NOISE_SIGMAS:g} se",
                    "yes" if r.passed else "NO"))
    return out


def table(results: list[Result]) -> str:
    """The rows as aligned plain text."""
    body = [COLUMNS, *rows(results)]
    widths = [max(len(row[k]) for row in body) for k in range(len(COLUMNS) - 1)]
    lines = []
    for row in body:
        cells = [cell.ljust(w) for cell, w in zip(row[:-1], widths, strict=True)]
        lines.append("  ".join([*cells, row[-1]]).rstrip())
    return "\n".join(lines)


def _figure(result: Result, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spectrace.images import atomic_path

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 4.8), sharex=True,
                                      gridspec_kw={"height_ratios": (2, 1)})
    x = result.x if result.x.size == result.reference.size else np.arange(result.reference.size)
    top.plot(x, result.reference, "k-", lw=1, label="reference (closed form)")
    top.errorbar(x, result.measured, yerr=NOISE_SIGMAS * result.stderr, fmt="o", ms=3,
                 color="tab:red", label=f"spectrace (± {NOISE_SIGMAS:g} se)")
    top.set_ylabel(result.quantity)
    top.set_title(f"{result.name}: {result.title}", fontsize=10)
    top.legend(fontsize=8)
    scale = np.maximum(np.abs(result.reference), 1e-12)
    bottom.plot(x, 100 * (result.measured - result.reference) / scale, "o", ms=3,
                color="tab:red")
    band = 100 * result.tolerance
    bottom.axhspan(-band, band, color="0.85", label="tolerance")
    bottom.axhline(0.0, color="k", lw=0.5)
    bottom.set_ylabel("error (%)")
    bottom.set_xlabel(result.xlabel or "")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=100)
    plt.close(fig)


def _versions() -> list[tuple[str, str]]:
    from importlib import metadata

    out = []
    for name in ("spectrace", "mitsuba", "drjit", "numpy", "colour-science"):
        try:
            out.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            out.append((name, "not installed"))
    return out


def write_report(results: list[Result], folder, *, variant: str, quick: bool,
                 seed: int) -> Path:
    """``folder/report.md`` with the table, the families' tolerances, a figure per modelled
    case (``folder/<case>.png``) and the versions used; returns its path."""
    from spectrace.images import atomic_path

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for r in results:
        if r.modelled:
            _figure(r, folder / f"{r.name}.png")
    passed = sum(r.passed for r in results)
    modelled = sum(r.modelled for r in results)
    lines = [
        "# spectrace validation: CIE 171:2006 case families",
        "",
        f"{passed} of {modelled} modelled cases pass "
        f"({'quick' if quick else 'full'} run, variant `{variant}`, seed {seed}, "
        f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC).",
        "",
        "| " + " | ".join(COLUMNS) + " |",
        "|" + "---|" * len(COLUMNS),
        *("| " + " | ".join(row) + " |" for row in rows(results)),
        "",
        "A point passes when |spectrace - reference| <= tolerance x |reference| + "
        f"{NOISE_SIGMAS:g} standard errors of its Monte Carlo mean.",
        "",
        "## Tolerances",
        "",
        "| family | tolerance | why |",
        "|---|---|---|",
        *(f"| {f.section} {f.name} | {100 * f.tolerance:g} % | {f.why} |"
          for f in FAMILIES.values()),
        "",
        "## Cases",
        "",
    ]
    for r in results:
        lines.append(f"### {r.name}: {r.title}")
        lines.append("")
        if r.modelled:
            lines += [f"{r.reference.size} points, {r.spp} samples a point.", "",
                      f"![{r.name}]({r.name}.png)", ""]
        else:
            lines += [f"Not modelled: {r.reason}.", ""]
    lines += ["## Versions", "", "| package | version |", "|---|---|",
              *(f"| {n} | {v} |" for n, v in _versions()), ""]
    path = folder / "report.md"
    with atomic_path(path) as tmp:
        Path(tmp).write_text("\n".join(lines), encoding="utf-8")
    return path
