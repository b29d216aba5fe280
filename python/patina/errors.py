"""Errors Patina raises for bad input: each names the file, the place and the problem."""

from __future__ import annotations


class FormatError(ValueError):
    """A file could not be read: `path`, `where` (line, byte offset, field) and `problem`."""

    def __init__(self, path: str, where: str, problem: str) -> None:
        self.path = str(path)
        self.where = where
        self.problem = problem
        place = f" ({where})" if where else ""
        super().__init__(f"{self.path}{place}: {problem}")
