"""`patina export MATERIAL --to TARGET --out FILE`: a fit or a measured table to Mitsuba 3,
pbrt-v4, MaterialX, glTF, USD, Blender or an RGL tensor file (docs/export.md)."""

from __future__ import annotations

import argparse
import os
from typing import Any

from patina.cli.common import UsageError
from patina.cli.files import add_input, add_output
from patina.export import TARGETS, export
from patina.export.measured import MEASURED_TARGETS, tensor_path
from patina.table.formats import load_brdf


def cmd_export(args: argparse.Namespace) -> int:
    target = TARGETS[args.to]
    if not args.out.lower().endswith(target.suffixes):
        raise UsageError(f"export: --out {args.out}: a {args.to} file ends with {' or '.join(target.suffixes)}")
    if args.standard_surface and args.to != "materialx":
        raise UsageError("export: --standard-surface is for --to materialx")
    sidecar = f"{args.out}.export.json"  # (--out itself was checked by the parser: docs/cli.md)
    companions = [sidecar]
    if args.to in MEASURED_TARGETS and not args.material.lower().endswith(".json"):
        companions.append(tensor_path(args.to, args.out))  # a table (or a scene's): the tensor file beside --out
    for companion in companions:
        if not args.force and os.path.lexists(companion):
            raise FileExistsError(f"{companion}: exists; pass --force to overwrite it")
    options = {"standard_surface": True} if args.standard_surface else {}
    if args.channels:
        options["channels"] = args.channels
    report = export(args.material, args.to, args.out, table=args.table, progress=True, **options)
    if "tensor_file" in report:
        return _print_measured(report, sidecar)
    m = report["error_against_source"]
    how = "refitted" if report["refitted"] else "exact"
    print(f"wrote {args.out} ({args.to}, {how}) and {sidecar}")
    print(
        f"  against {args.table or report['source']}: relative error median {m['relative_error_median']:.3g}, "
        f"95% {m['relative_error_p95']:.3g}; CIEDE2000 mean {m['ciede2000_mean']:.2f}, 95% {m['ciede2000_p95']:.2f}"
    )
    t = report["target_error_against_source"]
    if t:
        print(
            f"  as {t['evaluator']} evaluates it: relative error median {t['relative_error_median']:.3g}, "
            f"95% {t['relative_error_p95']:.3g}; CIEDE2000 mean {t['ciede2000_mean']:.2f}"
        )
    for note in report["notes"]:
        print(f"  note: {note}")
    return 0


def _print_measured(report: dict[str, Any], sidecar: str) -> int:
    tensor = report["tensor_file"]
    written = tensor if tensor == report["out"] else f"{report['out']}, {tensor}"
    print(f"wrote {written} ({report['target']}, measured: RGL tensor file) and {sidecar}")
    m = report["error_against_source"]
    print(
        f"  read back against {report['source']} at {m['pairs']} pairs: relative error median "
        f"{m['relative_error_median']:.3g}, 95% {m['relative_error_p95']:.3g}"
    )
    t = report["target_error_against_source"]
    if t:
        print(
            f"  as {t['evaluator']} evaluates it: relative error median {t['relative_error_median']:.3g}, "
            f"95% {t['relative_error_p95']:.3g}"
        )
    for note in report["notes"]:
        print(f"  note: {note}")
    return 0


def add_export_command(sub: Any) -> None:
    s = sub.add_parser("export", help="export a fit or a measured table to a renderer's material format")
    s.add_argument(
        "material", metavar="MATERIAL",
        help="a fit.json, a ranking from fit --compare, a measured table, or SCENE.json#name",
    )  # fmt: skip
    s.add_argument("--to", required=True, choices=tuple(TARGETS), help="the target format")
    add_output(s, "--out", required=True, metavar="FILE", help="the file to write (and FILE.export.json beside it)")
    add_input(
        s, "--table", read=load_brdf, metavar="TABLE",
        help="the measured table the fit came from: refit and measure the export against it (default: the fit)",
    )  # fmt: skip
    s.add_argument("--standard-surface", action="store_true", help="materialx: Standard Surface instead of OpenPBR")
    s.add_argument(
        "--channels", choices=("spectral", "rgb"),
        help="an RGL tensor file's channels (rgl; a table to mitsuba or pbrt): spectral (default) or rgb",
    )  # fmt: skip
    s.set_defaults(func=cmd_export)
