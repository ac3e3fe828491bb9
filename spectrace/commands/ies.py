"""``spectrace ies FILE``: what an IES LM-63 or EULUMDAT photometric file describes.

Prints the manufacturer, luminaire and lamp keywords, the format, photometric type and
symmetry, the angle counts and ranges, the luminous flux (lm, the intensity integrated
over the sphere) and its downward share (gamma <= 90), the peak intensity and its
direction (Type C gamma and C), the beam and field angles in the C0-C180 and C90-C270
planes (full angles to 50% and 10% of each plane's own peak; "not defined" where the
intensity never falls that far or the arc would exceed 180 degrees), and the luminous
opening (its shape and size, and the photometric distance, 5 times its largest
dimension, from which the luminaire may be taken as a point, and the measured
near-field error there: the relative difference between the illuminance of the opening
emitting I / A_proj and the point law's on the axis, ``spectrace.photometry.near_field``).
The numbers come from
:class:`spectrace.photometry.Photometry`. ``--plot OUT.png`` draws the polar candela
diagram of the C0-C180 and C90-C270 planes as datasheets do (nadir at the bottom, C0 and
C90 to the right, C180 and C270 to the left; written atomically). A missing or malformed
file is one ``error: ...`` line and exit status 2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from spectrace.errors import FileFormatError, UsageError

#: The polar plot's title: at most this many characters a line and this many lines of
#: the luminaire's name (longer names are cut with an ellipsis), so that it fits the figure.
TITLE_WIDTH = 48
TITLE_LINES = 2


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
    return "not defined" if math.isnan(x) else f"{x:.1f} deg"


def _planes(angles: dict[str, float]) -> str:
    return ", ".join(f"{plane} {_angle(value)}" for plane, value in angles.items())


def _opening(ph) -> str:
    try:
        o = ph.opening
    except FileFormatError as error:
        return str(error).removeprefix(f"{ph.path}: ").removeprefix("luminous opening: ")
    if o.shape == "point":
        return "point (no luminous size given)"
    if o.shape in ("disk", "sphere", "vertical_cylinder"):
        size = f"diameter {o.width:.3g} m" + (f", height {o.height:.3g} m"
                                               if o.shape == "vertical_cylinder" else "")
    else:
        size = f"width {o.width:.3g} m, length {o.length:.3g} m, height {o.height:.3g} m"
    return (f"{o.shape}, {size}; photometric distance {o.photometric_distance:.3g} m "
            f"(5 x {o.largest_dimension:.3g} m)")


def _near_field(ph) -> str | None:
    """The measured error of the point law at the photometric distance on the axis, or
    None when there is no opening (or no quadrature of its shape)."""
    from spectrace.photometry.near_field import SHAPES, axial_near_field_error

    try:
        o = ph.opening
    except FileFormatError:
        return None
    if o.shape not in SHAPES:
        return None
    error = axial_near_field_error(ph)
    if math.isnan(error):
        return "no intensity on the axis (gamma 0) to compare"
    return (f"{100 * error:+.2f}% (the opening's illuminance against the point law's, at "
            f"{o.photometric_distance:.3g} m on the axis, gamma 0)")


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
    rows.append(("beam", f"{_planes(ph.beam_angles)} (50% of each plane's peak)"))
    rows.append(("field", f"{_planes(ph.field_angles)} (10%)"))
    rows.append(("opening", _opening(ph)))
    near = _near_field(ph)
    if near:
        rows.append(("near field", near))
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
    ax.set_title(f"{plot_title(ph)}\n{ph.flux:.0f} lm, peak {ph.max_candela:.0f} cd",
                 fontsize=10)
    ax.legend(loc="lower left", bbox_to_anchor=(-0.12, -0.12), fontsize=8, frameon=False)
    path = Path(path)
    try:
        with atomic_path(path) as tmp:  # temporary name in the same folder, then os.replace
            fig.savefig(tmp, format="png")
    finally:
        plt.close(fig)
    return path


def plot_title(ph) -> str:
    """The luminaire's name (or the file's) wrapped to TITLE_WIDTH characters a line, at
    most TITLE_LINES lines, the rest cut with an ellipsis."""
    import textwrap

    name = _one_line(ph.keywords.get("LUMINAIRE", "") or ph.path.name)
    return "\n".join(textwrap.wrap(name, TITLE_WIDTH, max_lines=TITLE_LINES,
                                    placeholder=" ...", break_long_words=True))


def _nice_ticks(top: float) -> list[float]:
    """4-6 round ring values covering ``top``."""
    raw = top / 5
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    n = math.ceil(top / step - 1e-9)
    return [step * k for k in range(1, n + 1)]
