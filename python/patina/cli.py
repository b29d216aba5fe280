"""The `patina` command.

    patina info FILE [--json]
    patina convert IN OUT.ptab
    patina eval FILE --wi THETA PHI --wo THETA PHI [--json] [--width 1|4|8]
    patina validate FILE [--json]          (exit 0 clean, 1 problems found, 2 unreadable)
    patina fit FILE [--model ggx+lambert] [--lobes K] [--loss l2cos|log] [--out fit.json]
               [--coat [--coat-eta 1.5 | --fit-coat-eta]] [--per-channel] [--anisotropic]
    patina fit FILE --compare ggx+lambert beckmann+lambert lafortune+lambert:2 ward-aniso+lambert
    patina plot FILE [--fit fit.json] --out DIR [--no-3d] [--3d-log] [--3d-no-cos]
    patina slices FILE --out PNG
    patina bench [--only GROUP] [--json FILE]
    patina render SCENE.json [--out out.exr] [--spp N] [--integrator direct|path] [--threads T] [--seed S]
    patina luminaire info FILE [--json] | patina luminaire plot FILE --out PNG
    patina preview MATERIAL [--env ENV] [--shape sphere|ball|panel|MESH] [--spp N] [--out out.exr]

Bad input ends with one line naming the file, the place and the problem, and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any

import numpy as np

from .errors import FormatError


class UsageError(Exception):
    """A bad option value: reported like argparse does, exit status 2."""


def _print_json(obj: Any) -> None:
    json.dump(obj, sys.stdout, indent=2)
    sys.stdout.write("\n")


def _channel_labels(brdf: Any) -> list[str]:
    kind = brdf.channel_kind
    if kind == "rgb":
        return ["R", "G", "B"]
    if kind == "xyz":
        return ["X", "Y", "Z"]
    if kind == "spectral":
        return [f"{w:g}nm" for w in brdf.wavelengths]
    return ["value"]


def cmd_info(args: argparse.Namespace) -> int:
    from . import load_brdf

    brdf = load_brdf(args.file)
    info = brdf.info()
    if args.json:
        _print_json(info)
        return 0
    print(f"{info['source']}  ({info['format']})")
    print(
        f"  parametrization  {info['parametrization']}"
        + (f"  symmetry: {', '.join(info['symmetry'])}" if info["symmetry"] else "")
    )
    for a in info["axes"]:
        spacing = "uniform" if a["uniform"] else f"irregular, steps {a['min_step_deg']:.3g}-{a['max_step_deg']:.3g} deg"
        print(f"  {a['name']:<8} {a['knots']:>5} knots  {a['min_deg']:8.3f} .. {a['max_deg']:8.3f} deg  ({spacing})")
    labels = _channel_labels(brdf)
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
    from . import load_brdf

    if not args.output.endswith(".ptab"):
        raise UsageError(f"convert: {args.output}: the output must be a .ptab file")
    brdf = load_brdf(args.input)
    brdf.save(args.output)
    print(
        f"wrote {args.output} ({brdf.parametrization}, {'x'.join(str(a.size) for a in brdf.axes)}, "
        f"{brdf.channels} channels)"
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
    from . import load_brdf

    ti, pi = _angle_pair("--wi", args.wi)
    to, po = _angle_pair("--wo", args.wo)
    brdf = load_brdf(args.file)
    values = brdf.eval_angles(*np.radians([ti, pi, to, po]), width=args.width)
    labels = _channel_labels(brdf)
    if args.json:
        _print_json(
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
    from . import load_brdf
    from .plots import plot_inplane_slices

    brdf = load_brdf(args.file)
    plot_inplane_slices(brdf, args.out, incidence_deg=args.incidence)
    print(f"wrote {args.out}")
    return 0


def cmd_validate(args: argparse.Namespace) -> int:
    from . import load_brdf
    from .validation import Tolerances, format_report, validate

    brdf = load_brdf(args.file)
    report = validate(brdf, Tolerances(spike_factor=args.spike_factor, albedo_excess=args.albedo_tolerance))
    if args.json:
        _print_json(report.as_json())
    else:
        print(format_report(report))
    return 0 if report.ok else 1


def _model_options(args: argparse.Namespace) -> dict[str, Any]:
    """The fit options --compare shares with a single fit."""
    if (args.coat_eta is not None or args.fit_coat_eta) and not args.coat:
        raise UsageError("fit: --coat-eta and --fit-coat-eta need --coat")
    if args.coat_eta is not None and args.fit_coat_eta:
        raise UsageError("fit: give --coat-eta (a held index) or --fit-coat-eta (a fitted one), not both")
    options: dict[str, Any] = {"loss": args.loss, "coat": args.coat, "per_channel": args.per_channel}
    if args.coat_eta is not None:
        options["coat_eta"] = args.coat_eta
    if args.fit_coat_eta:
        options["fit_coat_eta"] = True
    if args.anisotropic:
        options["anisotropic"] = True
    return options


def cmd_fit(args: argparse.Namespace) -> int:
    from . import load_brdf
    from .fitting import compare, fit, write_fit

    if args.starts < 1:
        raise UsageError("fit: --starts must be at least 1")
    brdf = load_brdf(args.file)
    if args.compare:
        results = compare(brdf, args.compare, starts=args.starts, seed=args.seed, **_model_options(args))
        if args.json:
            _print_json([r.as_json() for r in results])
        else:
            print(f"{len(results)} models fitted to {args.file} (loss {args.loss}), best first:")
            print(f"  {'model':<24} {'loss':>10} {'rmse':>10} {'rel.err':>8} {'dE00':>6} {'dE00 95%':>8} {'time s':>7}")
            for r in results:
                m = r.metrics
                print(
                    f"  {r.model:<24} {m['loss_all_samples']:10.4g} {m['rmse']:10.4g} "
                    f"{m['relative_error_median']:8.3g} {m['ciede2000_mean']:6.2f} {m['ciede2000_p95']:8.2f} "
                    f"{r.seconds:7.1f}"
                )
                print("      " + ", ".join(f"{k} {v:.4g}" for k, v in r.parameters.items()))
                if not r.converged:
                    print(f"      not converged: {r.message}")
        if args.out:
            write_fit(results[0], args.out)
        return 0 if all(r.converged for r in results) else 1
    result = fit(brdf, model=args.model, lobes=args.lobes, starts=args.starts, seed=args.seed, **_model_options(args))
    if args.out:
        write_fit(result, args.out)
    if args.json:
        _print_json(result.as_json())
    else:
        print(
            f"{result.model} fitted to {args.file} ({result.samples} samples, loss {result.loss}) "
            f"in {result.seconds:.2f} s: {result.message}"
        )
        for name, value in result.parameters.items():
            print(f"  {name:<10} {value:.6g}" + ("   (at its bound)" if name in result.at_bounds else ""))
        m = result.metrics
        print(
            f"  loss {m['loss_all_samples']:.4g}  rmse {m['rmse']:.4g}  relative error median "
            f"{m['relative_error_median']:.3g}, 95% {m['relative_error_p95']:.3g}  "
            f"CIEDE2000 mean {m['ciede2000_mean']:.2f}, 95% {m['ciede2000_p95']:.2f}"
        )
        if args.out:
            print(f"wrote {args.out}")
    return 0 if result.converged else 1


def cmd_plot(args: argparse.Namespace) -> int:
    from . import load_brdf
    from .fitting import read_fit
    from .lobe3d import LobeOptions
    from .report import write_report

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


def cmd_bench(args: argparse.Namespace) -> int:
    from .bench import run_bench

    return run_bench(only=args.only, json_path=args.json, repeat=args.repeat, quick=args.quick)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="patina", description="Measured-material appearance workbench.")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    s = sub.add_parser("info", help="summarise a BRDF table")
    s.add_argument("file")
    s.add_argument("--json", action="store_true", help="machine-readable output")
    s.set_defaults(func=cmd_info)

    s = sub.add_parser("convert", help="convert any supported table to .ptab")
    s.add_argument("input")
    s.add_argument("output")
    s.set_defaults(func=cmd_convert)

    s = sub.add_parser("eval", help="evaluate a table at one direction pair (degrees)")
    s.add_argument("file")
    s.add_argument("--wi", nargs=2, type=float, required=True, metavar=("THETA", "PHI"))
    s.add_argument("--wo", nargs=2, type=float, required=True, metavar=("THETA", "PHI"))
    s.add_argument("--json", action="store_true")
    s.add_argument("--width", type=int, choices=(1, 4, 8), default=None, help="force a SIMD path")
    s.set_defaults(func=cmd_eval)

    s = sub.add_parser("validate", help="check a table: values, axes, coverage, reciprocity, albedo, spikes")
    s.add_argument("file")
    s.add_argument("--json", action="store_true", help="machine-readable report")
    s.add_argument("--spike-factor", type=float, default=5.0, help="a spike is this many times off every neighbour")
    s.add_argument("--albedo-tolerance", type=float, default=0.02, help="albedo may exceed 1 by this much")
    s.set_defaults(func=cmd_validate)

    s = sub.add_parser("fit", help="fit an analytic model to a table (nlopt)")
    s.add_argument("file")
    s.add_argument(
        "--model",
        default="ggx+lambert",
        help="ggx, beckmann, blinnphong, ward, ashikhmin, ward-aniso, ashikhmin-aniso or lafortune + lambert",
    )
    s.add_argument("--lobes", type=int, default=1, help="specular lobes, 1 to 3")
    s.add_argument("--coat", action="store_true", help="add a clear coat (roughness; index of refraction held)")
    s.add_argument("--coat-eta", type=float, default=None, metavar="ETA", help="the coat's held index (default 1.5)")
    s.add_argument("--fit-coat-eta", action="store_true", help="fit the coat's index too (weakly identified)")
    s.add_argument(
        "--anisotropic", action="store_true", help="lafortune: Cx and Cy apart (default: on anisotropic tables)"
    )
    s.add_argument("--per-channel", action="store_true", help="a lobe shape per colour channel (default: shared)")
    s.add_argument("--compare", nargs="+", metavar="MODEL", help="fit several models (MODEL or MODEL:LOBES), rank them")
    s.add_argument("--loss", default="l2cos", choices=("l2cos", "log"))
    s.add_argument("--starts", type=int, default=4, help="local optimisations from this many starts")
    s.add_argument("--seed", type=int, default=0)
    s.add_argument("--out", default=None, metavar="FIT_JSON", help="write the result as JSON")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_fit)

    s = sub.add_parser("plot", help="figures and index.html: slices, polar plots, 3-D lobes, validation, a fit")
    s.add_argument("file")
    s.add_argument("--fit", default=None, metavar="FIT_JSON", help="overlay a model written by patina fit --out")
    s.add_argument("--out", required=True, metavar="DIR")
    s.add_argument("--no-3d", action="store_true", help="leave out the 3-D lobe view (pyvista)")
    s.add_argument("--3d-log", dest="lobe_log", action="store_true", help="3-D lobes on a log radius (3 decades)")
    s.add_argument("--3d-no-cos", dest="lobe_no_cos", action="store_true", help="3-D lobes of f, not f cos(theta_o)")
    s.set_defaults(func=cmd_plot)

    s = sub.add_parser("slices", help="plot in-plane slices of a table to a PNG")
    s.add_argument("file")
    s.add_argument("--out", required=True)
    s.add_argument("--incidence", type=float, nargs="+", default=[0, 20, 40, 60, 75], metavar="DEG")
    s.set_defaults(func=cmd_slices)

    s = sub.add_parser("bench", help="measure kernel speed (ratios against baselines in the same run)")
    s.add_argument("--only", default=None, help="a group: math, brdf, fit, trace, render, lights (default: all)")
    s.add_argument("--json", default=None, metavar="FILE", help="also write the records as JSON")
    s.add_argument("--repeat", type=int, default=7, help="repetitions; medians are reported")
    s.add_argument("--quick", action="store_true", help="small inputs, for a smoke test")
    s.set_defaults(func=cmd_bench)

    from .cli_render import add_render_commands

    add_render_commands(sub)
    from .cli_luminaire import add_luminaire_commands

    add_luminaire_commands(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        from . import __version__

        print(f"patina {__version__}")
        return 0
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except UsageError as e:
        print(f"patina {e}", file=sys.stderr)
        return 2
    except FormatError as e:
        print(f"patina: error: {e}", file=sys.stderr)
        return 2
    except (ValueError, OSError) as e:
        print(f"patina: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("patina: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
