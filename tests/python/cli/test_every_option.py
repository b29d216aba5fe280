"""The command-line rules of docs/cli.md, checked on every command and option of the parser
tree itself: a command added tomorrow (`patina export`, `patina lighting ...`) is walked too.

For every command: its parsers take no abbreviations; a bad value of any option is one line
naming the option and what is allowed (exit 2, no usage); every numeric option has a stated
range; an existing output is refused without --force before any input is read; a file an
option names is opened before any work, and the message names the path the user gave.
"""

from __future__ import annotations

import argparse
import os
import re

import pytest

from patina.cli import build_parser, main
from patina.cli.parser import PatinaParser
from patina.cli.values import integer, number, number_or, numbers

MISSING = "missing-input"  # a positional's value: the checks here come before any input is read
# Words a value type must refuse whatever its range: Python's int()/float() take the first four.
NOT_NUMBERS = ["1_0", " 8", "\uff18", "8 ", "abc", "", "0x10", "1e999", "-inf", "nan", "inf", "+-1", "1e"]


def _walk(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(command words, parser) of every parser in the tree, the top one included."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, child in action.choices.items():
                yield from _walk(child, (*path, name))


def _is_leaf(parser: argparse.ArgumentParser) -> bool:
    return not any(isinstance(a, argparse._SubParsersAction) for a in parser._actions)


PARSERS = list(_walk(build_parser()))
COMMANDS = {" ".join(path): parser for path, parser in PARSERS if path and _is_leaf(parser)}
OPTIONS = [
    (name, action)
    for name, parser in COMMANDS.items()
    for action in parser._actions
    if action.option_strings and action.type is not None
]
CHOICES = [
    (name, action) for name, parser in COMMANDS.items() for action in parser._actions if action.choices is not None
]


def _id(item) -> str:
    name, action = item
    return f"{name} {action.option_strings[0] if action.option_strings else action.dest}"


def _example(kind) -> str:
    """A value the type takes."""
    if isinstance(kind, (integer, number)):
        return f"{kind.lo:g}" if isinstance(kind, number) else str(kind.lo)
    if isinstance(kind, number_or):
        return kind.word
    if isinstance(kind, numbers):
        return ",".join(_example(part) for part in kind.parts)
    raise AssertionError(f"no example for {kind!r}: give this value type a case in _example")


def _positionals(parser: argparse.ArgumentParser, given: dict[str, list[str]]) -> list[str]:
    words: list[str] = []
    for action in parser._actions:
        if not action.option_strings and not isinstance(action, argparse._SubParsersAction):
            count = action.nargs if isinstance(action.nargs, int) else 1
            words += given.get(action.dest, [MISSING] * count)
    return words


def _required(parser: argparse.ArgumentParser, given: dict[str, list[str]]) -> list[str]:
    """Each required option with a value it takes (or the one given)."""
    words: list[str] = []
    for action in parser._actions:
        if action.option_strings and action.required and action.dest not in given:
            count = action.nargs if isinstance(action.nargs, int) else 1
            value = str(action.choices[0]) if action.choices else _example(action.type) if action.type else "x"
            words += [action.option_strings[0], *[value] * count]
    for dest, values in given.items():
        option = next((a for a in parser._actions if a.dest == dest and a.option_strings), None)
        if option is not None:
            words += [option.option_strings[0], *values]
    return words


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "usage:" not in err and "Traceback" not in err, err
    return lines[0]


def test_the_tree_has_every_command():
    """The walk sees the subcommands of subcommands (luminaire info / plot) and every leaf."""
    assert {"render", "preview", "illuminance", "fit", "batch", "luminaire info", "luminaire plot"} <= set(COMMANDS)


@pytest.mark.parametrize("path", [" ".join(p) or "patina" for p, _ in PARSERS])
def test_every_parser_refuses_abbreviations(path):
    parser = dict((" ".join(p) or "patina", q) for p, q in PARSERS)[path]
    assert isinstance(parser, PatinaParser) and parser.allow_abbrev is False


@pytest.mark.parametrize("item", [(n, a) for n, p in COMMANDS.items() for a in p._actions if a.option_strings], ids=_id)
def test_an_abbreviated_option_is_refused_naming_the_option_meant(item, capsys):
    name, action = item
    option = max(action.option_strings, key=len)
    if not option.startswith("--") or len(option) < 5:
        pytest.skip("a short option has no shorter form")
    cut = option[:-1]
    if cut in COMMANDS[name]._option_string_actions:
        pytest.skip(f"{cut} is an option of its own")
    parser = COMMANDS[name]
    code = main([*name.split(), *_positionals(parser, {}), *_required(parser, {}), cut])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and f"patina {name}: error: command line ({cut}): no such option" in line, line
    assert option in line, line


@pytest.mark.parametrize("item", OPTIONS, ids=_id)
def test_every_typed_option_states_what_it_allows(item):
    """No bare int or float: a value type that range-checks and says what is allowed."""
    _, action = item
    assert hasattr(action.type, "allowed"), f"{action.type!r}: use a type of patina.cli.values"


@pytest.mark.parametrize("item", OPTIONS, ids=_id)
def test_a_bad_number_is_one_line_naming_the_option_and_what_is_allowed(item, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    name, action = item
    count = action.nargs if isinstance(action.nargs, int) else 1
    kind = action.type
    too_big = [str(kind.hi + 1) if isinstance(kind.hi, int) else f"{kind.hi * 2 + 1:g}"] if hasattr(kind, "hi") else []
    option = action.option_strings[0]
    for bad in NOT_NUMBERS + too_big:
        if count == 1:
            words = [f"{option}={bad}"]
        elif bad.strip() in ("", "--"):
            continue  # as a word of its own, the end of the options or nothing, not a value
        else:
            words = [option, bad, *[_example(kind)] * (count - 1)]
        code = main([*name.split(), *_positionals(COMMANDS[name], {}), *words])
        line = _one_line(capsys.readouterr().err)
        assert code == 2, (option, bad)
        assert f"patina {name}: error: command line ({option}): " in line and "expected" in line, line
        assert os.listdir(tmp_path) == [], "a refused command wrote something"
    if isinstance(kind, (integer, number)):
        assert kind.allowed in line  # the range, stated


@pytest.mark.parametrize("item", CHOICES, ids=_id)
def test_a_bad_choice_is_one_line_listing_the_choices(item, capsys):
    name, action = item
    if not action.option_strings:
        pytest.skip("a positional")
    bad = "nonsense"
    if isinstance(action.type, integer):  # a number of the type's range that is not a choice
        bad = str(next(v for v in range(action.type.lo, action.type.hi + 1) if v not in action.choices))
    code = main([*name.split(), *_positionals(COMMANDS[name], {}), action.option_strings[0], bad])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and f"({action.option_strings[0]}): invalid choice: " in line
    assert all(str(choice) in line for choice in action.choices), line


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_help_lists_the_options(name, capsys):
    with pytest.raises(SystemExit) as e:
        main([*name.split(), "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert all(o in out for a in COMMANDS[name]._actions for o in a.option_strings)


OUTPUTS = [(name, spec) for name, parser in COMMANDS.items() for spec in parser.get_default("_outputs") or ()]
# names that say "a file this command writes": such an option not declared with add_output
# would overwrite without --force (as fit, convert, slices and plot did)
OUTPUT_NAMES = re.compile(r"--(out|output|.*-out|png|exr|csv|jpg|json-file)$|^output$")


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_option_named_like_an_output_is_declared_one(name):
    parser = COMMANDS[name]
    declared = {spec.dest for spec in parser.get_default("_outputs") or ()}
    for action in parser._actions:
        names = action.option_strings or [action.dest]
        if action.nargs != 0 and any(OUTPUT_NAMES.match(n) for n in names):
            assert action.dest in declared, f"patina {name} {names[0]}: declare it with add_output"


def _taken(tmp_path, spec) -> tuple[str, str]:
    """An output path that exists already, and what it holds."""
    if not spec.folder:
        path = tmp_path / f"taken{spec.extensions[0] if spec.extensions else '.png'}"
        path.write_text("keep me")
        return str(path), "keep me"
    path = tmp_path / "taken"
    path.mkdir()
    (path / spec.folder[0]).write_text("keep me")  # what the command would write there
    return str(path), "keep me"


@pytest.mark.parametrize("item", OUTPUTS, ids=lambda i: f"{i[0]} {i[1].shown}")
def test_an_existing_output_is_refused_without_force_before_any_input_is_read(item, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    name, spec = item
    parser = COMMANDS[name]
    assert "--force" in parser._option_string_actions
    path, held = _taken(tmp_path, spec)
    given = {spec.dest: [path]}
    code = main([*name.split(), *_positionals(parser, given), *_required(parser, given)])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and line.startswith(f"patina: error: {path}") and "pass --force" in line, line
    assert MISSING not in line  # refused before the input was looked at
    inside = os.path.join(path, spec.folder[0]) if spec.folder else path
    with open(inside) as f:
        assert f.read() == held
    if spec.updates:  # an earlier run's folder is updated, not refused: the command goes on to its input
        (tmp_path / "taken" / spec.updates).write_text("{}")
        assert main([*name.split(), *_positionals(parser, given), *_required(parser, given)]) == 2
        assert MISSING in _one_line(capsys.readouterr().err)


INPUTS = [(name, spec) for name, parser in COMMANDS.items() for spec in parser.get_default("_inputs") or ()]


@pytest.mark.parametrize("item", INPUTS, ids=lambda i: f"{i[0]} {i[1].shown}")
def test_a_file_an_option_names_is_opened_before_any_work(item, tmp_path, monkeypatch, capsys):
    """`batch --env /etc/passwd`: refused at once, naming the option and the path as given."""
    monkeypatch.chdir(tmp_path)
    name, spec = item
    parser = COMMANDS[name]
    for given_path, content in (("passwd", "root:x:0:0:root:/root:/bin/bash\n"), ("broken.obj", "v 0 0\nf 1 2 9\n")):
        (tmp_path / given_path).write_text(content)
        given = {spec.dest: [given_path]}
        code = main([*name.split(), *_positionals(parser, given), *_required(parser, given)])
        line = _one_line(capsys.readouterr().err)
        assert code == 2 and line.startswith(f"patina: error: {given_path} ({spec.shown}"), line
        assert str(tmp_path) not in line  # the path as the user wrote it, not a made-up or absolute one
    given = {spec.dest: ["no-such-thing"]}
    code = main([*name.split(), *_positionals(parser, given), *_required(parser, given)])
    line = _one_line(capsys.readouterr().err)
    assert code == 2 and "no-such-thing" in line and spec.shown in line, line
