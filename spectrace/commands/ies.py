"""``spectrace ies FILE``: what an IES LM-63 or EULUMDAT photometric file describes.

Prints the manufacturer, luminaire and lamp keywords, the format, photometric type and
symmetry, the angle counts and ranges, the luminous flux (lm, the intensity integrated
over the sphere) and its downward share (gamma <= 90), the peak intensity and its
direction (Type C gamma and C), and the beam and field angles (full angles to 50% and
10% of the peak, the mean of the C0-C180 and C90-C270 planes). The numbers come from
:class:`spectrace.photometry.Photometry`. ``--plot OUT.png`` draws the polar candela
diagram of the C0-C180 and C90-C270 planes as datasheets do (nadir at the bottom, C0 and
C90 to the right, C180 and C270 to the left; written atomically). A missing or malformed
file is one ``error: ...`` line and exit status 2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from spectrace.errors import UsageError


def add_arguments(parser) -> None:
    parser.add_argument("file", help="photometric file: IES LM-63 (.ies) or EULUMDAT (.ldt)")
    parser.add_argument("--plot", metavar="OUT.png",
                        help="draw the polar candela diagram (C0-C180, C90-C270)")


def run(args) -> int:
    from spectrace.photometry import read_photometry

    if args.plot and Path(args.plot).suffix.lower() != ".png":
        raise UsageError(f"--plot {args.plot}: must end in .png")
    ph = read_photometry(args.file)  # before check_writable makes the plot's folder
    if args.plot:
        from spectrace.images import check_writable

        check_writable(args.plot)
    lines = describe(ph)
    if args.plot:
        plot_polar(args.plot, ph)
        lines.append(f"{'plot':<11}{args.plot}")
    print("\n".join(lines))
    return 0


def _one_line(text: str) -> str:
    """The text on one line, control characters (e.g. terminal escape codes) shown as ?."""
    import unicodedata

    text = " ".join(text.split())
    return "".join("?" if unicodedata.category(ch).startswith("C") else ch for ch in text)


def _angle(x: float) -> str:
    return "n/a" if math.isnan(x) else f"{x:.1f} deg"


def describe(ph) -> list[str]:
    """The report's lines."""
    rows = [("file", str(ph.path))]
    for key, label in (("MANUFAC", "manufac"), ("LUMINAIRE", "luminaire"),
                       ("LUMCAT", "lumcat"), ("LAMP", "lamp"), ("LAMPCAT", "lampcat")):
        if ph.keywords.get(key):
            rows.append((label, _one_line(ph.keywords[key])))
    rows.append(("format", f"{ph.format}, Type {ph.photometric_type}, symmetry {ph.symmetry}"))
    v, h = ph.vertical_angles, ph.horizontal_angles
    rows.append(("angles", f"{v.size} vertical ({v[0]:g} to {v[-1]:g}), "
                           f"{h.size} horizontal ({h[0]:g} to {h[-1]:g})"))
    if ph.lumens_per_lamp is None:
        basis = "absolute photometry"
    else:
        lamps = ph.lumens_per_lamp * ph.n_lamps
        basis = (f"relative: {ph.n_lamps} x {ph.lumens_per_lamp:g} lm lamps, "
                 f"light output ratio {100 * ph.flux / lamps:.1f}%")
    down = 100 * ph.flux_between(0.0, 90.0) / ph.flux if ph.flux > 0 else 0.0
    rows.append(("flux", f"{ph.flux:.1f} lm, {down:.1f}% downward ({basis})"))
    gamma, c = ph.peak_direction
    rows.append(("peak", f"{ph.max_candela:.1f} cd at gamma {gamma:g}, C {c:g}"))
    rows.append(("beam", f"{_angle(ph.beam_angle)} (50% of peak), field {_angle(ph.field_angle)}"
                         " (10%); mean of the C0-C180 and C90-C270 planes"))
    return [f"{label:<11}{text}" for label, text in rows]


def plot_polar(path, ph) -> Path:
    """Polar candela diagram of the C0-C180 and C90-C270 planes, written atomically.

    Nadir (gamma 0) at the bottom; C0 and C90 on the right half, C180 and C270 on the left,
    angle labels 0-180 on both sides, rings labelled in cd.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spectrace.images import atomic_path

    gamma = np.linspace(0.0, 180.0, 721)
    fig = plt.figure(figsize=(6, 6.4), dpi=100)
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("S")
    ax.set_theta_direction(1)  # counterclockwise from the bottom: positive angles on the right
    styles = (("C0-C180", 0.0, "-", "tab:red"), ("C90-C270", 90.0, "--", "tab:blue"))
    for label, c, style, colour in styles:
        right = ph.intensity(gamma, c)
        left = ph.intensity(gamma, c + 180.0)
        theta = np.radians(np.concatenate([-gamma[::-1], gamma]))
        ax.plot(theta, np.concatenate([left[::-1], right]), style, color=colour, lw=1.6,
                label=label)
    ax.set_thetagrids(np.arange(0, 360, 30),
                      [f"{a if a <= 180 else 360 - a}°" for a in range(0, 360, 30)])
    top = ph.max_candela if ph.max_candela > 0 else 1.0
    ticks = _nice_ticks(top)
    ax.set_rlim(0, ticks[-1])
    labels = [f"{t:g}" for t in ticks[:-1]] + [f"{ticks[-1]:g} cd"]
    ax.set_rgrids(ticks, labels, angle=100, fontsize=8)
    title = _one_line(ph.keywords.get("LUMINAIRE", "") or ph.path.name)
    ax.set_title(f"{title}\n{ph.flux:.0f} lm, peak {ph.max_candela:.0f} cd", fontsize=10)
    ax.legend(loc="lower left", bbox_to_anchor=(-0.12, -0.12), fontsize=8, frameon=False)
    path = Path(path)
    try:
        with atomic_path(path) as tmp:  # temporary name in the same folder, then os.replace
            fig.savefig(tmp, format="png")
    finally:
        plt.close(fig)
    return path


def _nice_ticks(top: float) -> list[float]:
    """4-6 round ring values covering ``top``."""
    raw = top / 5
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    n = math.ceil(top / step - 1e-9)
    return [step * k for k in range(1, n + 1)]
