"""The table commands: `patina info`, `convert`, `eval`, `validate`, `slices`."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from patina.cli.common import UsageError, add_simd_option, channel_labels, print_json
from patina.cli.files import add_output
from patina.cli.values import number
from patina.export.rgl import table_source, write_rgl_file
from patina.file_names import printable, refuse_special_file
from patina.plot.slices import plot_inplane_slices
from patina.table import Tolerances, format_report, load_brdf, validate
from patina.table.formats.lenient import read_reporting_bad_values


def cmd_info(args: argparse.Namespace) -> int:
    refuse_special_file(args.file)  # a FIFO: at once, not a wait for a writer
    brdf = load_brdf(args.file)
    info = brdf.info()
    if args.json:
        print_json(info)
        return 0
    print(f"{info['source']}  ({info['format']})")
    print(
        f"  parametrization  {info['parametrization']}"
        + (f"  symmetry: {', '.join(info['symmetry'])}" if info["symmetry"] else "")
    )
    for a in info["axes"]:
        spacing = "uniform" if a["uniform"] else f"irregular, steps {a['min_step_deg']:.3g}-{a['max_step_deg']:.3g} deg"
        print(f"  {a['name']:<8} {a['knots']:>5} knots  {a['min_deg']:8.3f} .. {a['max_deg']:8.3f} deg  ({spacing})")
    labels = channel_labels(brdf)
    shown = ", ".join(labels) if len(labels) <= 8 else f"{labels[0]} .. {labels[-1]}"
    print(f"  channels         {info['channels']} {info['channel_kind']} ({shown})")
    print(f"  grid points      {info['grid_points']}  missing: {info['missing_points']}")
    if info["value_max"]:
        rng = ", ".join(f"{lo:.4g}..{hi:.4g}" for lo, hi in zip(info["value_min"][:3], info["value_max"][:3]))
        print(f"  values           {rng} {info['units']}" + (" (first 3 channels)" if info["channels"] > 3 else ""))
    if info["provenance"]:
        print(f"  provenance       {info['provenance']}")
    return 0


def cmd_convert(args: argparse.Namespace) -> int:

    brdf = load_brdf(args.input)
    if args.output.lower().endswith(".bsdf"):
        return _convert_to_rgl(brdf, args)
    if args.channels:
        raise UsageError("convert: --channels is for an RGL .bsdf output")
    brdf.save(args.output)
    print(
        f"wrote {printable(args.output)} ({brdf.parametrization}, {'x'.join(str(a.size) for a in brdf.axes)}, "
        f"{brdf.channels} channels)"
    )
    return 0


def _convert_to_rgl(brdf: Any, args: argparse.Namespace) -> int:
    report = write_rgl_file(table_source(brdf, args.input), args.output, args.channels or "spectral", progress=True)
    err = report["read_back_error"]
    kind = "isotropic" if report["isotropic"] else "anisotropic"
    channels = " and ".join(report["channels"]) + (f" from {report['spectra_from']}" if report["spectra_from"] else "")
    print(f"wrote {args.output} (RGL tensor file, {kind}, {report['incident_angles']} incident directions, {channels})")
    print(
        f"  read back against {args.input} at {err['pairs']} direction pairs: relative error median "
        f"{err['relative_error_median']:.3g}, 95% {err['relative_error_p95']:.3g}"
    )
    return 0


def _angle_pair(name: str, values: list[float]) -> tuple[float, float]:
    theta, phi = values
    if not (np.isfinite(theta) and np.isfinite(phi)):
        raise UsageError(f"eval: {name} angles must be finite numbers")
    if not 0.0 <= theta <= 90.0:
        raise UsageError(f"eval: {name} theta={theta:g} deg is outside [0, 90]")
    return theta, phi


def cmd_eval(args: argparse.Namespace) -> int:

    ti, pi = _angle_pair("--wi", args.wi)
    to, po = _angle_pair("--wo", args.wo)
    brdf = load_brdf(args.file)
    values = brdf.eval_angles(*np.radians([ti, pi, to, po]), width=args.simd)
    labels = channel_labels(brdf)
    if args.json:
        print_json(
            {
                "file": args.file,
                "wi_deg": [ti, pi],
                "wo_deg": [to, po],
                "channel_kind": brdf.channel_kind,
                "channels": labels,
                "values": [float(v) for v in values],
                "units": brdf.info()["units"],
            }
        )
    else:
        print(f"f(wi=({ti:g}, {pi:g}) deg, wo=({to:g}, {po:g}) deg) =")
        for label, v in zip(labels, values):
            print(f"  {label:>8}  {v:.6g}")
    return 0


def cmd_slices(args: argparse.Namespace) -> int:

    brdf = load_brdf(args.file)
    plot_inplane_slices(brdf, args.out, incidence_deg=args.incidence)
    print(f"wrote {args.out}")
    return 0


def cmd_validate(args: argparse.Namespace) -> int:

    # NaN / infinite values are reported (exit 1), not refused as by the other commands
    brdf, bad = read_reporting_bad_values(args.file)
    tolerances = Tolerances(spike_factor=args.spike_factor, albedo_excess=args.albedo_tolerance)
    report = validate(brdf, tolerances, bad)
    if args.json:
        print_json(report.as_json())
    else:
        print(format_report(report))
    return 0 if report.ok else 1


def add_table_commands(sub: Any) -> None:
    s = sub.add_parser("info", help="summarise a BRDF table")
    s.add_argument("file")
    s.add_argument("--json", action="store_true", help="machine-readable output")
    s.set_defaults(func=cmd_info)

    s = sub.add_parser("convert", help="convert any supported table to .ptab or an RGL .bsdf tensor file")
    s.add_argument("input", help="a .ptab, MERL .binary, ASTM E1392, CSV, RGL .bsdf or other table")
    add_output(s, "output", extensions=(".ptab", ".bsdf"), help="the .ptab or .bsdf (RGL tensor file) to write")
    s.add_argument(
        "--channels",
        choices=("spectral", "rgb"),
        help=".bsdf: spectra (default; pbrt-v4, Mitsuba's spectral variants) or RGB (Mitsuba's RGB variants)",
    )
    s.set_defaults(func=cmd_convert)

    s = sub.add_parser("eval", help="evaluate a table at one direction pair (degrees)")
    s.add_argument("file")
    for option, which in (("--wi", "incident"), ("--wo", "outgoing")):
        s.add_argument(
            option,
            nargs=2,
            type=number(-360, 360),
            required=True,
            metavar=("THETA", "PHI"),
            help=f"{which} direction, degrees: theta from the normal (0..90), phi the azimuth",
        )
    s.add_argument("--json", action="store_true", help="machine-readable output")
    add_simd_option(s)
    s.set_defaults(func=cmd_eval)

    s = sub.add_parser("validate", help="check a table: values, axes, coverage, reciprocity, albedo, spikes")
    s.add_argument("file")
    s.add_argument("--json", action="store_true", help="machine-readable report")
    s.add_argument(
        "--spike-factor",
        type=number(1, 1e6, above=True),
        default=5.0,
        help="a spike is this many times (above 1) off every neighbour",
    )
    s.add_argument("--albedo-tolerance", type=number(0, 10), default=0.02, help="albedo may exceed 1 by this much")
    s.set_defaults(func=cmd_validate)

    s = sub.add_parser("slices", help="plot in-plane slices of a table to a PNG")
    s.add_argument("file")
    add_output(s, "--out", required=True, metavar="PNG", extensions=(".png",), help="the PNG to write")
    s.add_argument(
        "--incidence",
        type=number(0, 90),
        nargs="+",
        default=[0, 20, 40, 60, 75],
        metavar="DEG",
        help="incidence angles (theta_i, degrees) of the slices, one curve each",
    )
    s.set_defaults(func=cmd_slices)
