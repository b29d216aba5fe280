"""The `patina render`, `patina preview` and `patina illuminance` commands (registered by cli.py).

Outputs (docs/render.md, "Outputs"): `--out X.exr` writes the float EXR (beauty, AOVs,
metadata) and a tone-mapped PNG beside it (`--png FILE` elsewhere, `--png none` not at all);
`--out X.png` / `.jpg` writes only that tone-mapped image (`--exr FILE` adds the EXR). An
existing output is refused without `--force`; every output path is checked before the work
starts. Ctrl-C and SIGTERM: see render/run.py and docs/render.md, "Interruption".
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import signal
import sys
import threading
from collections.abc import Iterator
from functools import cache
from typing import Any

import numpy as np

from patina.batch.render_tiles import render_on_dask
from patina.batch.scheduling import IN_PROCESS, check_scheduler, connect, dashboard, dask_available
from patina.bundled import studio_environment
from patina.cli.common import add_simd_option
from patina.cli.files import add_input, add_output, check_outputs
from patina.cli.values import integer, number, number_or, numbers
from patina.colour_constants import luminance
from patina.errors import FormatError
from patina.geometry.mesh import load_mesh
from patina.lighting.sensors import parse_sensor
from patina.native import _core
from patina.render import illuminance as il
from patina.render.cache_memory import cache_memory_notice
from patina.render.images import read_image
from patina.render.outputs import auto_exposure, metadata, write_outputs
from patina.render.prepare import PreparedScene, check_render_memory
from patina.render.run import RenderAborted, render
from patina.scene.preview import preview_scene_dict
from patina.scene.reading import (
    AA_SAMPLERS,
    CACHE_INTEGER_KEYS,
    CACHE_RANGES,
    INTEGRATORS,
    MAX_EXPOSURE,
    MAX_IMAGE_SIDE,
    MAX_SEED,
    MAX_SPP,
    MAX_THREADS,
    SAMPLERS,
    check_run_options,
    load_scene,
    parse_scene,
    with_overrides,
)
from patina.scene.types import CacheParams, Scene
from patina.signals import terminate_as_interrupt
from patina.table.formats.loading import split_side

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg")  # tone-mapped 8-bit sRGB
PREVIEW_SHAPES = ("ball", "sphere", "panel")
# preview under another map: auto exposure when its level is this many stops from the studio's
AUTO_EXPOSURE_STOPS = 2.0
# illuminance: grid coordinates and height, metres either way; float32 keeps 8 mm steps out here
MAX_COORDINATE_M = 1e5
MAX_GRID_SIDE = 4096  # sensors along a side, as render/illuminance.py's parse_grid allows
MAX_WORKERS = 1024


# ---------------------------------------------------------------- options


def _command_line(option: str, problem: str) -> FormatError:
    return FormatError("command line", option, problem)


def _outputs(args: argparse.Namespace) -> tuple[str | None, str | None]:
    """(EXR path or None, tone-mapped image path or None) from --out, --png and --exr."""
    base, ext = os.path.splitext(args.out)
    ext = ext.lower()
    if args.png not in (None, "none") and os.path.splitext(args.png)[1].lower() not in IMAGE_EXTENSIONS:
        raise _command_line("--png", f"expected a .png or .jpg file (or none), got '{args.png}'")
    if args.exr is not None and os.path.splitext(args.exr)[1].lower() != ".exr":
        raise _command_line("--exr", f"expected a .exr file, got '{args.exr}'")
    if ext == ".exr":
        if args.exr is not None:
            raise _command_line("--exr", "--out is already the EXR; --exr goes with a .png or .jpg --out")
        return args.out, None if args.png == "none" else (args.png or base + ".png")
    if ext in IMAGE_EXTENSIONS:
        if args.png is not None:
            raise _command_line("--png", "--out is already the tone-mapped image; --exr FILE adds the float EXR")
        return args.exr, args.out
    raise _command_line("--out", f"expected a .exr, .png or .jpg file, got '{args.out}'")


def _image_size(scene: Scene, width: int | None, height: int | None) -> tuple[int | None, int | None]:
    """--width or --height alone keeps the scene's aspect (the other side follows, rounded)."""
    aspect = scene.camera.width / scene.camera.height
    if width is not None and height is None and width >= 1:
        height = max(1, round(width / aspect))
    elif height is not None and width is None and height >= 1:
        width = max(1, round(height * aspect))
    return width, height


