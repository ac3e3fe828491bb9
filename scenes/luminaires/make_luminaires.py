"""Write the example luminaires of ``scenes/luminaires.xml`` (run from anywhere).

    python scenes/luminaires/make_luminaires.py

* ``downlight.ies`` (LM-63-2002, rotational symmetry, absolute photometry): a narrow
  downlight I = I0 cos^29(gamma) below the horizon, beam angle
  2 arccos(0.5^(1/29)) = 25.0 degrees, I0 = 800 * 30 / (2 pi) cd so that the analytic
  flux 2 pi I0 / (n + 1) is 800 lm;
* ``downlight.ldt``: the same distribution as EULUMDAT (Isym 1, a 1000 lm LED module,
  intensities in cd/klm);
* ``wallwasher.ies`` (LM-63-2019, bilateral about the C0-C180 plane): an asymmetric lobe
  aimed 35 degrees from nadir towards C = 0 (the wall), plus a weak downlight term,
  scaled to 1500 lm.

The profiles are analytic (spectrace.photometry.generate); the files are made by this
script, so they carry no manufacturer's data. Re-running it rewrites them identically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from spectrace.photometry import Photometry
from spectrace.photometry import generate as G

HERE = Path(__file__).resolve().parent
N_DOWN = 29  # cos^n exponent: beam angle 25.0 degrees
FLUX_DOWN = 800.0  # lm
FLUX_WALL = 1500.0  # lm
GAMMA_DOWN = np.arange(0.0, 90.001, 1.0)
GAMMA_WALL = np.arange(0.0, 90.001, 2.5)
C_WALL = G.horizontal_angles("bilateral_0_180", 5.0)


def common_keywords(catalogue: str, name: str, lamp: str) -> dict[str, str]:
    return {
        "TEST": f"{catalogue}-T2026",
        "TESTLAB": "spectrace (computed, not measured)",
        "ISSUEDATE": "2026-12-01",
        "MANUFAC": "spectrace examples",
        "LUMCAT": catalogue,
        "LUMINAIRE": name,
        "LAMPCAT": "LED-3000K",
        "LAMP": lamp,
        "BALLAST": "constant-current LED driver",
        "OTHER": "Analytic profile written by spectrace.photometry.generate\n"
                 "for the example scene scenes/luminaires.xml",
    }


def main() -> list[Path]:
    I0 = FLUX_DOWN * (N_DOWN + 1) / (2 * np.pi)
    down = G.cos_power(I0, N_DOWN)
    written = [
        G.write_ies_function(
            HERE / "downlight.ies", down, symmetry="rotational", vertical_angles=GAMMA_DOWN,
            version="LM-63-2002", input_watts=9.0, opening=(-0.06, -0.06, 0.0),
            keywords=common_keywords("SPX-DL25", "Narrow downlight, 25 degree beam, round 60 mm",
                                     "LED module 3000 K CRI 90, 800 lm"),
        ),
        G.write_ldt(
            HERE / "downlight.ldt", down, isym=1, mc=24, gamma_angles=GAMMA_DOWN,
            lamp_flux=1000.0, luminaire="Narrow downlight, 25 degree beam, round 60 mm",
            luminaire_number="SPX-DL25", report="SPX-DL25-T2026", lamp_type="LED module",
            colour="3000K", cri="90", watts=9.0, dimensions_mm=(60.0, 0.0, 80.0),
        ),
    ]
    wall = G.wall_washer(1.0, tilt_deg=35.0, n=6.0, downlight=0.15)
    unit = Photometry(path=HERE / "wallwasher.ies", format="LM-63-2019", photometric_type="C",
                      vertical_angles=GAMMA_WALL, horizontal_angles=C_WALL,
                      candela=G.tabulate(wall, GAMMA_WALL, C_WALL), symmetry="bilateral_0_180")
    scale = FLUX_WALL / unit.flux  # the table's own flux: the file states 1500 lm exactly
    written.append(
        G.write_ies(
            HERE / "wallwasher.ies", GAMMA_WALL, C_WALL, unit.candela * scale,
            version="LM-63-2019", input_watts=16.0, opening=(0.1, 0.3, 0.0),
            keywords=common_keywords("SPX-WW35", "Asymmetric wall-washer, 300 mm",
                                     "LED board 3000 K CRI 90, 1500 lm")
            | {"FILEGENINFO": "computed from an analytic distribution, not measured"},
        )
    )
    return written


if __name__ == "__main__":
    for path in main():
        print(path)
