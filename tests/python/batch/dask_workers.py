"""A worker process killed mid-task, as a crash or the OOM killer would: for the Dask tests."""

from __future__ import annotations

import os
import signal
import threading
import time


def kill_a_busy_worker(client, killed: list[str], stop: threading.Event) -> None:
    """SIGKILL the process of the first worker seen running a task (its address into `killed`)."""
    pids = client.run(os.getpid)
    while not stop.is_set():
        for worker, keys in client.processing().items():
            if keys and worker in pids:
                time.sleep(0.2)  # into the task, past its start
                os.kill(pids[worker], signal.SIGKILL)
                killed.append(worker)
                return
        time.sleep(0.02)