def _with_options(scene: Scene, args: argparse.Namespace) -> Scene:
    check_run_options(threads=args.threads, exposure=args.exposure)  # ranges, before any work
    width, height = _image_size(scene, args.width, args.height)
    return with_overrides(
        scene,
        spp=args.spp,
        integrator=args.integrator,
        seed=args.seed,
        width=width,
        height=height,
        aa=args.aa,
        aa_threshold=args.aa_threshold,
        indirect_illuminance=True if args.indirect_illuminance else None,
        sampler=args.sampler,
        **{f"cache_{key}": getattr(args, f"cache_{key}") for key in CACHE_RANGES},
    )


def _on_dask(args: argparse.Namespace) -> bool:
    """--scheduler ADDRESS or --workers N: the render's tiles as Dask tasks (patina.batch.render_tiles)."""
    return args.workers is not None or args.scheduler not in (None, IN_PROCESS)


def _check_cluster_options(args: argparse.Namespace) -> None:
    """--scheduler and --workers, before the scene is read; the address is tried later (connect)."""
    check_scheduler(args.scheduler)
    if args.workers is not None:
        if args.scheduler is not None:
            raise _command_line("--workers", "sets the size of the local cluster; a --scheduler has its own workers")
    if _on_dask(args):
        if args.threads:
            raise _command_line("--threads", "a distributed render runs a task a worker thread; the workers set them")
        if not dask_available():
            raise _command_line(
                "--scheduler" if args.scheduler else "--workers",
                "Dask distributed is not installed (pip install .[cluster])",
            )


@contextlib.contextmanager
def _dask_client(args: argparse.Namespace) -> Iterator[Any]:
    """None for a render on this machine's threads; else a Dask client, connected before the
    scene is prepared, so an unreachable scheduler is told within seconds."""
    if not _on_dask(args):
        yield None
        return
    with connect(args.scheduler, args.workers) as (client, what):
        print(f"rendering on {what}; dashboard: {dashboard(client)}", flush=True)
        yield client


# ---------------------------------------------------------------- signals


