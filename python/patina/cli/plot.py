"""`patina plot`: the report of a table (and a fit): figures, 3-D lobes, validation, index.html."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any

from patina.fitting import read_fit
from patina.plot.lobes import LobeOptions
from patina.plot.report import write_report
from patina.table import load_brdf


def cmd_plot(args: argparse.Namespace) -> int:

    brdf = load_brdf(args.file)
    fitted, fit_doc = None, None
    if args.fit:
        fitted = read_fit(args.fit)
        with open(args.fit, encoding="utf-8") as f:
            fit_doc = json.load(f)
    skipped: list[str] = []
    lobes = None if args.no_3d else LobeOptions(cosine=not args.lobe_no_cos, log=args.lobe_log)
    write_report(brdf, args.out, fitted, fit_doc, lobes=lobes, on_skip=skipped.append)
    for why in skipped:
        print(f"patina plot: 3-D lobe view skipped: {why}", file=sys.stderr)
    made = "slices.png, polar.png, " + ("lobe3d.png, " if lobes is not None and not skipped else "")
    print(f"wrote {os.path.join(args.out, 'index.html')} ({made}validate.json)")
    return 0


def add_plot_command(sub: Any) -> None:
    s = sub.add_parser("plot", help="figures and index.html: slices, polar plots, 3-D lobes, validation, a fit")
    s.add_argument("file")
    s.add_argument("--fit", default=None, metavar="FIT_JSON", help="overlay a model written by patina fit --out")
    s.add_argument("--out", required=True, metavar="DIR")
    s.add_argument("--no-3d", action="store_true", help="leave out the 3-D lobe view (pyvista)")
    s.add_argument("--3d-log", dest="lobe_log", action="store_true", help="3-D lobes on a log radius (3 decades)")
    s.add_argument("--3d-no-cos", dest="lobe_no_cos", action="store_true", help="3-D lobes of f, not f cos(theta_o)")
    s.set_defaults(func=cmd_plot)
