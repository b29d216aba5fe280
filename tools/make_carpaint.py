#!/usr/bin/env python3
"""Generates the bundled car-paint base table, materials/carpaint-base.ptab, and prints its accuracy.

    PYTHONPATH=python .venv/bin/python tools/make_carpaint.py [--paint NAME] [--out PATH]

The table is the base of Günther et al.'s (2005) car-paint model (paint 'blue' by default)
at the directions refracted through a smooth clear coat of index 1.5, on an irregular
half/difference grid of the outside directions (see patina/carpaint_table.py). The renderer
puts the coat back on top. The figures printed are those in materials/carpaint-base.md.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from patina import Brdf, validate
from patina.synthetic.carpaint import PAINTS, base_brdf, coated_base, coated_paint, dielectric_fresnel
from patina.synthetic.carpaint_table import (
    BUNDLED_PAINT,
    base_table,
    interpolation_errors,
    peak_pairs,
    random_pairs,
)
from patina.table.formats import table_from_data

MATERIALS = os.path.join(os.path.dirname(__file__), "..", "materials")


def report(brdf: Brdf, name: str) -> None:
    paint = PAINTS[name]
    model = coated_base(paint)
    rng = np.random.default_rng(2005)
    print(f"{brdf}")
    print("table against the model, relative error over RGB:")
    print(
        "  random pairs (uniform, theta < 85 deg):  ",
        interpolation_errors(brdf, model, *random_pairs(200_000, rng)).as_text(),
    )
    print(
        "  near the peak (theta_h < 3 deg):         ",
        interpolation_errors(brdf, model, *peak_pairs(100_000, rng)).as_text(),
    )
    print(
        "  at the peak (theta_h < 1 deg):           ",
        interpolation_errors(brdf, model, *peak_pairs(100_000, rng, 1.0)).as_text(),
    )
    # what ignoring the coat's refraction would cost: the base at the outside directions
    wi, wo = random_pairs(200_000, rng)
    naive = base_brdf(paint)(wi, wo)
    t = (1 - dielectric_fresnel(wi[:, 2])) * (1 - dielectric_fresnel(wo[:, 2]))
    rel = np.abs(naive * t[:, None] - coated_paint(paint)(wi, wo)) / coated_paint(paint)(wi, wo)
    print(
        f"  (a table of the base at unrefracted directions would be off by median {100 * np.median(rel):.1f}%, "
        f"99th percentile {100 * np.percentile(rel, 99):.0f}%)"
    )
    result = validate(brdf)
    checks = result.checks
    print(
        f"validate: problems {result.problems}; max albedo {checks['albedo']['max']:.4f}; "
        f"reciprocity p95 {checks['reciprocity']['p95']:.2e}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paint", default=BUNDLED_PAINT, choices=sorted(PAINTS))
    parser.add_argument("--out", default=os.path.join(MATERIALS, "carpaint-base.ptab"))
    args = parser.parse_args()
    brdf = Brdf(table_from_data(base_table(PAINTS[args.paint])), args.out)
    brdf.save(args.out)
    print(f"wrote {os.path.normpath(args.out)} ({os.path.getsize(args.out)} bytes)")
    report(brdf, args.paint)


if __name__ == "__main__":
    main()
