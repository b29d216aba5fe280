"""Reading decoded JSON with key paths: every wrong value becomes a FormatError naming where it is.

The scene parser is written against `Obj`, a JSON object being read: it knows its key
path (`materials.paint.coat`), rejects keys nobody asked for (with a did-you-mean
suggestion), reports missing required keys, and reads typed values (finite numbers in a
range, integers, booleans, choices, 3-vectors, RGB triples, existing files). Nothing here
knows what a scene is, so the same reader serves any JSON file Patina reads later.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, NoReturn, TypeVar

from patina.errors import FormatError

T = TypeVar("T")
FLOAT32_MAX = 3.4028234663852886e38
FLOAT32_TINY = 1.1754943508222875e-38  # the smallest normal float32
REQUIRED: Any = object()  # the default that means "this key must be there"


class JsonObject(dict):
    """A decoded JSON object that remembers keys given more than once (json keeps only the last)."""

    duplicates: tuple[str, ...] = ()


def object_pairs(pairs: list[tuple[str, Any]]) -> JsonObject:
    """`json.loads(..., object_pairs_hook=object_pairs)`: duplicates are reported where they are read."""
    obj = JsonObject(pairs)
    if len(obj) != len(pairs):
        seen: set[str] = set()
        repeated = []
        for k, _ in pairs:
            if k in seen:
                repeated.append(k)
            seen.add(k)
        obj.duplicates = tuple(repeated)
    return obj


def key_path(where: str, key: str | int) -> str:
    if isinstance(key, int):
        return f"{where}[{key}]"
    return f"{where}.{key}" if where else key


def describe(value: Any) -> str:
    """What a JSON value is, for 'must be X, got Y' messages."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, (int, float)):
        return f"a number ({value!r})" if len(repr(value)) < 40 else "a number"
    if isinstance(value, str):
        return f"a string ({value[:30]!r})"
    if isinstance(value, list):
        return f"an array of {len(value)}"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def suggestion(word: str, options: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


@dataclass(frozen=True)
class Ctx:
    """The file being read (named in every error) and the directory its relative paths start from."""

    file: str
    base: str

    def fail(self, where: str, problem: str) -> NoReturn:
        raise FormatError(self.file, where, problem)


# --- single values ------------------------------------------------------------------------


def _in_range(ctx: Ctx, where: str, x: float, lo: float | None, hi: float | None, lo_open: bool, hi_open: bool) -> None:
    below = lo is not None and (x <= lo if lo_open else x < lo)
    above = hi is not None and (x >= hi if hi_open else x > hi)
    if below or above:
        left = "" if lo is None else ("(" if lo_open else "[") + f"{lo:g}"
        right = "" if hi is None else f"{hi:g}" + (")" if hi_open else "]")
        if lo is None:
            wanted = f"{'<' if hi_open else '<='} {hi:g}"
        elif hi is None:
            wanted = f"{'>' if lo_open else '>='} {lo:g}"
        else:
            wanted = f"in {left}, {right}"
        ctx.fail(where, f"must be {wanted}, got {x:g}")


def number(
    ctx: Ctx,
    where: str,
    value: Any,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
    hi_open: bool = False,
) -> float:
    """A finite JSON number as a float, inside [lo, hi] (either end open or absent)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        ctx.fail(where, f"must be a number, got {describe(value)}")
    try:
        x = float(value)
    except OverflowError:
        ctx.fail(where, "is too large to be a number")
    if not math.isfinite(x):
        ctx.fail(where, f"must be finite, got {x}")
    _in_range(ctx, where, x, lo, hi, lo_open, hi_open)
    # the renderer computes in 32-bit floats: beyond their range a legal JSON number would
    # become inf, and a positive one below their smallest normal would become 0 or lose precision
    if abs(x) > FLOAT32_MAX:
        ctx.fail(where, f"{x:g} is beyond the renderer's 32-bit float range (+-{FLOAT32_MAX:.3g})")
    if lo == 0.0 and lo_open and x < FLOAT32_TINY:
        ctx.fail(where, f"{x:g} is too small for the renderer's 32-bit floats (it must be >= {FLOAT32_TINY:.3g})")
    return x


def integer(ctx: Ctx, where: str, value: Any, lo: int | None = None, hi: int | None = None) -> int:
    """A JSON integer (not 2.0, not true) inside [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, int):
        ctx.fail(where, f"must be an integer, got {describe(value)}")
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        shown = f"{value}" if abs(value) < 10**30 else "a huge integer"
        if hi is None:
            ctx.fail(where, f"must be an integer >= {lo}, got {shown}")
        ctx.fail(where, f"must be an integer in [{lo}, {hi}], got {shown}")
    return int(value)


def boolean(ctx: Ctx, where: str, value: Any) -> bool:
    if not isinstance(value, bool):
        ctx.fail(where, f"must be true or false, got {describe(value)}")
    return value


def string(ctx: Ctx, where: str, value: Any) -> str:
    if not isinstance(value, str):
        ctx.fail(where, f"must be a string, got {describe(value)}")
    return value


def choice(ctx: Ctx, where: str, value: Any, options: Sequence[str]) -> str:
    s = string(ctx, where, value)
    if s not in options:
        known = ", ".join(f"'{o}'" for o in options)
        ctx.fail(where, f"unknown value '{s[:40]}'{suggestion(s, options)}; expected one of {known}")
    return s


def array(ctx: Ctx, where: str, value: Any, length: int | None = None) -> list[Any]:
    if not isinstance(value, list):
        wanted = f"an array of {length}" if length is not None else "an array"
        ctx.fail(where, f"must be {wanted}, got {describe(value)}")
    if length is not None and len(value) != length:
        ctx.fail(where, f"must be an array of {length}, got {len(value)} elements")
    return value


def vector(ctx: Ctx, where: str, value: Any, n: int = 3, **limits: Any) -> tuple[float, ...]:
    items = array(ctx, where, value, n)
    return tuple(number(ctx, key_path(where, i), v, **limits) for i, v in enumerate(items))


def rgb(ctx: Ctx, where: str, value: Any, **limits: Any) -> tuple[float, float, float]:
    """[r, g, b], or one number meaning grey."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        x = number(ctx, where, value, **limits)
        return (x, x, x)
    if not isinstance(value, list):
        ctx.fail(where, f"must be [r, g, b] or one number (grey), got {describe(value)}")
    r, g, b = vector(ctx, where, value, 3, **limits)
    return (r, g, b)


def existing_file(ctx: Ctx, where: str, value: Any, suffixes: Sequence[str] | None = None) -> str:
    """A path, relative to the scene file's directory unless absolute, of a regular file that exists."""
    s = string(ctx, where, value)
    if not s or "\x00" in s:
        ctx.fail(where, "must be a file name")
    path = os.path.normpath(os.path.join(ctx.base, s))
    if suffixes is not None and os.path.splitext(path)[1].lower() not in suffixes:
        ctx.fail(where, f"'{s}' is not one of the file kinds read here ({', '.join(suffixes)})")
    try:
        exists, regular = os.path.exists(path), os.path.isfile(path)
    except (OSError, ValueError):
        exists = regular = False
    if not exists:
        ctx.fail(where, f"no such file: {path}")
    if not regular:
        ctx.fail(where, f"not a regular file: {path}")
    return path


# --- objects ------------------------------------------------------------------------------


class Obj:
    """A JSON object at `where`; `allow(keys)` rejects every other key."""

    def __init__(self, ctx: Ctx, where: str, value: Any, what: str = "an object") -> None:
        if not isinstance(value, dict):
            ctx.fail(where, f"must be {what}, got {describe(value)}")
        for dup in getattr(value, "duplicates", ()):
            ctx.fail(key_path(where, dup), "key given more than once")
        self.ctx = ctx
        self.where = where
        self.value: dict[str, Any] = value

    def at(self, key: str | int) -> str:
        return key_path(self.where, key)

    def has(self, key: str) -> bool:
        return key in self.value

    def allow(self, keys: Iterable[str], owner: str = "") -> None:
        known = list(keys)
        for k in self.value:
            if k not in known:
                hint = suggestion(k, known) or (f"; known keys: {', '.join(known)}" if known else "; no keys are")
                self.ctx.fail(self.at(k), f"unknown key '{k[:40]}'{' for ' + owner if owner else ''}{hint}")

    def raw(self, key: str, default: Any = REQUIRED) -> Any:
        if key in self.value:
            return self.value[key]
        if default is REQUIRED:
            close = difflib.get_close_matches(key, list(self.value), n=1, cutoff=0.6)
            hint = f" (is '{close[0]}' a misspelling?)" if close else ""
            self.ctx.fail(self.at(key), f"missing required key '{key}'{hint}")
        return default

    def read(self, key: str, reader: Callable[..., T], default: Any = REQUIRED, **options: Any) -> T:
        """`reader(ctx, where, value, **options)` on the key's value; a missing optional key gives `default`."""
        if key not in self.value and default is not REQUIRED:
            return default
        return reader(self.ctx, self.at(key), self.raw(key), **options)

    def obj(self, key: str, default: Any = REQUIRED) -> Obj:
        return Obj(self.ctx, self.at(key), self.raw(key, default))
