"""Table importers (ASTM E1392 text, CSV, RGL .bsdf tensor files; scattered data resampled onto
a grid) and the one entry point, `load_brdf` / `read_any`, that recognises a file and
returns a Brdf (docs/formats.md)."""

from patina.table.formats.loading import detect_format, load_brdf, read_any
from patina.table.formats.tabledata import TableData, table_from_data

__all__ = ["TableData", "detect_format", "load_brdf", "read_any", "table_from_data"]
