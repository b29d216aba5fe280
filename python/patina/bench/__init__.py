"""Benchmarks: records and timing (records), one module per group (kernels: math and brdf;
fit, trace, render, lights), and the runner behind `patina bench` (run)."""

from patina.bench.records import Record
from patina.bench.run import GROUPS, run_bench

__all__ = ["GROUPS", "Record", "run_bench"]
