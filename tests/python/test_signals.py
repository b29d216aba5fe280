"""patina.signals: SIGINT and SIGTERM while worker processes start are this process's: the
workers ignore them, and one that came meanwhile is raised when the start is done."""

from __future__ import annotations

import multiprocessing
import os
import signal

import pytest

from patina.signals import INTERRUPTS, held_from_children, terminate_as_interrupt


def _dispositions(queue) -> None:
    queue.put([signal.getsignal(s) for s in INTERRUPTS])


def test_workers_started_meanwhile_ignore_both_and_this_process_keeps_them():
    """Before: the start ignored SIGINT here too, and the Ctrl-C was lost (the run went on to
    its end); SIGTERM to the process group killed the workers."""
    context = multiprocessing.get_context("forkserver")
    before = [signal.getsignal(s) for s in INTERRUPTS]
    with pytest.raises(KeyboardInterrupt), held_from_children():
        queue = context.Queue()
        worker = context.Process(target=_dispositions, args=(queue,))
        worker.start()
        os.kill(os.getpid(), signal.SIGTERM)  # to the process: any of its threads may take it
        os.kill(os.getpid(), signal.SIGINT)
        assert queue.get(timeout=60) == [signal.SIG_IGN, signal.SIG_IGN]
        worker.join(60)
    assert [signal.getsignal(s) for s in INTERRUPTS] == before


def test_a_quiet_start_raises_nothing():
    with held_from_children():
        pass


def test_sigterm_is_an_interrupt_meanwhile():
    with pytest.raises(KeyboardInterrupt), terminate_as_interrupt():
        signal.raise_signal(signal.SIGTERM)
        signal.sigtimedwait([], 0.1)  # a moment for the handler
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL
