"""The `patina luminaire info|plot` commands (registered by cli.py)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from patina.cli.files import add_output
from patina.cli.values import number
from patina.lighting.ugr_table import format_table, ugr_table
from patina.photometry.luminaire import load_luminaire
from patina.plot.luminaire import plot_luminaire


def _fmt(value: float | None, unit: str = "deg") -> str:
    return "-" if value is None else f"{value:.1f} {unit}"


def cmd_luminaire_info(args: argparse.Namespace) -> int:

    info = load_luminaire(args.file).info()
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    fa = info["file_angles"]
    h, v = fa["horizontal"], fa["vertical"]
    print(f"{info['source']}  ({info['format']} {info['version']}, type {info['type']})")
    if info["luminaire"] or info["manufacturer"]:
        print(f"  luminaire        {info['luminaire'] or '-'}  ({info['manufacturer'] or 'no manufacturer'})")
    print(
        f"  angles           {h['count']} horizontal {h['min_deg']:g}..{h['max_deg']:g} deg, "
        f"{v['count']} vertical {v['min_deg']:g}..{v['max_deg']:g} deg; "
        f"symmetry {info['symmetry']}"
    )
    if info["absolute_photometry"]:
        stated = info["luminaire_lumens_declared"]
        print(
            f"  lumens           absolute photometry; the table integrates to {info['lumens_integrated']:.1f} lm"
            + (f" (the file states {stated:.1f} lm)" if stated is not None else "")
        )
    else:
        stated = info["light_output_ratio_declared"]
        print(
            f"  lumens           declared {info['lumens_declared']:g} ({info['lamps']} lamps), "
            f"table {info['lumens_integrated']:.1f}: light output ratio {100 * info['light_output_ratio']:.2f} %"
            + (f" (the file states {100 * stated:.2f} %)" if stated is not None else "")
        )
    at = info["max_at_deg"]
    print(f"  max intensity    {info['max_candela']:.1f} cd at h {at['horizontal']:g}, v {at['vertical']:g} deg")
    for name in info["beam_angle_deg"]:
        beam, field = _fmt(info["beam_angle_deg"][name]), _fmt(info["field_angle_deg"][name])
        print(f"  {name:<16} beam (50 %) {beam}, field (10 %) {field}")
    if info["tilt"]:
        print(f"  tilt             {len(info['tilt']['angles_deg'])} angles, lamp geometry {info['tilt']['geometry']}")
    for warning in info["warnings"]:
        print(f"  warning          {warning}")
    return 0


def cmd_luminaire_plot(args: argparse.Namespace) -> int:

    lum = load_luminaire(args.file)
    plot_luminaire(lum, args.out)
    print(f"wrote {args.out}")
    return 0


def cmd_luminaire_ugr(args: argparse.Namespace) -> int:
    table = ugr_table(load_luminaire(args.file), args.spacing)
    if args.json:
        json.dump(table.to_json(), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(format_table(table))
    return 0


def add_luminaire_commands(sub: Any) -> None:
    s = sub.add_parser("luminaire", help="photometric files (IES LM-63, EULUMDAT): info and polar plot")
    lsub = s.add_subparsers(dest="luminaire_command", metavar="info|plot|ugr")
    lsub.required = True
    p = lsub.add_parser("info", help="summary: angles, symmetry, lumens declared and integrated, beam angles")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--json", action="store_true", help="the summary as JSON")
    p.set_defaults(func=cmd_luminaire_info)
    p = lsub.add_parser("plot", help="polar intensity plot (PNG)")
    p.add_argument("file", metavar="FILE")
    add_output(p, "--out", required=True, metavar="PNG", extensions=(".png",), help="the PNG to write")
    p.set_defaults(func=cmd_luminaire_plot)
    p = lsub.add_parser("ugr", help="the UGR table by the tabular method (CIE 117 formula, CIE 190 standard rooms)")
    p.add_argument("file", metavar="FILE")
    p.add_argument(
        "--spacing",
        type=number(0, 2, above=True),
        default=1.0,
        help="luminaire spacing in H (CIE 190: 1.0; CIE 117's table: 0.25)",
    )
    p.add_argument("--json", action="store_true", help="the table as JSON")
    p.set_defaults(func=cmd_luminaire_ugr)
