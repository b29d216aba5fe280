"""Options that name files, checked before a command does any work (docs/cli.md).

A command declares them with `add_output` (a file or folder it writes) and `add_input` (a
file an option reads, with the reader that opens it); `patina.cli.main` calls `check_files`
on the parsed arguments before the command runs. So on every command:

- an output that exists is refused without `--force` (which `add_output` adds), and an output
  that cannot be written is refused, before the inputs are read;
- a file an option names is opened and read by the reader the command will use, so
  `--env /etc/passwd` or a broken `--shape` mesh ends at once, not after every task's fit;
- each message names the path as the user gave it (and the option where it helps): `out.png:
  exists; pass --force to overwrite it`, `/etc/passwd (--env, file name): extension ...`.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from patina.atomic import check_writable
from patina.errors import FormatError


@dataclass(frozen=True)
class Output:
    dest: str
    shown: str  # the option (--out) or the positional's metavar (OUTPUT)
    folder: tuple[str, ...]  # a folder output: the names it writes in it; () a file output
    updates: str  # a folder output a rerun updates: the file that marks an earlier run's folder ("" none)
    extensions: tuple[str, ...]  # allowed, lower case with the dot; () any
    skip: tuple[str, ...]  # values that are not paths ("none")


@dataclass(frozen=True)
class Input:
    dest: str
    shown: str
    read: Callable[[str], Any]  # opens and reads the file; FormatError (or OSError) when it cannot
    keywords: tuple[str, ...]  # values that are not files (--shape ball)
    what: str  # the kind of file, for a message: "mesh file"


def _shown(action: argparse.Action) -> str:
    return action.option_strings[0] if action.option_strings else str(action.metavar or action.dest).upper()


def _declare(s: argparse.ArgumentParser, key: str, spec: Output | Input) -> None:
    s.set_defaults(**{key: (s.get_default(key) or ()) + (spec,)})


def add_output(
    s: argparse.ArgumentParser,
    *names: str,
    folder: Iterable[str] = (),
    updates: str = "",
    extensions: Iterable[str] = (),
    skip: Iterable[str] = (),
    **kwargs: Any,
) -> argparse.Action:
    """An output option (or positional); the command gains `--force`. A file, or with `folder`
    (the names the command writes in it) a folder; with `updates` (the file an earlier run
    leaves there) a folder the command updates (`patina batch`)."""
    action = s.add_argument(*names, **kwargs)
    spec = Output(action.dest, _shown(action), tuple(folder), updates, tuple(extensions), tuple(skip))
    _declare(s, "_outputs", spec)
    if "--force" not in s._option_string_actions:
        s.add_argument("--force", action="store_true", help="overwrite existing outputs (refused without it)")
    return action


def add_input(
    s: argparse.ArgumentParser,
    *names: str,
    read: Callable[[str], Any],
    keywords: Iterable[str] = (),
    what: str = "file",
    **kwargs: Any,
) -> argparse.Action:
    """An option naming a file the command reads (or one of `keywords`): `read(path)` is tried
    before the command runs."""
    action = s.add_argument(*names, **kwargs)
    _declare(s, "_inputs", Input(action.dest, _shown(action), read, tuple(keywords), what))
    return action


def _values(args: argparse.Namespace, dest: str) -> list[str]:
    value = getattr(args, dest, None)
    if value is None:
        return []
    return [str(v) for v in value] if isinstance(value, list) else [str(value)]


def check_output(path: str, shown: str, force: bool, spec: Output | None = None) -> None:
    """One output, before any work: its extension, its existence (without --force), writable."""
    if spec and spec.extensions and os.path.splitext(path)[1].lower() not in spec.extensions:
        raise FormatError(path, shown, f"expected a {' or '.join(spec.extensions)} file")
    if not (spec and spec.folder):
        if not force and os.path.lexists(path):
            raise FormatError(path, "", "exists; pass --force to overwrite it")
        check_writable(path)
        return
    if force or not os.path.isdir(path):
        return  # a folder that cannot be made is the command's to report, when it makes it
    if spec.updates and os.path.exists(os.path.join(path, spec.updates)):
        return  # an earlier run's folder, which this run updates
    taken = [name for name in spec.folder if os.path.lexists(os.path.join(path, name))]
    if taken:
        raise FormatError(path, shown, f"holds {taken[0]}; pass --force to overwrite it")


def check_outputs(paths: list[tuple[str, str]], force: bool) -> None:
    """[(path, option)]: each output as check_output, and no two the same file."""
    for path, shown in paths:
        check_output(path, shown, force)
    _distinct(paths)


def _distinct(paths: list[tuple[str, str]]) -> None:
    seen: dict[str, str] = {}
    for path, shown in paths:
        same = seen.setdefault(os.path.abspath(path), shown)
        if same != shown:
            raise FormatError(path, shown, f"is also the output of {same}; give them different names")


def check_files(args: argparse.Namespace) -> None:
    """Every declared output and input of the parsed command, before it runs."""
    force = bool(getattr(args, "force", False))
    outputs = []
    for spec in getattr(args, "_outputs", ()):
        for path in _values(args, spec.dest):
            if path not in spec.skip:
                check_output(path, spec.shown, force, spec)
                outputs.append((path, spec.shown))
    _distinct(outputs)
    for spec in getattr(args, "_inputs", ()):
        for path in _values(args, spec.dest):
            if path not in spec.keywords:
                _try_reading(spec, path)


def _try_reading(spec: Input, path: str) -> None:
    if spec.keywords and not os.path.lexists(path):
        named = f"one of {', '.join(spec.keywords)} nor a {spec.what}"
        raise FormatError("command line", spec.shown, f"'{path}' is not {named}")
    try:
        spec.read(path)
    except FormatError as e:
        where = f"{spec.shown}, {e.where}" if e.where else spec.shown
        problem = e.problem.replace(os.path.abspath(path), path)
        raise FormatError(path, where, problem) from None
    except OSError as e:
        raise FormatError(path, spec.shown, e.strerror or str(e)) from None
