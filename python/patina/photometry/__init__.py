"""Photometric files (IES LM-63, EULUMDAT) read into one model, `Photometry`
(docs/luminaires.md): `read_photometry(path)` picks the reader by content, then extension;
`Luminaire` evaluates the candela table with the coherent search the BRDF tables use."""

from patina.photometry.angles import angles_of, direction_of
from patina.photometry.ies import read_ies
from patina.photometry.ldt import read_ldt
from patina.photometry.luminaire import Luminaire, load_luminaire
from patina.photometry.model import Opening, Photometry, Tilt
from patina.photometry.reading import read_photometry

__all__ = [
    "Luminaire",
    "Opening",
    "Photometry",
    "Tilt",
    "angles_of",
    "direction_of",
    "load_luminaire",
    "read_ies",
    "read_ldt",
    "read_photometry",
]
