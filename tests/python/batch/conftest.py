"""The batch tests' library fixture (the helpers are in batch_library.py, beside this file)."""

from __future__ import annotations

import os
import sys

import pytest

sys.path.append(os.path.dirname(__file__))  # appended: `conftest` stays the one of tests/python (others import it)

from batch_library import make_library


@pytest.fixture
def library(tmp_path) -> str:
    return make_library(str(tmp_path / "library"))
