"""The `patina` command.

    patina info FILE [--json]
    patina convert IN OUT.ptab
    patina eval FILE --wi THETA PHI --wo THETA PHI [--json] [--simd 1|4|8]
    patina validate FILE [--json]          (exit 0 clean, 1 problems found, 2 unreadable)
    patina fit FILE [--model ggx+lambert] [--lobes K] [--loss l2cos|log] [--out fit.json]
               [--coat [--coat-eta 1.5 | --fit-coat-eta]] [--per-channel] [--anisotropic]
    patina fit FILE --compare ggx+lambert beckmann+lambert lafortune+lambert:2 ward-aniso+lambert
    patina plot FILE [--fit fit.json] --out DIR [--no-3d] [--3d-log] [--3d-no-cos]
    patina slices FILE --out PNG
    patina bench [--only GROUP] [--json FILE] [--quick | --large] [--quiet]
    patina render SCENE.json [--out out.exr] [--spp N] [--integrator direct|path] [--threads T] [--seed S]
    patina luminaire info FILE [--json] | patina luminaire plot FILE --out PNG
    patina luminaire ugr FILE [--spacing S] [--json]
    patina preview MATERIAL [--env ENV] [--shape sphere|ball|panel|MESH] [--spp N] [--out out.exr]
    patina lighting report PROJECT.json --standard en12464-1|en13201|en12193 --out DIR
    patina export MATERIAL --to mitsuba|pbrt|materialx|gltf|usd|blender --out FILE [--force]

Bad input ends with one line naming the file, the place and the problem, and exit status 2.
`--quiet` (where a command has it) leaves only errors: standard output goes nowhere and
progress is off. Output into a closed pipe (`patina info FILE | head -1`) ends quietly.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys

from patina.cli.batch import add_batch_command
from patina.cli.bench import add_bench_command
from patina.cli.common import UsageError, brief_warnings
from patina.cli.export import add_export_command
from patina.cli.files import check_files
from patina.cli.fit import add_fit_command
from patina.cli.lighting import add_lighting_commands
from patina.cli.luminaire import add_luminaire_commands
from patina.cli.parser import PatinaParser
from patina.cli.plot import add_plot_command
from patina.cli.render import add_render_commands
from patina.cli.table import add_table_commands
from patina.errors import FormatError
from patina.native import _core


def build_parser() -> argparse.ArgumentParser:
    # every subcommand's parser is a PatinaParser too (docs/cli.md: the rules every command follows)
    p = PatinaParser(prog="patina", description="Measured-material appearance workbench.")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    add_table_commands(sub)
    add_fit_command(sub)
    add_export_command(sub)
    add_plot_command(sub)
    add_bench_command(sub)
    add_render_commands(sub)
    add_luminaire_commands(sub)
    add_batch_command(sub)
    add_lighting_commands(sub)
    return p


def _closed_pipe() -> int:
    """The reader of our stdout went away (`| head -1`): not an error. Point stdout at
    /dev/null so the interpreter's last flush does not raise again, and exit as a process
    killed by SIGPIPE would (128 + 13), as other command-line tools do."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    with contextlib.suppress(OSError, ValueError):
        os.dup2(devnull, sys.stdout.fileno())
    os.close(devnull)
    return 141


def main(argv: list[str] | None = None) -> int:
    try:
        try:
            return _run(argv)
        finally:
            # a closed pipe shows at this flush, inside the handler, not at interpreter exit
            # (also after --help, whose SystemExit a BrokenPipeError here replaces)
            sys.stdout.flush()
    except BrokenPipeError:
        return _closed_pipe()


def command() -> int:
    """The `patina` program (and `python -m patina.cli`): main() with this process's arguments,
    then Ctrl-C and SIGTERM ignored while the interpreter exits. The command has decided its
    status by then; Python hands SIGINT back to the system's default action as it finalises
    (a few hundred ms after a Dask render), so a second Ctrl-C that came then -- after the
    first one's partial image was written -- killed the process by the signal instead of letting
    it exit with its status (130). Not in main(): the tests call main() in their own process."""
    status = main()
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, signal.SIG_IGN)
    return status


def _run(argv: list[str] | None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # a bad command line (its one line is printed): the status, as any error's
        if e.code in (0, None):
            raise  # --help
        return int(e.code)
    if args.version:
        print(f"patina {_core.__version__}")
        return 0
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        check_files(args)  # outputs and the files options name, before the command's work
        with brief_warnings():
            if getattr(args, "quiet", False):
                # --quiet: nothing but errors (stderr); the commands turn their progress off themselves
                # errors="replace": a name that is not UTF-8 in a line nobody reads is no failure
                with open(os.devnull, "w", errors="replace") as devnull, contextlib.redirect_stdout(devnull):
                    return int(args.func(args) or 0)
            return int(args.func(args) or 0)
    except BrokenPipeError:
        raise  # an OSError, but not a failure: main() handles it
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
