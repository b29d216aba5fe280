"""`patina fit`: one model, or several compared and ranked."""

from __future__ import annotations

import argparse
from typing import Any

from patina.cli.common import UsageError, print_json
from patina.cli.files import add_output
from patina.cli.values import integer, number
from patina.fitting import FitResult, compare, fit, parse_accept, recommended, write_fit, write_ranking
from patina.fitting.verdict import LABELS, Check
from patina.table import load_brdf


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
    if args.accept is not None:
        try:
            options["accept"] = parse_accept(args.accept)
        except ValueError as e:
            raise UsageError(f"fit: --accept: {e}") from None
    return options


def verdict_lines(r: FitResult, indent: str = "  ") -> list[str]:
    """The verdict and the numbers that decided it, each with its threshold."""
    head = "usable" if r.usable else "NOT USABLE"
    lines = [f"{indent}verdict: {head} (thresholds: --accept KEY=VALUE,... to change them)"]
    for c in r.verdict:
        mark = "ok  " if c["passed"] else "FAIL"
        lines.append(f"{indent}  {mark} {LABELS[c['metric']]:<30} {c['value']:8.3g}  threshold {c['threshold']:g}")
    decided = {Check(c["metric"], c["value"], c["threshold"]).describe() for c in r.verdict}
    others = [p for p in r.problems if p not in decided]  # the symmetry, the albedo bound, the loss
    lines += [f"{indent}  FAIL {p}" for p in others]
    return lines


def _print_ranking(path: str, loss: str, results: list[FitResult]) -> None:
    print(f"{len(results)} models fitted to {path} (loss {loss}), best first:")
    print(f"  {'model':<24} {'loss':>10} {'rmse':>10} {'rel.err':>8} {'dE00':>6} {'dE00 95%':>8} {'time s':>7}")
    for r in results:
        m = r.metrics
        print(
            f"  {r.model:<24} {m['loss']:10.4g} {m['rmse']:10.4g} "
            f"{m['relative_error_median']:8.3g} {m['ciede2000_mean']:6.2f} {m['ciede2000_p95']:8.2f} "
            f"{r.seconds:7.1f}" + ("" if r.usable else "  UNUSABLE")
        )
        print("      " + ", ".join(f"{k} {v:.4g}" + ("*" if k in r.at_bounds else "") for k, v in r.parameters.items()))
        if r.at_bounds:
            print(f"      * at its bound: {', '.join(r.at_bounds)}")
        if not r.usable:
            print(f"      unusable: {'; '.join(r.problems)}")
        if not r.converged:
            print(f"      not converged: {r.message}")
    best = recommended(results)
    if best is not None:
        print(f"recommended: {best.model} (passes every threshold)")
    else:
        print(f"no fit passes the thresholds; the least bad is {results[0].model}:")
    print("\n".join(verdict_lines(results[0])))


def cmd_fit(args: argparse.Namespace) -> int:
    options = _model_options(args)  # checked before the table is read
    brdf = load_brdf(args.file)
    if args.compare:
        results = compare(brdf, args.compare, progress=not args.json, starts=args.starts, seed=args.seed, **options)
        if args.json:
            print_json([r.as_json() for r in results])
        else:
            _print_ranking(args.file, args.loss, results)
        if args.out:
            write_ranking(results, args.out)
            if not args.json:
                print(f"wrote {args.out} (the best fit, and every model under 'ranking')")
        return 0 if all(r.converged for r in results) and results[0].usable else 1
    result = fit(brdf, model=args.model, lobes=args.lobes, starts=args.starts, seed=args.seed, **options)
    if args.out:
        write_fit(result, args.out)
    if args.json:
        print_json(result.as_json())
    else:
        print(
            f"{result.model} fitted to {args.file} ({result.samples} samples, loss {result.loss}) "
            f"in {result.seconds:.2f} s: {result.message}"
        )
        for name, value in result.parameters.items():
            print(f"  {name:<10} {value:.6g}" + ("   (at its bound)" if name in result.at_bounds else ""))
        m = result.metrics
        print(
            f"  loss {m['loss']:.4g}  rmse {m['rmse']:.4g}  relative error median "
            f"{m['relative_error_median']:.3g}, 95% {m['relative_error_p95']:.3g}  "
            f"CIEDE2000 mean {m['ciede2000_mean']:.2f}, 95% {m['ciede2000_p95']:.2f}"
        )
        print("\n".join(verdict_lines(result)))
        if args.out:
            print(f"wrote {args.out}")
    return 0 if result.converged and result.usable else 1


def add_fit_command(sub: Any) -> None:
    s = sub.add_parser("fit", help="fit an analytic model to a table (nlopt)")
    s.add_argument("file")
    s.add_argument(
        "--model",
        default="ggx+lambert",
        help="a specular lobe over a Lambert diffuse: ggx, beckmann, blinnphong, ward, ashikhmin, ward-aniso, "
        "ashikhmin-aniso or lafortune, each written with or without '+lambert' (ggx means ggx+lambert)",
    )
    s.add_argument("--lobes", type=integer(1, 3), default=1, help="specular lobes, 1 to 3")
    s.add_argument("--coat", action="store_true", help="add a clear coat (roughness; index of refraction held)")
    s.add_argument(
        "--coat-eta",
        type=number(1, 3, above=True),  # 1 is no coat
        default=None,
        metavar="ETA",
        help="the coat's held index, above 1 (default 1.5)",
    )
    s.add_argument("--fit-coat-eta", action="store_true", help="fit the coat's index too (weakly identified)")
    s.add_argument(
        "--anisotropic", action="store_true", help="lafortune: Cx and Cy apart (default: on anisotropic tables)"
    )
    s.add_argument("--per-channel", action="store_true", help="a lobe shape per colour channel (default: shared)")
    s.add_argument(
        "--compare",
        nargs="+",
        metavar="MODEL",
        help="fit several models (MODEL or MODEL:LOBES) and rank them, usable fits first; "
        "flags parameters at their bounds and unusable fits",
    )
    s.add_argument(
        "--loss",
        default="l2cos",
        choices=("l2cos", "log"),
        help="l2cos: squared differences of cosine-weighted values (Ngan et al. 2005); "
        "log: of log(1 + cosine-weighted value), which weighs dim regions more (Low et al. 2012)",
    )
    s.add_argument(
        "--starts",
        type=integer(1, 64),
        default=4,
        help="local optimisations (BOBYQA): from the global stage's best, the rest random",
    )
    # numpy's and nlopt's seeds are unsigned
    s.add_argument(
        "--seed",
        type=integer(0, 2**63 - 1),
        default=0,
        help="seed of the random subsamples and starts (same seed, same fit)",
    )
    add_output(
        s,
        "--out",
        default=None,
        metavar="FIT_JSON",
        extensions=(".json",),
        help="write the result as JSON (with --compare: the best fit, and every model under 'ranking')",
    )
    s.add_argument(
        "--accept",
        default=None,
        metavar="KEY=VALUE[,...]",
        help="the largest errors a usable fit may have (docs/fitting.md): relative_error_median (0.2), "
        "ciede2000_mean (3), ciede2000_p95 (8), cosine_relative_rmse (0.25)",
    )
    s.add_argument("--json", action="store_true", help="machine-readable output")
    s.set_defaults(func=cmd_fit)
