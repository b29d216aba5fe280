"""Pictures of tables and luminaires: in-plane slices (slices), 3-D lobe views (lobes, drawn
off-screen by lobes_render in a child process), polar intensity diagrams (luminaire) and
the HTML report of `patina plot` (report)."""
