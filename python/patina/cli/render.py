"""The `patina render`, `patina preview` and `patina illuminance` commands (registered by cli.py)."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any

from patina.bundled import studio_environment
from patina.errors import FormatError
from patina.render import illuminance as il
from patina.render.outputs import auto_exposure, write_outputs
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.preview import preview_scene_dict
from patina.scene.reading import load_scene, parse_scene, with_overrides


def _png_path(exr: str, png: str | None) -> str | None:
    if png == "none":
        return None
    return png or os.path.splitext(exr)[0] + ".png"


def _exposure(value: str) -> str:
    if value != "auto":
        try:
            float(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected stops (a number) or auto, got '{value}'") from None
    return value


def _render_and_write(scene: Any, args: argparse.Namespace) -> int:

    prepared = PreparedScene(scene)
    print(
        f"rendering {scene.camera.width}x{scene.camera.height}, {scene.render.spp} spp, "
        f"{scene.render.integrator}, {prepared.triangles} triangles (Ctrl-C keeps the passes done so far)",
        flush=True,
    )
    result = render(scene, threads=args.threads, simd=args.simd, progress=not args.quiet, prepared=prepared)
    png = _png_path(args.out, args.png)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    exposure = auto_exposure(result.rgb) if args.exposure == "auto" else float(args.exposure)
    write_outputs(scene, result, args.out, png, exposure=exposure, curve=args.tonemap)
    rate = result.rays / max(result.seconds, 1e-9) / 1e6
    state = "complete" if result.complete else f"PARTIAL (at least {int(result.samples.min())} of {result.spp} spp)"
    print(
        f"rendered {scene.camera.width}x{scene.camera.height}, {result.spp} spp, {state}: "
        f"{result.seconds:.2f} s, {rate:.2f} Mrays/s, SIMD width {result.simd_width}, {result.threads} threads"
    )
    print(f"wrote {args.out}" + (f" and {png}" if png else ""))
    if not result.complete:
        return 130
    if not (result.rgb == result.rgb).all():
        print("patina: error: the image has NaN pixels", file=sys.stderr)
        return 1
    return 0


def cmd_render(args: argparse.Namespace) -> int:

    scene = load_scene(args.scene)
    scene = with_overrides(
        scene, spp=args.spp, integrator=args.integrator, seed=args.seed, width=args.width, height=args.height
    )
    return _render_and_write(scene, args)


def cmd_preview(args: argparse.Namespace) -> int:

    for what, path in (("the material to preview", args.material), ("the --env map", args.env)):
        if path is not None and not os.path.isfile(path):
            raise FormatError(path, "", f"no such file ({what})")
    env = args.env or studio_environment()
    obj = preview_scene_dict(args.material, env, args.shape, args.coat)
    scene = parse_scene(obj, os.path.join(os.getcwd(), "(preview)"))
    scene = with_overrides(
        scene, spp=args.spp, integrator=args.integrator, seed=args.seed, width=args.width, height=args.height
    )
    return _render_and_write(scene, args)


def _output_options(s: argparse.ArgumentParser, default_out: str) -> None:
    s.add_argument("--out", default=default_out, metavar="EXR", help=f"float EXR with AOVs (default {default_out})")
    s.add_argument("--png", default=None, metavar="PNG", help="tone-mapped PNG (default: beside the EXR; none: skip)")
    s.add_argument("--exposure", type=_exposure, default="0", help="PNG exposure in stops, or auto")
    s.add_argument("--tonemap", choices=("filmic", "clamp"), default="filmic", help="PNG tone curve")
    s.add_argument("--spp", type=int, default=None, help="samples per pixel")
    s.add_argument("--integrator", choices=("direct", "path"), default=None)
    s.add_argument("--seed", type=int, default=None)
    s.add_argument("--width", type=int, default=None, help="image width in pixels")
    s.add_argument("--height", type=int, default=None, help="image height in pixels")
    s.add_argument("--threads", type=int, default=0, help="worker threads (default: all cores)")
    s.add_argument("--simd", type=int, choices=(1, 4, 8), default=None, help="force a SIMD width")
    s.add_argument("--quiet", action="store_true", help="no progress line")


def cmd_illuminance(args: argparse.Namespace) -> int:

    scene = load_scene(args.scene)
    grid = il.parse_grid(args.grid, args.height, args.facing)
    if args.samples < 1:
        raise ValueError("--samples must be at least 1")
    report = il.compute(scene, grid, samples=args.samples, threads=args.threads, width=args.simd)
    if args.json:
        json.dump(report.as_json(), sys.stdout)
        sys.stdout.write("\n")
    else:
        print(il.summary(report, args.scene))
    for path, write in ((args.csv, il.write_csv), (args.json_out, il.write_json)):
        if path:
            write(report, path)
    if args.png:
        il.write_png(report, args.png, os.path.basename(args.scene))
    return 0


def add_render_commands(sub: Any) -> None:
    s = sub.add_parser("render", help="render a scene file (docs/scene.md) to EXR + PNG")
    s.add_argument("scene", metavar="SCENE_JSON")
    _output_options(s, "render.exr")
    s.set_defaults(func=cmd_render)

    s = sub.add_parser("preview", help="render a material (table or fit.json) on a preview object")
    s.add_argument("material", metavar="MATERIAL")
    s.add_argument("--env", default=None, help="lat-long EXR/HDR environment (default: the bundled studio)")
    s.add_argument("--shape", default="ball", help="sphere, ball, panel or a mesh file")
    s.add_argument("--coat", action="store_true", help="put a smooth clear coat (eta 1.5) over the material")
    _output_options(s, "preview.exr")
    s.set_defaults(func=cmd_preview)

    s = sub.add_parser("illuminance", help="direct illuminance (lux) on a grid of sensors, with uniformity")
    s.add_argument("scene", metavar="SCENE_JSON")
    s.add_argument("--grid", required=True, metavar="X0,Z0,X1,Z1,NX,NZ", help="sensors on a horizontal grid (m)")
    s.add_argument("--height", type=float, default=0.0, help="the grid's height y (m)")
    s.add_argument("--facing", default="up", help="sensors facing up (default) or down")
    s.add_argument("--samples", type=int, default=256, help="light samples per sensor")
    s.add_argument("--threads", type=int, default=0)
    s.add_argument("--simd", type=int, choices=(1, 4, 8), default=None)
    s.add_argument("--json", action="store_true", help="print the report as JSON")
    s.add_argument("--json-out", default=None, metavar="FILE", help="also write the JSON report")
    s.add_argument("--csv", default=None, metavar="FILE", help="also write x, y, z, lux rows")
    s.add_argument("--png", default=None, metavar="FILE", help="a false-colour map")
    s.set_defaults(func=cmd_illuminance)
