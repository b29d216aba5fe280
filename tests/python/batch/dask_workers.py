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


def wait_for_live_workers(client, n: int = 2, timeout: float = 60.0) -> None:
    """Until the scheduler lists at least `n` workers and every one of them answers. After a
    kill the scheduler may list the dead worker for a while beside its nanny's replacement, so
    wait_for_workers(n) can return while a scatter would still go to the dead one."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        listed = len(client.scheduler_info()["workers"])
        if listed >= n:
            try:
                if len(client.run(os.getpid)) == listed:
                    return
            except Exception:  # a listed worker that is gone: wait for the scheduler to drop it
                pass
        time.sleep(0.1)
    raise TimeoutError(f"fewer than {n} live Dask workers after {timeout} s")
