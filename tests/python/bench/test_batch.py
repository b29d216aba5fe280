"""The `batch` benchmark group: its two records in quick mode, finite, and its generated
library made of tables that read and validate."""

from __future__ import annotations

import math
import os

import pytest

from patina.bench import GROUPS
from patina.bench.batch import bench_batch, write_library
from patina.table import load_brdf, validate


def test_the_generated_library_is_of_valid_tables(tmp_path):
    write_library(str(tmp_path), 3)
    names = sorted(os.listdir(tmp_path))
    assert names == ["plastic00.ptab", "plastic01.ptab", "plastic02.ptab"]
    for name in names:
        assert validate(load_brdf(str(tmp_path / name))).ok


def test_quick_group_records():
    pytest.importorskip("distributed")
    records = bench_batch(1, quick=True)
    assert [r.name for r in records] == ["batch.library.workers2", "batch.machine.processes2", "batch.render.tiles"]
    library, ceiling, tiles = records
    assert math.isfinite(ceiling.ratio) and ceiling.ratio > 0 and ceiling.value == pytest.approx(ceiling.ratio / 2)
    assert math.isfinite(library.ratio) and library.ratio > 0 and library.value == pytest.approx(library.ratio / 2)
    assert math.isfinite(tiles.ratio) and tiles.ratio > 0 and tiles.value == pytest.approx(1 / tiles.ratio - 1)
    assert "batch" in GROUPS
