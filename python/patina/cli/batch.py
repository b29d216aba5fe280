"""`patina batch LIBRARY_DIR --out OUT_DIR`: every table of a folder validated, fitted, previewed
and reported, and one library report (patina.batch; docs/batch.md)."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from patina.batch import DEFAULT_MODELS, IN_PROCESS, Settings, parse_steps, run_batch
from patina.batch.library import MAX_SIDE, MAX_SPP, check_settings
from patina.cli.common import UsageError
from patina.cli.files import add_output
from patina.cli.render import MAX_WORKERS, PREVIEW_SHAPES, add_preview_object_options
from patina.cli.values import integer


def cmd_batch(args: argparse.Namespace) -> int:
    try:
        settings = Settings(
            steps=parse_steps(args.steps),
            models=tuple(args.models),
            loss=args.loss,
            starts=args.starts,
            seed=args.seed,
            width=args.width,
            height=args.height,
            spp=args.spp,
            shape=args.shape if args.shape in PREVIEW_SHAPES else os.path.abspath(args.shape),
            env=os.path.abspath(args.env) if args.env else "",
            lobes=args.lobes,
        )
        check_settings(settings)
    except ValueError as e:
        raise UsageError(f"batch: {e}") from None
    say = print if not args.quiet else (lambda line: None)
    try:
        summary = run_batch(
            args.library,
            args.out,
            settings,
            scheduler=args.scheduler,
            workers=args.workers,
            progress=not args.quiet,
            say=say,
        )
    except ValueError as e:  # options, the folder, the scheduler: before any task ran
        raise UsageError(f"batch: {e}") from None
    counts = summary["counts"]
    for row in summary["materials"]:
        if row["status"] == "failed":
            print(f"patina batch: {row['name']}: {row['error']}", file=sys.stderr)
    say(
        f"{counts['ok']} of {counts['tables']} tables processed, {counts['failed']} failed "
        f"({counts['tasks_run']} tasks run, {counts['tasks_reused']} reused); "
        f"wrote {os.path.join(summary['out'], 'index.html')}, summary.json, summary.csv"
    )
    return 0 if counts["ok"] > 0 else 1  # non-zero only when nothing could be processed


def add_batch_command(sub: Any) -> None:
    s = sub.add_parser(
        "batch",
        help="a library of tables validated, fitted, previewed and reported (on Dask distributed when installed)",
        description="Processes every table in LIBRARY_DIR (the formats patina info reads; other files are listed "
        "as skipped) into OUT_DIR/materials/NAME/ and writes OUT_DIR/index.html (a sortable gallery), "
        "summary.json and summary.csv. A rerun skips the work whose inputs and settings are unchanged. "
        "Exit 0 when at least one table was processed, 1 when none could be, 2 for bad options.",
    )
    s.add_argument("library", metavar="LIBRARY_DIR", help="the folder of tables (read one level deep)")
    add_output(
        s,
        "--out",
        required=True,
        metavar="OUT_DIR",
        folder=("index.html", "summary.json", "summary.csv", "materials"),
        updates="summary.json",
        help="the folder for the reports (made if missing; an earlier run's is updated, its unchanged work kept)",
    )
    s.add_argument(
        "--steps", default="validate,fit,preview,report", help="comma-separated, of validate, fit, preview, report"
    )
    s.add_argument(
        "--models",
        nargs="+",
        default=list(DEFAULT_MODELS),
        metavar="MODEL",
        help=f"the models compared, MODEL or MODEL:LOBES as patina fit --compare (default: {' '.join(DEFAULT_MODELS)})",
    )
    s.add_argument("--loss", default="l2cos", choices=("l2cos", "log"), help="the fitting loss (as patina fit)")
    s.add_argument("--starts", type=integer(1, 64), default=2, help="local starts a model (as patina fit)")
    s.add_argument("--seed", type=integer(0, 2**63 - 1), default=0, help="the seed of the fits and the preview renders")
    s.add_argument(
        "--width", type=integer(1, MAX_SIDE), default=160, help="each preview image's width (two side by side)"
    )
    s.add_argument("--height", type=integer(1, MAX_SIDE), default=120, help="each preview image's height")
    s.add_argument("--spp", type=integer(1, MAX_SPP), default=16, help="samples a pixel of the previews")
    add_preview_object_options(s)  # the preview object and its environment
    s.add_argument("--lobes", action="store_true", help="the 3-D lobe view in each report (slower)")
    s.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help=f"a running Dask scheduler (tcp://host:8786), or {IN_PROCESS} for no Dask "
        "(default: a local cluster on this machine)",
    )
    s.add_argument(
        "--workers",
        type=integer(1, MAX_WORKERS),
        default=None,
        help="worker processes of the local cluster (default: cores)",
    )
    s.add_argument("--quiet", action="store_true", help="errors only")
    s.set_defaults(func=cmd_batch)
