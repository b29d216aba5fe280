"""Table importers (ASTM E1392 text, CSV, scattered data resampled onto a grid) and the
one entry point, `load_brdf` / `read_any`, that recognises a file and returns a Brdf."""

from patina.table.formats.loading import detect_format, load_brdf, read_any, table_from_data
from patina.table.formats.tabledata import TableData

__all__ = ["TableData", "detect_format", "load_brdf", "read_any", "table_from_data"]
