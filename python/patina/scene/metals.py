"""Complex indices of refraction (eta, k) of common metals at the R, G, B wavelengths 650, 550, 450 nm.

An RGB renderer needs one eta and one k per channel; these are the measured spectra
sampled at one wavelength per channel (not integrated against colour matching functions),
which is what "conductor" materials with a `metal` preset use.

Source: the spectra Mitsuba 3 ships as data (mitsuba 3.9.1 on PyPI, `data/ior/<metal>.eta.spd`
and `<metal>.k.spd`, whose headers say "data from www.luxpop.com database"), linearly
interpolated in wavelength at 650, 550 and 450 nm and rounded to 4 digits
(tools/metal_constants.py recomputes them from an installed mitsuba).
"""

from __future__ import annotations

WAVELENGTHS_NM = (650.0, 550.0, 450.0)

# name -> ((eta_r, eta_g, eta_b), (k_r, k_g, k_b))
METALS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "Au": ((0.1678, 0.3504, 1.5085), (3.1378, 2.7141, 1.8788)),
    "Ag": ((0.1394, 0.1248, 0.1517), (4.1288, 3.3396, 2.4704)),
    "Cu": ((0.2166, 0.9582, 1.1658), (3.6377, 2.5771, 2.3939)),
    "Al": ((1.4748, 0.9586, 0.6180), (7.7941, 6.6870, 5.4694)),
    "Cr": ((3.6375, 3.1158, 1.9277), (4.3644, 4.4228, 4.1675)),
}
