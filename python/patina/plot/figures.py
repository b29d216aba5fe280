"""Figures written whole: a matplotlib figure saved through a temporary file and a rename."""

from __future__ import annotations

from typing import Any

from patina.atomic import atomic_output


def save_figure(fig: Any, path: str) -> None:
    """Writes a matplotlib figure as PNG through a temporary file and a rename, then closes it."""
    import matplotlib.pyplot as plt

    try:
        atomic_output(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    finally:
        plt.close(fig)
