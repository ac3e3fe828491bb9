"""``spectrace spd SOURCE``: colorimetry of one spectral power distribution.

SOURCE is a two-column CSV file (wavelength in nm, value) or a colour-science dataset name
(illuminants "D65", "A", "FL2", ...; ColorChecker patches "dark skin",
"BabelColor Average:dark skin"). Prints:

* XYZ: emissive CIE XYZ (X = integral S xbar / integral ybar, same unit as the SPD values;
  a constant SPD of 1 has Y = 1) for the chosen observer, and its chromaticity xy;
* CCT (Ohno 2013) and Duv; CRI Ra (CIE 13.3) for light sources;
* sRGB: the SPD's colour as encoded sRGB, scaled so that its largest linear component is 1
  (out-of-gamut components clipped to [0, 1]), also as #rrggbb.

With ``--reflectance`` (automatic for ColorChecker patches), the SPD is a reflectance and
XYZ is taken under an illuminant (``--illuminant``, default D65; perfect white Y = 1)
instead, without CCT/CRI. Wavelengths in micrometres or metres and negative values are
refused with a line that names them. The numbers come from
:func:`spectrace.spectral.describe.describe_spd`.
``--plot out.png`` draws the SPD with the area under it coloured by wavelength.
A missing or malformed file is one ``error: ...`` line and exit status 2.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from spectrace.errors import UsageError, first_line

OBSERVER_CHOICES = {
    "2": "CIE 1931 2 Degree Standard Observer",
    "10": "CIE 1964 10 Degree Standard Observer",
}


def add_arguments(parser) -> None:
    parser.add_argument(
        "source",
        help="SPD file (CSV: wavelength_nm, value) or dataset name (D65, A, FL2, 'dark skin')",
    )
    parser.add_argument(
        "--observer",
        choices=sorted(OBSERVER_CHOICES),
        default="2",
        help="CIE 1931 2 degree (default) or CIE 1964 10 degree observer",
    )
    parser.add_argument(
        "--reflectance",
        action="store_true",
        help="treat the SPD as a reflectance seen under --illuminant (automatic for "
        "ColorChecker patches)",
    )
    parser.add_argument(
        "--illuminant", default="D65", help="illuminant for --reflectance (default D65)"
    )
    parser.add_argument("--plot", metavar="OUT.png", help="draw the SPD coloured by wavelength")


def run(args) -> int:
    from spectrace import spectral as S
    from spectrace.spectral.datasets import is_reflectance_dataset
    from spectrace.spectral.describe import describe_spd

    wl, values, label = S.load_spd(args.source)
    # A ColorChecker patch is a reflectance: CCT and CRI describe light sources only.
    reflectance = args.reflectance or is_reflectance_dataset(args.source)
    if reflectance and args.illuminant not in _illuminant_names():
        raise UsageError(f"--illuminant: unknown illuminant {args.illuminant!r}")
    if reflectance and float(np.max(values)) > 1.0:
        print(f"warning: {label} has values up to {float(np.max(values)):.4g}: not a "
              "reflectance in [0, 1], so its Y and sRGB are not those of a surface",
              file=sys.stderr)
    if args.plot:
        from spectrace.images import check_writable

        if Path(args.plot).suffix.lower() != ".png":
            raise UsageError(f"--plot {args.plot}: must end in .png")
        check_writable(args.plot)
    try:
        info = describe_spd(wl, values, OBSERVER_CHOICES[args.observer], reflectance,
                            args.illuminant, where=label)
    except ValueError as e:  # colour-science's own checks too
        raise UsageError(first_line(e)) from None
    x, y, z = info["XYZ"]
    print(f"SPD      {label}: {wl.size} samples, {wl[0]:g}-{wl[-1]:g} nm"
          + ("  (a reflectance dataset)" if reflectance and not args.reflectance else ""))
    print(
        f"XYZ      {x:.6g} {y:.6g} {z:.6g}"
        + (f"  (reflectance under {args.illuminant}, white Y = 1)" if reflectance else "")
    )
    print(f"xy       {info['xy'][0]:.5f} {info['xy'][1]:.5f}")
    if "CCT" in info:
        print(f"CCT      {info['CCT']:.0f} K  (Duv {info['Duv']:+.5f})")
        print(f"CRI Ra   {info['CRI']:.1f}")
    rgb = info["sRGB"]
    hexcode = "#" + "".join(f"{int(round(c * 255)):02x}" for c in rgb)
    print(f"sRGB     {rgb[0]:.4f} {rgb[1]:.4f} {rgb[2]:.4f}  {hexcode}")
    if args.plot:
        plot_spd(args.plot, wl, values, label)
        print(f"plot     {args.plot}")
    return 0


def _illuminant_names():
    import colour

    return set(colour.SDS_ILLUMINANTS)


def plot_spd(path, wavelengths, values, title: str = "") -> Path:
    """Plot the SPD; the area under it is filled with the colour of each wavelength.

    The colour of wavelength l is the encoded sRGB of the CMF triple (xbar, ybar, zbar)(l),
    normalised to its largest linear component and clipped to the gamut. Written atomically.
    """
    import matplotlib

    matplotlib.use("Agg")
    import colour
    import matplotlib.pyplot as plt

    from spectrace import spectral as S

    cmfs = colour.MSDS_CMFS[S.CIE_1931_2]
    grid = np.linspace(max(wavelengths[0], 360.0), min(wavelengths[-1], 830.0), 512)
    if grid[0] >= grid[-1]:
        grid = np.linspace(wavelengths[0], wavelengths[-1], 512)
    cmf = np.stack(
        [np.interp(grid, cmfs.wavelengths, cmfs.values[:, c], 0, 0) for c in range(3)], -1
    )
    lin = np.clip(S.xyz_to_linear_srgb(cmf), 0, None)
    lin = lin / np.maximum(lin.max(axis=-1, keepdims=True), 1e-12)
    strip = S.encode_srgb(np.clip(lin, 0, 1))[None]

    fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
    top = float(np.max(values)) * 1.05
    im = ax.imshow(strip, extent=(grid[0], grid[-1], 0, top), aspect="auto", origin="lower")
    (line,) = ax.plot(wavelengths, values, color="black", lw=1.5)
    poly = ax.fill_between(wavelengths, 0, values, facecolor="none", edgecolor="none")
    im.set_clip_path(poly.get_paths()[0], transform=ax.transData)
    ax.set_xlim(wavelengths[0], wavelengths[-1])
    ax.set_ylim(min(0.0, float(np.min(values))), top)
    ax.set_xlabel("wavelength (nm)")
    ax.set_ylabel("value")
    ax.set_title(title)
    fig.tight_layout()
    from spectrace.images import atomic_path

    path = Path(path)
    try:
        with atomic_path(path) as tmp:  # temporary name, umask mode, renamed on success
            fig.savefig(tmp, format="png")
    finally:
        plt.close(fig)
    return path
