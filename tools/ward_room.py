#!/usr/bin/env python3
"""Ward's (1990) benchmark room in full: Patina's `--indirect` floor illuminance against the
radiosity solve of tests/python/render/test_illuminance_cie171.py (the suite runs a smaller
version), the figures of docs/lighting-validation.md.

    PYTHONPATH=python .venv/bin/python tools/ward_room.py [--samples 4096] [--patch 0.25]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.join(HERE, "..", "tests", "python"), os.path.join(HERE, "..", "tests", "python", "render")]

from test_illuminance_cie171 import ward_errors  # noqa: E402 (the test module is the one place the solve lives)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], allow_abbrev=False)
    ap.add_argument("--samples", type=int, default=4096, help="sensor paths and light samples per point")
    ap.add_argument("--patch", type=float, default=0.25, help="radiosity patch size (m)")
    ap.add_argument("--points", type=float, default=0.5, help="floor point spacing (m), from half of it")
    args = ap.parse_args()
    start = time.perf_counter()
    rel = ward_errors(args.points, args.patch, args.samples)
    print(
        f"{len(rel)} points, {args.samples} samples, {args.patch:g} m patches: "
        f"max |error| {np.abs(rel).max():.2%}, rms {np.sqrt(np.mean(rel**2)):.2%}, mean {rel.mean():+.2%} "
        f"({time.perf_counter() - start:.0f} s)"
    )


if __name__ == "__main__":
    main()
