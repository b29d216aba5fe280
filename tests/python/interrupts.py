"""Starting a `patina` subprocess that a test interrupts with SIGINT."""

from __future__ import annotations

import signal
import subprocess

from patina.signals import handling


def start_interruptible(cmd: list[str]) -> subprocess.Popen:
    """`cmd` with its stdout and stderr piped (text), taking SIGINT as a terminal's Ctrl-C. A
    shell runs a background job (`make test &`) with SIGINT ignored, and an ignored signal
    stays ignored across exec, where Python would then install no KeyboardInterrupt handler
    and the test's Ctrl-C would be lost; a caught one is reset to its default. So the child is
    started while this process catches SIGINT."""
    with handling(signal.SIGINT, signal.default_int_handler):
        return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
