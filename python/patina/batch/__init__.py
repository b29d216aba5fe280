"""`patina batch`: a library of tables validated, fitted, previewed and reported, on Dask
distributed when it is installed (a LocalCluster by default, or any scheduler), else in this
process. The library's tables and the settings (library), the tasks: pure functions of an
input file, a step, the settings and a seed, that read and write files (tasks), the manifests
that let a rerun skip what is done (manifest), planning and running the tasks (scheduling),
and the library report: gallery, summary.json and summary.csv (gallery). docs/batch.md."""

from patina.batch.library import DEFAULT_MODELS, STEPS, Material, Settings, find_tables, parse_steps
from patina.batch.scheduling import IN_PROCESS, run_batch

__all__ = ["DEFAULT_MODELS", "IN_PROCESS", "STEPS", "Material", "Settings", "find_tables", "parse_steps", "run_batch"]
