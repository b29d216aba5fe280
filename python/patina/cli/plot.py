"""`patina plot`: the report of a table (and its fits): figures, 3-D lobes, validation, index.html."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from patina.cli.common import UsageError
from patina.cli.files import add_output
from patina.plot.fits import read_all_fits
from patina.plot.lobes import LobeOptions
from patina.plot.report import REPORT_STEPS, write_report
from patina.progress import Progress
from patina.table import load_brdf


def cmd_plot(args: argparse.Namespace) -> int:

    # The fits are read before the table and the figures, so a bad fit file is refused before any work.
    fits = read_all_fits(args.fit or [])
    brdf = load_brdf(args.file)
    try:  # the output directory too, before the figures: not after a minute of work
        os.makedirs(args.out, exist_ok=True)
    except OSError as e:
        raise UsageError(f"plot: --out {args.out}: cannot make the report directory: {e.strerror}") from None
    skipped: list[str] = []
    lobes = None if args.no_3d else LobeOptions(cosine=not args.lobe_no_cos, log=args.lobe_log)
    with Progress(REPORT_STEPS, "report", unit="step") as progress:
        write_report(brdf, args.out, fits, lobes=lobes, on_skip=skipped.append, on_step=progress.update)
    for why in skipped:
        print(f"patina plot: 3-D lobe view skipped: {why}", file=sys.stderr)
    made = "slices.png, polar.png, " + ("lobe3d.png, " if lobes is not None and not skipped else "")
    print(f"wrote {os.path.join(args.out, 'index.html')} ({made}validate.json)")
    return 0


def add_plot_command(sub: Any) -> None:
    s = sub.add_parser(
        "plot",
        help="an HTML report (index.html and figures): slices, polar plots, 3-D lobes, validation, fits",
        description="Writes DIR/index.html with the table's validation, in-plane slices, polar plots and "
        "3-D lobes; with --fit, each fit is overlaid on the slices and polar plots and its parameters and "
        "metrics are listed side by side.",
    )
    s.add_argument("file")
    s.add_argument(
        "--fit",
        nargs="+",
        default=None,
        metavar="FIT_JSON",
        help="fits to overlay and compare: fit.json files (patina fit --out) and/or rankings (patina fit "
        "--compare --out, every model of it; or the JSON list patina fit --compare --json prints) (default: none)",
    )
    add_output(
        s,
        "--out",
        required=True,
        metavar="DIR",
        folder=("index.html",),
        help="directory for index.html and its figures",
    )
    s.add_argument("--no-3d", action="store_true", help="leave out the 3-D lobe view (pyvista)")
    s.add_argument("--3d-log", dest="lobe_log", action="store_true", help="3-D lobes on a log radius (3 decades)")
    s.add_argument("--3d-no-cos", dest="lobe_no_cos", action="store_true", help="3-D lobes of f, not f cos(theta_o)")
    s.set_defaults(func=cmd_plot)
