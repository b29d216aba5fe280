"""Lighting calculations a lighting engineer signs (docs/lighting.md): exact direct
illuminance from point, spot and goniometric luminaires, sensor kinds, grids laid out by
the standards' rules (EN 12464-1, EN 13201-3, EN 12193), road luminance from r-tables and
the standards' classes checked with their margins."""
