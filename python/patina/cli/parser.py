"""The argument parser every `patina` command and subcommand is built on (docs/cli.md).

Subparsers made through `add_subparsers` are of the parent's class, so a command added by
`sub.add_parser(...)` anywhere in patina.cli follows these rules without asking:

- no abbreviated options (`--sp 4` is not `--spp 4`): an unknown option is refused, naming
  the options it may have meant;
- a bad command line ends with one line, `patina CMD: error: command line (--option): problem`
  (the form of every option error, also those found after parsing), and exit status 2, never
  the whole usage;
- a value that starts with '-' and then a digit, '.', 'inf' or 'nan' is a value, so the range
  check names the option (`--cache-error -inf` is not "expected one argument").
"""

from __future__ import annotations

import argparse
import difflib
import re
from collections.abc import Sequence
from typing import Any, NoReturn

from patina.cli.common import HelpFormat

# argparse takes any word starting with '-' for an option unless it matches this; its own
# pattern knows neither '-inf', '-nan' nor '-3.5,-15,...' (illuminance --grid).
NEGATIVE_VALUE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


class PatinaParser(argparse.ArgumentParser):
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("allow_abbrev", False)
        kwargs.setdefault("formatter_class", HelpFormat)
        super().__init__(*args, **kwargs)
        # no patina option looks like a negative number, so such a word is always a value
        self._negative_number_matcher = NEGATIVE_VALUE

    def error(self, message: str) -> NoReturn:
        """One line, the command named, exit status 2 (argparse prints the usage first)."""
        message = " ".join(message.split())  # one line, whatever argparse or a type function wrote
        place = re.match(r"^(?:argument )?(-[^:\s]+|[A-Z_]+(?:/-[^:\s]+)?): ", message)
        if place:
            message = f"command line ({place.group(1)}): {message[place.end() :]}"
        else:
            message = f"command line: {message}"
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        """Unknown words are refused by the parser that met them, which knows its own options."""
        namespace, extras = super().parse_known_args(args, namespace)
        if extras:
            self.error(self._unknown(extras[0]))
        return namespace, extras

    def _unknown(self, word: str) -> str:
        if not word.startswith("-") or NEGATIVE_VALUE.match(word):
            return f"unexpected argument '{word}' (see {self.prog} --help)"
        name = word.split("=", 1)[0]
        options = sorted(s for s in self._option_string_actions if s.startswith("--"))
        near = [s for s in options if s.startswith(name)] or difflib.get_close_matches(name, options, n=3)
        hint = f"did you mean {' or '.join(near)}?" if near else f"see {self.prog} --help"
        return f"{name}: no such option ({hint}; options are never abbreviated)"  # error() places the name
