"""Progress in a log (stderr not a terminal): each state once, the last one too."""

from __future__ import annotations

import patina.progress
from patina.progress import Progress


def test_the_last_line_is_written_once(monkeypatch, capsys):
    """`fit --compare` and `bench` wrote their final "n/n" line twice in logs: once from the
    last update, again from tqdm's closing redraw."""
    monkeypatch.setattr(patina.progress, "LOG_INTERVAL_S", 0.0)  # a line at every update
    with Progress(3, "fitting", unit="model") as bar:
        for done in range(4):
            bar.update(done, postfix=f"model {done}")
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1].startswith("fitting: 100%") and sum("3/3" in line for line in lines) == 1, lines


def test_a_final_state_not_yet_written_is_written_at_the_close(capsys):
    with Progress(2, "report", unit="step") as bar:  # lines every few seconds: the updates are quicker
        bar.update(1)
        bar.update(2)
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1].startswith("report: 100%") and sum("2/2" in line for line in lines) == 1, lines
