"""Prints the eta and k of patina.scene.metals from the spectra an installed mitsuba ships.

    python tools/metal_constants.py        # needs `pip install mitsuba==3.9.1` (the test extra)

Each spectrum (`mitsuba/data/ior/<metal>.{eta,k}.spd`, two columns: nm, value) is
interpolated linearly at patina.scene.metals.WAVELENGTHS_NM (R, G, B) and rounded to 4
digits. The wavelengths and the list of metals come from that module, so the table it
holds and the table printed here cannot disagree about what was sampled.
"""

from __future__ import annotations

import os

import numpy as np

from patina.scene.metals import METALS, WAVELENGTHS_NM

Triple = tuple[float, float, float]


def sample_spectrum(path: str) -> Triple:
    """The spectrum in `path` at WAVELENGTHS_NM, rounded as METALS is."""
    table = np.loadtxt(path, comments="#")
    r, g, b = (round(float(np.interp(nm, table[:, 0], table[:, 1])), 4) for nm in WAVELENGTHS_NM)
    return (r, g, b)


def compute(folder: str) -> dict[str, tuple[Triple, Triple]]:
    """(eta, k) per metal of METALS from the `.spd` spectra in `folder`."""
    return {
        metal: tuple(sample_spectrum(os.path.join(folder, f"{metal}.{quantity}.spd")) for quantity in ("eta", "k"))
        for metal in METALS
    }


def mitsuba_ior_folder() -> str:
    import mitsuba  # heavy optional library: only this tool needs it

    return os.path.join(os.path.dirname(mitsuba.__file__), "data", "ior")


def main() -> None:
    for metal, (eta, k) in compute(mitsuba_ior_folder()).items():
        print(f'"{metal}": ({eta}, {k}),')


if __name__ == "__main__":
    main()
