"""`patina lighting report PROJECT --standard en12464-1|en13201|en12193 --out DIR`: a lighting
project (docs/lighting.md) computed and written as an HTML report, a PDF of it, the plans and
result.json. Exit 0 when every requirement is met, 1 when one fails, 2 on bad input."""

from __future__ import annotations

import argparse
import os
from typing import Any

from patina.cli.files import add_output
from patina.cli.render import deferred_interrupts, terminate_as_interrupt
from patina.errors import FormatError
from patina.lighting.calculation import run
from patina.lighting.project import STANDARDS, read_project
from patina.lighting.report import write_report

OUTPUTS = ("index.html", "result.json", "report.pdf")


def cmd_lighting_report(args: argparse.Namespace) -> int:
    with terminate_as_interrupt():
        # (the standard's name and the output folder were checked by the parser: docs/cli.md)
        if os.path.exists(args.out) and not os.path.isdir(args.out):
            raise FormatError("command line", "--out", f"'{args.out}' exists and is not a folder")
        project = read_project(args.project, args.standard)
        result = run(project, progress=not args.quiet)
        with deferred_interrupts() as came:  # the report's files are each whole, and all of them or none new
            notes = write_report(result, args.out, pdf=not args.no_pdf)
        if came:
            return 130
        for line in notes:
            print(line)
        print(f"wrote {os.path.join(args.out, 'index.html')}")
        for c in result.checks:
            status = {True: "pass", False: "FAIL", None: "not computed"}[c.passed]
            value = "—" if c.value is None else f"{c.value:.4g}"
            margin = "" if c.margin is None else f" (margin {c.margin:+.1%})"
            print(f"  {c.figure:<6} {value:>10}  {'>=' if c.kind == 'min' else '<='} {c.limit:<6g} {status}{margin}")
        return 0 if all(c.passed for c in result.checks) else 1


def add_lighting_commands(sub: Any) -> None:
    s = sub.add_parser("lighting", help="lighting calculations to EN 12464-1, EN 13201 and EN 12193 (docs/lighting.md)")
    lsub = s.add_subparsers(dest="lighting_command", metavar="SUBCOMMAND", required=True)
    p = lsub.add_parser(
        "report", help="compute a lighting project and write its HTML / PDF report (exit 1 when a requirement fails)"
    )
    p.add_argument(
        "project", metavar="PROJECT_JSON", help="a lighting project file naming its scene (docs/lighting.md)"
    )
    p.add_argument("--standard", required=True, choices=STANDARDS, help="the standard the project is checked against")
    add_output(
        p, "--out", folder=OUTPUTS, required=True, metavar="DIR",
        help="the report's folder (index.html, report.pdf, plans, result.json)",
    )  # fmt: skip
    p.add_argument("--no-pdf", action="store_true", help="skip the PDF (printed by headless Chromium)")
    p.add_argument("--quiet", action="store_true", help="no progress display")
    p.set_defaults(func=cmd_lighting_report)