@contextlib.contextmanager
def deferred_interrupts() -> Iterator[list[int]]:
    """Ctrl-C and SIGTERM wait while the outputs are written, so each file is finished (and
    the set of them whole) before the command stops; the list holds the signals that came."""
    came: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield came
        return

    def note(signum: int, frame: Any) -> None:
        came.append(signum)

    previous = {s: signal.signal(s, note) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield came
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


# ---------------------------------------------------------------- exposure


def _environment_level(path: str) -> float:
    """Mean luminance of a lat-long map over the sphere (rows weighted by their solid angle)."""
    y = luminance(read_image(path))
    rows = y.shape[0]
    weight = np.cos((np.arange(rows) + 0.5) / rows * np.pi - np.pi / 2)
    return float((y.mean(axis=1) * weight).sum() / weight.sum())


@cache
def _studio_level() -> float:
    return _environment_level(studio_environment())


def preview_exposure(env: str | None) -> str:
    """The preview's default exposure: 0 stops under the studio (what its materials are judged
    by) and under maps within AUTO_EXPOSURE_STOPS of its level; auto (the rendered image's
    log-average to 0.18) under a map brighter or darker than that, such as a sunny sky."""
    if env is None:
        return "0"
    level = _environment_level(env)
    if level <= 0:
        return "auto"
    return "auto" if abs(math.log2(level / _studio_level())) > AUTO_EXPOSURE_STOPS else "0"


# ---------------------------------------------------------------- commands


def _render_and_write(scene: Any, args: argparse.Namespace, exposure_choice: str) -> int:
    exr, image = _outputs(args)
    check_render_memory(scene)
    notice = cache_memory_notice(scene, args.threads)
    if notice:
        print(notice, file=sys.stderr)
    with _dask_client(args) as client:
        prepared = PreparedScene(scene)
        print(
            f"rendering {scene.camera.width}x{scene.camera.height}, {scene.render.spp} spp, "
            f"{scene.render.integrator}, {prepared.triangles} triangles "
            "(Ctrl-C stops after the first pass keeping the passes done; twice aborts)",
            flush=True,
        )
        progress = not args.quiet
        try:
            if client is None:
                result = render(scene, threads=args.threads, simd=args.simd, progress=progress, prepared=prepared)
            else:
                result = render_on_dask(scene, client, simd=args.simd, progress=progress, prepared=prepared)
        except RenderAborted:
            print("patina: interrupted twice: the render was aborted, nothing written", file=sys.stderr)
            return 130
    exposure = auto_exposure(result.rgb) if exposure_choice == "auto" else float(exposure_choice)
    with deferred_interrupts() as came:
        for path in (exr, image):
            if path:
                os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        write_outputs(scene, result, exr, image, exposure=exposure, curve=args.tonemap)
    rate = result.rays / max(result.seconds, 1e-9) / 1e6
    state = "complete" if result.complete else f"PARTIAL (at least {int(result.samples.min())} of {result.spp} spp)"
    print(
        f"rendered {scene.camera.width}x{scene.camera.height}, {result.spp} spp, {state}: "
        f"{result.seconds:.2f} s, {rate:.2f} Mrays/s, SIMD width {result.simd_width}, {result.threads} "
        + ("Dask worker threads" if _on_dask(args) else "threads")
    )
    if result.cache_queries:
        texels = max(result.cache_texels_reprojected + result.cache_texels_traced, 1)
        print(
            f"radiance cache: {result.cache_points} cache points for {result.cache_queries} first hits, "
            f"{100 * result.cache_texels_reprojected / texels:.1f} % of their texels reprojected"
        )
    if result.aa_level is not None:
        meta = metadata(scene, result)
        print(
            f"adaptive antialiasing: {meta['patina:aa_rays_per_pixel']:.2f} camera rays per pixel, pixels at "
            + ", ".join(f"level {k} {100 * float(meta[f'patina:aa_level{k}_fraction']):.1f} %" for k in (1, 2, 3))
        )
    shown = f" at {exposure:+.2f} stops" if exposure_choice == "auto" else ""
    print("wrote " + " and ".join(p for p in (exr, image) if p) + shown)
    if came:
        print("patina: interrupted while writing: the outputs were finished first", file=sys.stderr)
        return 130
    if result.interrupted:
        return 130
    if not (result.rgb == result.rgb).all():
        print("patina: error: the image has NaN pixels", file=sys.stderr)
        return 1
    return 0


def _check_outputs(args: argparse.Namespace) -> None:
    """The outputs --out implies (the PNG beside an EXR), before the scene is read."""
    exr, image = _outputs(args)
    named = [(exr, "--exr" if args.exr else "--out"), (image, "--png" if args.png else "--out")]
    check_outputs([(path, option) for path, option in named if path], args.force)


def cmd_render(args: argparse.Namespace) -> int:
    with terminate_as_interrupt():
        _check_outputs(args)  # option errors before the scene is read
        _check_cluster_options(args)
        scene = _with_options(load_scene(args.scene), args)
        return _render_and_write(scene, args, args.exposure or "0")


def cmd_preview(args: argparse.Namespace) -> int:
    with terminate_as_interrupt():
        _check_outputs(args)
        _check_cluster_options(args)
        if not os.path.isfile(split_side(args.material)[0]):  # FILE.xml#back names a side
            raise FormatError(args.material, "MATERIAL", "no such file")
        exposure = args.exposure or preview_exposure(args.env)
        env = args.env or studio_environment()
        obj = preview_scene_dict(args.material, env, args.shape, args.coat)
        with _named_as_given(args):
            scene = parse_scene(obj, os.path.join(os.getcwd(), "preview.json"))
            return _render_and_write(_with_options(scene, args), args, exposure)


@contextlib.contextmanager
def _named_as_given(args: argparse.Namespace) -> Iterator[None]:
    """A FormatError about a file of the preview (its scene is made up, its paths absolute) is
    told under the path the user gave and the option that gave it."""
    given = {"materials.material": ("MATERIAL", args.material), "environment": ("--env", args.env)}
    if args.shape not in PREVIEW_SHAPES:
        given["shapes[0]"] = ("--shape", args.shape)
    try:
        yield
    except FormatError as e:
        for key, (option, path) in given.items():
            if not path:
                continue
            problem = e.problem.replace(os.path.abspath(path), path)
            if e.where.startswith(key):  # the scene's key that names the file
                raise FormatError(path, option, problem) from None
            if e.path == os.path.abspath(path):  # the file's own reader, at a place inside it
                raise FormatError(path, f"{option}, {e.where}" if e.where else option, problem) from None
        raise


def cmd_illuminance(args: argparse.Namespace) -> int:
    with terminate_as_interrupt():
        grid = il.parse_grid(args.grid, args.height, args.facing)
        if args.sensor is not None:
            parse_sensor(args.sensor)  # before any work
        check_run_options(threads=args.threads)
        scene = load_scene(args.scene)
        report = il.compute(
            scene,
            grid,
            samples=args.samples,
            threads=args.threads,
            width=args.simd,
            progress=True,
            indirect=args.indirect,
            sensor=args.sensor,
            indirect_cache=args.indirect_cache,
        )
        if args.json:
            json.dump(report.as_json(), sys.stdout)
            sys.stdout.write("\n")
        else:
            print(il.summary(report, args.scene))
        with deferred_interrupts() as came:
            for path, write in ((args.csv, il.write_csv), (args.json_out, il.write_json)):
                if path:
                    write(report, path)
            if args.png:
                il.write_png(report, args.png, os.path.basename(args.scene), scene)
        return 130 if came else 0


def _output_options(s: argparse.ArgumentParser, default_out: str, exposure_help: str) -> None:
    add_output(
        s,
        "--out",
        default=default_out,
        metavar="FILE",
        help="X.exr: the float EXR with AOVs (and a PNG beside it); X.png or X.jpg: only the tone-mapped image",
    )
    add_output(
        s,
        "--png",
        default=None,
        metavar="FILE",
        skip=("none",),
        help="with an EXR --out: the tone-mapped image (.png or .jpg; default: beside the EXR; none: skip)",
    )
    add_output(s, "--exr", default=None, metavar="FILE", help="with a .png/.jpg --out: also write the float EXR here")
    s.add_argument("--exposure", type=number_or("auto", -MAX_EXPOSURE, MAX_EXPOSURE), default=None, help=exposure_help)
    s.add_argument("--tonemap", choices=("filmic", "clamp"), default="filmic", help="tone curve of the PNG/JPEG")
    s.add_argument("--spp", type=integer(1, MAX_SPP), default=None, help="samples per pixel (default: the scene's)")
    s.add_argument(
        "--integrator",
        default=None,
        choices=INTEGRATORS,
        metavar="|".join(INTEGRATORS),
        help="the integrator (default: the scene's); cache and cache-guided: docs/radiance-cache.md",
    )
    defaults = CacheParams()
    for key, (lo, hi) in CACHE_RANGES.items():
        what = getattr(_core.CacheSettings, key).__doc__  # the renderer's field, documented once
        whole = key in CACHE_INTEGER_KEYS
        s.add_argument(
            f"--cache-{key.replace('_', '-')}",
            type=integer(int(lo), int(hi)) if whole else number(lo, hi),
            default=None,
            metavar="R" if whole else "X",
            help=f"{what}, {lo:g} to {hi:g} (default: the scene's render.cache.{key}, {getattr(defaults, key):g})",
        )
    s.add_argument("--seed", type=integer(0, MAX_SEED), default=None, help="random seed (default: the scene's)")
    s.add_argument(
        "--aa",
        default=None,
        choices=AA_SAMPLERS,
        metavar="|".join(AA_SAMPLERS),
        help="the pixel sampler (default: the scene's render.aa)",
    )
    s.add_argument(
        "--aa-threshold",
        type=number(0, 1),
        default=None,
        metavar="T",
        help="the adaptive sampler's contrast threshold in [0, 1] (default: the scene's, 0.15)",
    )
    s.add_argument(
        "--sampler",
        default=None,
        choices=SAMPLERS,
        metavar="|".join(SAMPLERS),
        help="the paths' random numbers: Owen-scrambled Sobol or independent (default: the scene's render.sampler)",
    )
    s.add_argument(
        "--width",
        type=integer(1, MAX_IMAGE_SIDE),
        default=None,
        help="image width in pixels (default: the scene's; alone: keeps the aspect)",
    )
    s.add_argument(
        "--height",
        type=integer(1, MAX_IMAGE_SIDE),
        default=None,
        help="image height in pixels (default: the scene's; alone: keeps the aspect)",
    )
    s.add_argument(
        "--indirect-illuminance",
        action="store_true",
        help="the illuminance AOV also counts light reflected by the scene (default: the scene's "
        "render.indirect_illuminance; slower: one more path per sample)",
    )
    s.add_argument("--threads", type=integer(0, MAX_THREADS), default=0, help="worker threads (0: all cores)")
    s.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="render the tiles on a running Dask scheduler's workers (tcp://host:8786); the same image bit "
        f"for bit ({IN_PROCESS}: on this machine's threads, as without it)",
    )
    s.add_argument(
        "--workers",
        type=integer(1, MAX_WORKERS),
        default=None,
        metavar="N",
        help="render the tiles on a local Dask cluster of N processes",
    )
    add_simd_option(s)
    s.add_argument("--quiet", action="store_true", help="no progress display")


