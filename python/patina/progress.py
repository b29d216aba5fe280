"""Progress of long work on stderr (tqdm): done, left, rate and time left.

On a terminal the bar redraws in place; when stderr is not a terminal (a log, CI, a pipe)
it writes a plain line every few seconds instead, so long runs are never silent. Quiet
when `enabled` is false.
"""

from __future__ import annotations

import sys
from types import TracebackType
from typing import TextIO

from tqdm import tqdm

LOG_INTERVAL_S = 5.0  # seconds between lines when stderr is not a terminal


class _Lines:
    """stderr for a log: tqdm redraws with a carriage return, which a log file or a CI viewer
    does not move back on, so each redraw becomes one line of its own (blank ones dropped)."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream

    def write(self, text: str) -> None:
        line = text.replace("\r", "").rstrip()
        if line:
            self.stream.write(line + "\n")

    def flush(self) -> None:
        self.stream.flush()


class Progress:
    """`with Progress(total, "rendering", unit="pass") as p: p.update(done)` (absolute counts)."""

    def __init__(self, total: float, description: str, unit: str = "it", enabled: bool = True) -> None:
        terminal = sys.stderr.isatty()
        self._terminal = terminal
        self._bar = tqdm(
            total=total,
            desc=description,
            unit=unit,
            file=sys.stderr if terminal else _Lines(sys.stderr),
            disable=not enabled,
            dynamic_ncols=terminal,
            mininterval=0.25 if terminal else LOG_INTERVAL_S,
            maxinterval=LOG_INTERVAL_S,
            ascii=not terminal,
            leave=True,
        )

    def update(self, done: float, postfix: str = "") -> None:
        """Sets the count done so far (not an increment) and an optional note after the bar."""
        if postfix:
            self._bar.set_postfix_str(postfix, refresh=False)
        self._bar.update(done - self._bar.n)

    def write(self, line: str) -> None:
        """A message line that does not break the bar."""
        self._bar.write(line, file=sys.stderr)

    def close(self) -> None:
        if not self._terminal and getattr(self._bar, "last_print_n", None) == self._bar.n:
            # a log already holds the line of this final count: tqdm's closing redraw would
            # print it a second time (a terminal redraws it in place)
            self._bar.leave = False
        self._bar.close()

    def __enter__(self) -> Progress:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, value: BaseException | None, traceback: TracebackType | None
    ) -> None:
        self.close()
