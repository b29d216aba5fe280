"""Prints the eta and k of patina.scene.metals from the spectra an installed mitsuba ships.

    python tools/metal_constants.py        # needs `pip install mitsuba==3.9.1` (the test extra)

Each spectrum (`mitsuba/data/ior/<metal>.{eta,k}.spd`, two columns: nm, value) is
interpolated linearly at 650, 550 and 450 nm (R, G, B) and rounded to 4 digits.
"""

from __future__ import annotations

import os

import numpy as np


def main() -> None:
    import mitsuba

    folder = os.path.join(os.path.dirname(mitsuba.__file__), "data", "ior")
    for metal in ("Au", "Ag", "Cu", "Al", "Cr"):
        values = []
        for quantity in ("eta", "k"):
            table = np.loadtxt(os.path.join(folder, f"{metal}.{quantity}.spd"), comments="#")
            values.append(tuple(round(float(np.interp(nm, table[:, 0], table[:, 1])), 4) for nm in (650, 550, 450)))
        print(f'"{metal}": ({values[0]}, {values[1]}),')


if __name__ == "__main__":
    main()
