#!/usr/bin/env python3
"""Writes the bundled synthetic r-table, materials/rtables/synthetic-road.rtab.

    PYTHONPATH=python .venv/bin/python tools/make_rtable.py [--out PATH]

The CIE's standard road-surface tables (R1-R4, C1-C2) are copyrighted, so Patina ships a
made-up surface of about their kind on their grid (CIE 144 / EN 13201-3: 29 rows of tan gamma
0 to 12, 20 columns of beta 0 to 180 degrees): a diffuse part q_d and a forward-scattering
sheen that grows with the incidence and falls off with beta, q(beta, gamma) = q_d +
q_s exp(-(beta / 25 deg)^2) tan(gamma)^1.5, stored as r = q cos^3 gamma x 10^4, rounded.
It is an example of the format and the computation, not a surface to design a road with.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from patina.lighting.rtable import read_rtable, write_rtable

BETA = np.array([0, 2, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180], float)
TAN_GAMMA = np.concatenate([np.arange(0, 2.0, 0.25), np.arange(2.0, 12.01, 0.5)])
Q_DIFFUSE = 0.055  # 1/sr: a fairly dark asphalt
Q_SHEEN = 0.03  # 1/sr at tan gamma 1, beta 0
SHEEN_BETA = 25.0  # degrees
OUT = os.path.join(os.path.dirname(__file__), "..", "materials", "rtables", "synthetic-road.rtab")


def synthetic_r_e4() -> np.ndarray:
    cos3 = np.cos(np.arctan(TAN_GAMMA))[:, None] ** 3
    q = Q_DIFFUSE + Q_SHEEN * np.exp(-((BETA[None, :] / SHEEN_BETA) ** 2)) * TAN_GAMMA[:, None] ** 1.5
    return np.round(q * cos3 * 1e4)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], allow_abbrev=False)
    ap.add_argument("--out", default=OUT)
    args = ap.parse_args()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    header = {"name": "synthetic road surface (Patina example, not a CIE table)", "source": "tools/make_rtable.py"}
    write_rtable(args.out, synthetic_r_e4(), BETA, TAN_GAMMA, header)
    table = read_rtable(args.out)
    print(f"{args.out}: {len(TAN_GAMMA)} x {len(BETA)}, Q0 = {table.q0():.4f} 1/sr")


if __name__ == "__main__":
    main()
