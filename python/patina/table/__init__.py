"""Measured tables: the Brdf type, angle conventions, spectral to colour, validation, and
the importers (`formats/`) that turn every supported file into a Brdf."""

from patina.table.angles import angles_to_directions, halfdiff_to_directions
from patina.table.brdf import Brdf
from patina.table.formats import load_brdf, read_any
from patina.table.validation import Report, Tolerances, format_report, validate

__all__ = [
    "Brdf",
    "Report",
    "Tolerances",
    "angles_to_directions",
    "format_report",
    "halfdiff_to_directions",
    "load_brdf",
    "read_any",
    "validate",
]
