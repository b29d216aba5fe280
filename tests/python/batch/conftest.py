"""The batch tests' fixtures: the library (its helpers are in batch_library.py, beside this
file) and one LocalCluster of 2 worker processes that the Dask tests share."""

from __future__ import annotations

import os
import shutil
import sys
from contextlib import contextmanager
from dataclasses import dataclass

import pytest

sys.path.append(os.path.dirname(__file__))  # appended: `conftest` stays the one of tests/python (others import it)

from batch_library import QUICK, make_library

from patina.batch import IN_PROCESS, run_batch


@pytest.fixture
def library(tmp_path) -> str:
    return make_library(str(tmp_path / "library"))


@dataclass(frozen=True)
class Finished:
    library: str
    out: str
    summary: dict
    lines: tuple[str, ...]  # what the run said


@pytest.fixture(scope="session")
def finished_once(tmp_path_factory) -> Finished:
    """The library processed once in this process (QUICK settings), shared: read it, never change it."""
    root = tmp_path_factory.mktemp("batch")
    library = make_library(str(root / "library"))
    out = str(root / "out")
    lines: list[str] = []
    summary = run_batch(library, out, QUICK, scheduler=IN_PROCESS, progress=False, say=lines.append)
    return Finished(library, out, summary, tuple(lines))


@pytest.fixture
def finished(finished_once, tmp_path) -> Finished:
    """A copy of the processed library and its outputs, to change (the manifests hold checksums, not paths)."""
    library = shutil.copytree(finished_once.library, tmp_path / "library")
    out = shutil.copytree(finished_once.out, tmp_path / "out")
    return Finished(str(library), str(out), finished_once.summary, finished_once.lines)


@contextmanager
def _local_client():
    """A Dask client of a LocalCluster of 2 worker processes, one thread each (skipped without Dask)."""
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster,
        distributed.Client(cluster) as c,
    ):
        yield c


@pytest.fixture(scope="session")
def client():
    """The LocalCluster the Dask tests share; no test kills its workers (see client_to_kill)."""
    with _local_client() as c:
        yield c


@pytest.fixture
def client_to_kill():
    """A LocalCluster of its own for a test that kills a worker. On the shared one, the next
    tests had to wait for the nanny to restart the killed worker, which under the loaded suite
    once took more than a minute; a fresh cluster costs a few seconds."""
    with _local_client() as c:
        yield c
