"""Mitsuba's log while the bench runs: its warnings gathered instead of printed as they come.

Mitsuba writes each warning as a coloured line on stdout (72 in `patina bench --only render`,
most of them "[MultijitterSampler] Sample count rounded up to ..." for a spp the sampler
plugin rounds, which the bench accounts for). They are caught by an Appender on Mitsuba's
logger for the run and summed up at its end in one line, or listed once each with their
counts under `--verbose`. Errors still reach stderr at once. Mitsuba in child processes
(bench/mitsuba_split.py, the LLVM probe) writes into pipes the bench reads, not here.
"""

from __future__ import annotations

import contextlib
import re
import sys
from collections import Counter
from collections.abc import Iterator
from typing import Any

_STAMP = re.compile(r"^\S+ \S+ WARN\s+")  # "2026-12-03 22:35:35 WARN  [Plugin] text"


def _appender_class(mi: Any, warnings: Counter[str]) -> Any:
    class Gathering(mi.Appender):  # type: ignore[misc, name-defined]
        def append(self, level: Any, text: str) -> None:
            if level >= mi.LogLevel.Error:
                print(text, file=sys.stderr)
            elif level >= mi.LogLevel.Warn:
                warnings[_STAMP.sub("", text.strip())] += 1

        def log_progress(self, *args: Any) -> None:
            pass  # the bench draws its own progress

    return Gathering


@contextlib.contextmanager
def gathered_mitsuba_warnings(verbose: bool = False) -> Iterator[Counter[str]]:
    """Within: Mitsuba's warnings counted (by text) instead of printed; at the end, one line on
    stderr (every distinct warning with its count when `verbose`). Nothing without Mitsuba."""
    warnings: Counter[str] = Counter()
    try:
        import mitsuba as mi

        logger = mi.logger()
    except (ImportError, AttributeError):  # no Mitsuba, or one older than mi.logger()
        yield warnings
        return
    previous = [logger.appender(i) for i in range(logger.appender_count())]
    logger.clear_appenders()
    logger.add_appender(_appender_class(mi, warnings)())
    try:
        yield warnings
    finally:
        logger.clear_appenders()
        for appender in previous:
            logger.add_appender(appender)
        _report(warnings, verbose)


def _report(warnings: Counter[str], verbose: bool) -> None:
    if not warnings:
        return
    total = sum(warnings.values())
    if verbose:
        print(f"patina bench: Mitsuba's warnings ({total}):", file=sys.stderr)
        for text, count in warnings.most_common():
            print(f"  {count:>5} x {text}", file=sys.stderr)
        return
    text, count = warnings.most_common(1)[0]
    others = f"; {len(warnings) - 1} other kinds" if len(warnings) > 1 else ""
    print(
        f"patina bench: Mitsuba warned {total} times, {count} x {text}{others} (--verbose lists them)",
        file=sys.stderr,
    )
