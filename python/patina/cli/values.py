"""Option value types that say what is allowed: `type=integer(1, 1024)`, `type=number(0, 1)`.

Python's int() and float() accept more than a user means ('1_0', ' 8', a full-width digit,
'nan', '1e999' as inf), and argparse then reports "invalid int value" without the range. These
read plain ASCII numbers only, check the range at parse time (before any work), and a bad
value's message names what is allowed: `--workers: expected a whole number from 1 to 1024, got
'abc'`. Every numeric option of every command uses them (tests/python/cli/test_every_option.py
checks that, and their messages, on the parser tree itself).
"""

from __future__ import annotations

import argparse
import math
import re
from dataclasses import dataclass

_INTEGER = re.compile(r"[+-]?[0-9]+")
_NUMBER = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


def _shown(bound: float) -> str:
    if bound == 2**63 - 1:
        return "2^63-1"
    if isinstance(bound, int) and bound >= 1 << 20 and bound & (bound - 1) == 0:
        return f"2^{bound.bit_length() - 1}"
    return f"{bound:g}"


@dataclass(frozen=True)
class integer:
    """A whole number in [lo, hi]."""

    lo: int
    hi: int

    @property
    def allowed(self) -> str:
        return f"a whole number from {_shown(self.lo)} to {_shown(self.hi)}"

    def __call__(self, text: str) -> int:
        if not (_INTEGER.fullmatch(text) and self.lo <= int(text) <= self.hi):
            raise argparse.ArgumentTypeError(f"expected {self.allowed}, got '{text}'")
        return int(text)


@dataclass(frozen=True)
class number:
    """A finite decimal number in [lo, hi] (in (lo, hi] when `above`: --coat-eta above 1)."""

    lo: float
    hi: float
    above: bool = False

    @property
    def allowed(self) -> str:
        if self.above:
            return f"a number above {_shown(self.lo)}, at most {_shown(self.hi)}"
        return f"a number from {_shown(self.lo)} to {_shown(self.hi)}"

    def __call__(self, text: str) -> float:
        value = float(text) if _NUMBER.fullmatch(text) else math.nan
        low_ok = value > self.lo if self.above else value >= self.lo
        if not (math.isfinite(value) and low_ok and value <= self.hi):
            raise argparse.ArgumentTypeError(f"expected {self.allowed}, got '{text}'")
        return value


@dataclass(frozen=True)
class numbers:
    """Comma-separated values, each read by its own type: `numbers((number(..),) * 4 + (integer(..),) * 2)`."""

    parts: tuple[integer | number, ...]
    form: str  # as the user writes it: X0,Z0,X1,Z1,NX,NZ

    @property
    def allowed(self) -> str:
        return f"{self.form}: " + ", ".join(p.allowed for p in self.parts)

    def __call__(self, text: str) -> str:
        words = text.split(",")
        if len(words) != len(self.parts):
            raise argparse.ArgumentTypeError(f"expected {self.form} ({len(self.parts)} values), got '{text}'")
        for name, word, part in zip(self.form.split(","), words, self.parts):
            try:
                part(word)
            except argparse.ArgumentTypeError:
                raise argparse.ArgumentTypeError(f"{name}: expected {part.allowed}, got '{word}'") from None
        return text


@dataclass(frozen=True)
class number_or:
    """A word (`auto`) or a number in [lo, hi]; the value stays a string."""

    word: str
    lo: float
    hi: float

    @property
    def allowed(self) -> str:
        return f"{number(self.lo, self.hi).allowed}, or {self.word}"

    def __call__(self, text: str) -> str:
        if text != self.word:
            try:
                number(self.lo, self.hi)(text)
            except argparse.ArgumentTypeError:
                raise argparse.ArgumentTypeError(f"expected {self.allowed}, got '{text}'") from None
        return text
