"""`patina bench`: kernel and renderer speed as ratios against baselines in the same run."""

from __future__ import annotations

import argparse
from typing import Any

from patina.bench import GROUPS, run_bench
from patina.cli.files import add_output
from patina.cli.values import integer


def cmd_bench(args: argparse.Namespace) -> int:

    return run_bench(
        only=args.only,
        json_path=args.json,
        repeat=args.repeat,
        quick=args.quick,
        progress=not args.quiet,
        verbose=args.verbose,
        large=args.large,
    )


def add_bench_command(sub: Any) -> None:
    s = sub.add_parser("bench", help="measure kernel speed (ratios against baselines in the same run)")
    s.add_argument("--only", default=None, choices=tuple(GROUPS), help="one group (default: all)")
    add_output(s, "--json", default=None, metavar="FILE", extensions=(".json",), help="also write the records as JSON")
    s.add_argument("--repeat", type=integer(1, 1000), default=7, help="repetitions; medians are reported")
    s.add_argument("--quick", action="store_true", help="small inputs, for a smoke test")
    s.add_argument(
        "--large", action="store_true", help="the cache group at 384 pixels wide (records named *.large), not 192"
    )
    s.add_argument("--quiet", action="store_true", help="no progress and no table: errors only (use with --json)")
    s.add_argument("--verbose", action="store_true", help="list each of Mitsuba's warnings (else one line sums them)")
    s.set_defaults(func=cmd_bench)
