"""Tables with known answers: analytic BRDFs in double precision and tables sampled from
them (analytic), the Günther et al. car-paint model (carpaint) and the bundled car-paint
base table's grid (carpaint_table). Used by tests, benchmarks and tools/, never by the
workbench's own commands."""