def add_preview_object_options(s: argparse.ArgumentParser) -> None:
    """--env and --shape, of `patina preview` and `patina batch`: each file opened before any work."""
    add_input(
        s,
        "--env",
        default=None,
        metavar="MAP",
        read=read_image,
        help="lat-long EXR/HDR environment map (default: the bundled studio)",
    )
    add_input(
        s,
        "--shape",
        default="ball",
        read=load_mesh,
        keywords=PREVIEW_SHAPES,
        what="mesh file",
        help=f"one of {', '.join(PREVIEW_SHAPES)}, or a mesh file (.obj, .ply, .stl, .gltf, .glb)",
    )


def add_render_commands(sub: Any) -> None:
    s = sub.add_parser("render", help="render a scene file (docs/scene.md) to EXR + PNG, or to a PNG/JPEG")
    s.add_argument("scene", metavar="SCENE_JSON", help="a scene file (docs/scene.md)")
    _output_options(s, "render.exr", "exposure of the PNG/JPEG in stops, or auto (default: 0)")
    s.set_defaults(func=cmd_render)

    s = sub.add_parser("preview", help="render a material (table, RGL .bsdf or fit.json) on a preview object")
    s.add_argument("material", metavar="MATERIAL", help="a BRDF table, an RGL .bsdf (rendered natively) or a fit.json")
    add_preview_object_options(s)
    s.add_argument("--coat", action="store_true", help="put a smooth clear coat (eta 1.5) over the material")
    _output_options(
        s,
        "preview.exr",
        "exposure of the PNG/JPEG in stops, or auto (default: 0 under the studio; auto under an --env map "
        f"more than {AUTO_EXPOSURE_STOPS:g} stops brighter or darker than the studio)",
    )
    s.set_defaults(func=cmd_preview)

    s = sub.add_parser(
        "illuminance",
        help="illuminance (lux) on a grid of sensors, with uniformity: direct, or with interreflections (--indirect)",
    )
    s.add_argument("scene", metavar="SCENE_JSON", help="a scene file (docs/scene.md)")
    coordinate = number(-MAX_COORDINATE_M, MAX_COORDINATE_M)
    s.add_argument(
        "--grid",
        required=True,
        type=numbers((coordinate,) * 4 + (integer(1, MAX_GRID_SIDE),) * 2, "X0,Z0,X1,Z1,NX,NZ"),
        metavar="X0,Z0,X1,Z1,NX,NZ",
        help="sensors on a horizontal grid: corners in metres, counts; --grid -3.5,-15,3.5,15,8,31 or --grid=...",
    )
    s.add_argument("--height", type=coordinate, default=0.0, help="the grid's height y (m)")
    s.add_argument("--facing", choices=("up", "down"), default="up", help="the sensors' facing")
    s.add_argument(
        "--sensor",
        default=None,
        metavar="KIND",
        help="what the sensors measure instead of --facing: up, down, vertical:AZ, cylindrical or "
        "semicylindrical:AZ (AZ degrees from +x towards +z; EN 13201-3 cylinders: point, spot and goniometric "
        "luminaires only)",
    )
    s.add_argument("--samples", type=integer(1, il.MAX_SAMPLES), default=256, help="light samples per sensor")
    s.add_argument(
        "--indirect",
        action="store_true",
        help="also count light reflected by the scene (interreflections): as many sensor paths per sensor, "
        "at most the scene's render.max_depth segments each (its path setting, whatever render.integrator says)",
    )
    s.add_argument(
        "--indirect-cache",
        action="store_true",
        help="with --indirect: the interreflections from the radiance cache (cache points at some sensors, "
        "16 x 16 paths each, the others gathering from them; biased: docs/lighting.md) instead of sensor paths",
    )
    s.add_argument("--threads", type=integer(0, MAX_THREADS), default=0, help="worker threads (0: all cores)")
    add_simd_option(s)
    s.add_argument("--json", action="store_true", help="print the report as JSON")
    add_output(s, "--json-out", default=None, metavar="FILE", extensions=(".json",), help="also write the JSON report")
    add_output(s, "--csv", default=None, metavar="FILE", extensions=(".csv",), help="also write x, y, z, lux rows")
    add_output(s, "--png", default=None, metavar="FILE", extensions=(".png",), help="a false-colour map")
    s.set_defaults(func=cmd_illuminance)
