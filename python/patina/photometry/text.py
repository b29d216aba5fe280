"""Text handling shared by the photometric readers: tolerant decoding, 1-based lines and
numbers tagged with the line they stand on, so every error can name its line.

Photometric files come from many tools and decades: Latin-1 or UTF-8 text, CRLF or LF
line ends, numbers separated by spaces, tabs or commas and wrapped over lines at will.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass

from patina.errors import FormatError

MAX_BYTES = 16 * 1024 * 1024  # photometric files are kilobytes; refuse anything absurd before reading it

_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?")
_SEPARATORS = re.compile(r"[\s,]+")


def read_lines(path: str) -> list[str]:
    """The file's lines (without their ends), decoded as UTF-8 if valid, else as Latin-1."""
    try:
        size = os.path.getsize(path)
        if size > MAX_BYTES:
            raise FormatError(path, "", f"is {size} bytes; photometric files are far smaller (limit {MAX_BYTES})")
        with open(path, "rb") as f:
            data = f.read(MAX_BYTES + 1)
    except IsADirectoryError:
        raise FormatError(path, "", "is a directory, not a file") from None
    except FileNotFoundError:
        raise FormatError(path, "", "no such file") from None
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")  # every byte is a Latin-1 character: never fails
    return _LINE_BREAK.split(text)


@dataclass(frozen=True)
class Token:
    text: str
    line: int  # 1-based


def tokens(lines: list[str], first_line: int) -> list[Token]:
    """Whitespace- and comma-separated tokens of lines[first_line - 1:], each with its line number.

    A DOS end-of-file mark (Ctrl-Z) ends the text, as old tools wrote one.
    """
    out: list[Token] = []
    for number in range(first_line, len(lines) + 1):
        line = lines[number - 1]
        stop = line.find("\x1a")
        if stop >= 0:
            line = line[:stop]
        out.extend(Token(t, number) for t in _SEPARATORS.split(line) if t)
        if stop >= 0:
            break
    return out


def parse_number(path: str, text: str, line: int, what: str) -> float:
    """A finite decimal number (a Fortran-style D exponent is accepted), else FormatError."""
    if not _NUMBER.fullmatch(text):
        raise FormatError(path, f"line {line}", f"{what}: {_show(text)} is not a number")
    value = float(text.replace("d", "e").replace("D", "e"))
    if not math.isfinite(value):
        raise FormatError(path, f"line {line}", f"{what}: {_show(text)} is out of range")
    return value


def parse_int(path: str, text: str, line: int, what: str) -> int:
    """An integer, written as one or as a number with an integral value (`2.0`), else FormatError."""
    value = parse_number(path, text, line, what)
    if value != int(value):
        raise FormatError(path, f"line {line}", f"{what}: {_show(text)} is not a whole number")
    return int(value)


def _show(text: str) -> str:
    shown = text if len(text) <= 24 else text[:21] + "..."
    return repr(shown)


class TokenStream:
    """Reads numbers off a token list, naming the line of each problem; counts are checked
    against what remains before anything is allocated."""

    def __init__(self, path: str, toks: list[Token], last_line: int) -> None:
        self.path = path
        self.toks = toks
        self.pos = 0
        self.last_line = last_line

    @property
    def remaining(self) -> int:
        return len(self.toks) - self.pos

    @property
    def line(self) -> int:
        """The line of the next token (or of the file's end)."""
        return self.toks[self.pos].line if self.pos < len(self.toks) else self.last_line

    def _next(self, what: str) -> Token:
        if self.pos >= len(self.toks):
            raise FormatError(self.path, f"line {self.last_line}", f"the file ends where {what} should follow")
        tok = self.toks[self.pos]
        self.pos += 1
        return tok

    def number(self, what: str) -> float:
        tok = self._next(what)
        return parse_number(self.path, tok.text, tok.line, what)

    def integer(self, what: str) -> int:
        tok = self._next(what)
        return parse_int(self.path, tok.text, tok.line, what)

    def require(self, count: int, what: str) -> None:
        """FormatError unless at least `count` tokens remain (checked before allocating)."""
        if count > self.remaining:
            end = self.toks[-1].line if self.toks else self.last_line  # where the numbers run out
            raise FormatError(
                self.path,
                f"line {end}",
                f"{what}: the header declares {count} values but only {self.remaining} numbers follow",
            )

    def numbers(self, count: int, what: str) -> tuple[list[float], list[int]]:
        """`count` numbers and the line of each."""
        self.require(count, what)
        toks = self.toks[self.pos : self.pos + count]
        self.pos += count
        return [parse_number(self.path, t.text, t.line, what) for t in toks], [t.line for t in toks]

    def expect_end(self, what: str) -> None:
        if self.pos < len(self.toks):
            tok = self.toks[self.pos]
            raise FormatError(
                self.path,
                f"line {tok.line}",
                f"{self.remaining} more values after {what}: the declared counts do not match the numbers present",
            )
