"""Running a batch: the tasks planned (one per material and step, each after the steps it
needs), run on Dask distributed or, without it, one after the other in this process; then the
library report (patina.batch.gallery).

Dask: a LocalCluster on this machine by default (a worker process per core, one thread each,
so a worker's fits and renders run on one thread and the workers fill the cores), or any
running scheduler (`tcp://host:8786`) whose workers see the same files at the same paths.
Tasks are submitted with RETRIES: a worker that dies mid-task loses nothing, the scheduler
runs the task again on another worker (its outputs are written whole or not at all, the
manifest last), and a task that keeps failing is reported as failed, the others go on.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import uuid
import warnings
from collections.abc import Callable, Iterator
from concurrent.futures import CancelledError
from dataclasses import dataclass
from typing import Any

from patina.atomic import check_writable, remove_dead_temporaries
from patina.batch.gallery import summarise, write_gallery
from patina.batch.library import Material, Settings, find_tables
from patina.batch.scheduler_address import CONNECT_TIMEOUT_S, IN_PROCESS, check_scheduler, probe_scheduler
from patina.batch.tasks import NEEDS, one_line, result, run_task
from patina.file_names import printable
from patina.progress import Progress
from patina.signals import held_from_children, terminate_as_interrupt

RETRIES = 2  # a task whose worker died (or that raised) is run up to this many times more
WORKERS_TIMEOUT_S = 20  # a scheduler with no worker: waited for this long, then reported
CLOSE_TIMEOUT_S = 2  # closing the local client and cluster once its workers are killed: no longer
# The local cluster's housekeeping at a slower beat than Dask's defaults (a 10 ms profiler,
# a 100 ms memory monitor, a 20 ms event-loop tick): idle, its 2 workers and scheduler took
# 0.13 s of CPU a second on this project's 2-core machine, with these 0.03 s; every
# task still runs the same, the dashboard's profile tab stays empty.
QUIET_CLUSTER = {
    "distributed.worker.profile.enabled": False,
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.admin.tick.interval": "100ms",
    # workers forked from a fork server that ignores SIGINT and SIGTERM (patina.signals.held_from_children)
    "distributed.worker.multiprocessing-method": "forkserver",
}


@dataclass(frozen=True)
class Task:
    step: str
    material: Material
    needs: tuple[int, ...]  # indices of the tasks whose results it takes


def plan(materials: list[Material], settings: Settings) -> list[Task]:
    """Every material's steps in order; a task comes after the tasks it needs."""
    tasks: list[Task] = []
    for m in materials:
        index: dict[str, int] = {}
        for step in settings.steps:
            index[step] = len(tasks)
            tasks.append(Task(step, m, tuple(index[s] for s in NEEDS[step] if s in index)))
    return tasks


# A step's cost relative to the others, what the Dask priorities go by (on the bench library,
# docs/bench.md: validate 0.25 s, fit 0.2 s, preview 1.8 s a table; a report's figures some seconds)
STEP_COST = {"validate": 1, "fit": 1, "preview": 8, "report": 8}


def priorities(tasks: list[Task]) -> list[int]:
    """Each task's Dask priority (higher runs first): the cost of the longest chain of tasks
    that starts with it. The fits go first (each unlocks a preview and a report), then the
    previews and reports, and the validations, short and needed by none, last: they fill the
    workers while the last long tasks finish, instead of a worker idle through a lone preview."""
    dependents: list[list[int]] = [[] for _ in tasks]
    for j, task in enumerate(tasks):
        for i in task.needs:
            dependents[i].append(j)
    chain = [0] * len(tasks)
    for i in reversed(range(len(tasks))):  # a task's dependents come after it (plan)
        chain[i] = STEP_COST[tasks[i].step] + max((chain[j] for j in dependents[i]), default=0)
    return chain


def _raised(task: Task, e: BaseException) -> dict[str, Any]:
    """The result of a task that raised (after its retries): failed, with one line."""
    return result(task.material, task.step, "failed", f"{type(e).__name__}: {one_line(e)}")


def run_in_process(tasks: list[Task], settings: Settings, out_dir: str, progress: Progress) -> list[dict[str, Any]]:
    results: list[dict[str, Any]] = []
    for done, task in enumerate(tasks):
        progress.update(done, postfix=f"{printable(task.material.name)} {task.step}")
        try:
            results.append(run_task(task.step, task.material, settings, out_dir, 0, *(results[i] for i in task.needs)))
        except Exception as e:  # one material's trouble (a MemoryError too) does not stop the library
            results.append(_raised(task, e))
    progress.update(len(tasks))
    return results


def run_on_dask(
    tasks: list[Task], settings: Settings, out_dir: str, client: Any, progress: Progress
) -> list[dict[str, Any]]:
    import dask
    from distributed import as_completed

    run_id = uuid.uuid4().hex[:12]  # keys unique to this run, on a scheduler other batches share
    # One graph, submitted at once: the scheduler sees every task and its priority before it
    # places any (tasks submitted one by one, the first few of each step went to the workers
    # at once and ran before fits of higher priority that came later)
    delayed: list[Any] = []
    for i, (task, priority) in enumerate(zip(tasks, priorities(tasks))):
        with dask.annotate(priority=priority):
            delayed.append(
                dask.delayed(run_task, pure=False)(
                    task.step,
                    task.material,
                    settings,
                    out_dir,
                    1,  # one thread a task: the workers fill the cores
                    *(delayed[j] for j in task.needs),
                    # the step in the key's prefix: Dask learns each step's duration on its own
                    # (for where to run and what to steal), not one average of long and short tasks
                    dask_key_name=f"patina-batch-{task.step}-{run_id}-{i}",
                )
            )
    futures: list[Any] = client.compute(delayed, optimize_graph=False, retries=RETRIES)
    position = {f.key: i for i, f in enumerate(futures)}
    # each result fetched as its task ends, not one round trip a task after the last; on this
    # client's loop (left to itself, as_completed takes the newest client's: with two clients,
    # as the bench has, fetching another client's results there waited forever)
    returned: dict[int, Any] = {}
    finished = as_completed(futures, loop=client.loop, with_results=True, raise_errors=False)
    try:
        for done, (future, value) in enumerate(finished, 1):
            returned[position[future.key]] = value
            task = tasks[position[future.key]]
            progress.update(done, postfix=f"{printable(task.material.name)} {task.step}")
    except BaseException:
        client.cancel(futures)  # Ctrl-C: the finished tasks' outputs and manifests stay
        raise
    results: list[dict[str, Any]] = []
    for i, (task, future) in enumerate(zip(tasks, futures)):
        if future.status == "finished":
            results.append(returned[i])
        elif any(results[j]["status"] != "ok" for j in task.needs):
            # Dask fails a task whose input failed with the same error: say which it was
            results.append(result(task.material, task.step, "blocked", "not run: an earlier step failed"))
        else:
            results.append(_raised(task, future.exception()))
    return results


# ---------------------------------------------------------------- Dask


def dask_available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


def dashboard(client: Any) -> str:
    """The dashboard's address, or why there is none (it needs bokeh where the scheduler runs)."""
    try:
        if "dashboard" in client.scheduler_info().get("services", {}):
            return client.dashboard_link
    except Exception:  # an old scheduler's info: no dashboard to print
        pass
    return "none (the scheduler serves no dashboard: bokeh is not installed there)"


@contextlib.contextmanager
def connect(scheduler: str | None, workers: int | None) -> Iterator[tuple[Any, str]]:
    """(a Dask client, what it is) for a scheduler address, or a LocalCluster of `workers`
    processes (default: one per core). ValueError, within seconds, for an address that does
    not answer or a scheduler with no workers."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler is None:
        n = workers or os.cpu_count() or 1
        cluster = None
        try:
            # the worker processes ignore SIGINT and SIGTERM (held_from_children); one that
            # comes meanwhile is raised here once the cluster is up, and closes it
            with warnings.catch_warnings(), held_from_children(), dask.config.set(QUIET_CLUSTER):
                # 8787 taken (another batch, another user): Dask takes a free port, and we print it
                warnings.filterwarnings("ignore", message="Port .* is already in use")
                cluster = LocalCluster(
                    n_workers=n,
                    threads_per_worker=1,
                    processes=True,
                    silence_logs=logging.ERROR,  # the batch's own lines and progress, not the cluster's log
                    dashboard_address=":8787",
                )
            client = Client(cluster)
            try:
                yield client, f"a local Dask cluster of {n} worker process{'es' if n > 1 else ''}"
            finally:
                # the workers stop first, not after the tasks in flight (closing asks them to
                # finish those: 10 s after a render's second Ctrl-C)
                kill_workers(cluster)
                with contextlib.suppress(Exception):
                    client.close(timeout=CLOSE_TIMEOUT_S)
        finally:
            if cluster is not None:
                kill_workers(cluster)
                with contextlib.suppress(Exception):  # what is left of it goes with this process
                    cluster.close(timeout=CLOSE_TIMEOUT_S)
        return
    if workers is not None:
        raise ValueError("--workers: sets the size of the local cluster; a --scheduler has its own workers")
    probe_scheduler(scheduler)  # a silent port or one speaking something else: one line, no Dask traceback
    with quiet_dask_logs():
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT_S)
        except Exception as e:  # whatever Dask raises is one line here
            raise ValueError(f"--scheduler {scheduler}: cannot connect: {one_line(e)}") from None
        try:
            try:
                client.wait_for_workers(1, timeout=WORKERS_TIMEOUT_S)
            except (OSError, TimeoutError):
                raise ValueError(f"--scheduler {scheduler}: no worker joined within {WORKERS_TIMEOUT_S} s") from None
            try:
                yield client, f"the Dask scheduler at {scheduler} ({len(client.nthreads())} workers)"
            except (OSError, CancelledError) as e:  # the scheduler died or the network went
                raise ValueError(f"--scheduler {scheduler}: the scheduler was lost: {one_line(e)}") from None
        finally:
            client.close()


def _dask_loggers() -> list[logging.Logger]:
    names = ["distributed", *(n for n in logging.root.manager.loggerDict if n.startswith("distributed."))]
    return [logging.getLogger(n) for n in names]


@contextlib.contextmanager
def quiet_dask_logs() -> Iterator[None]:
    """Dask's own log lines off meanwhile (a scheduler that dies mid-run: CancelledError
    tracebacks, "Failed to reconnect"): Patina says what happened in one line."""
    loggers = _dask_loggers()
    before = [lg.disabled for lg in loggers]
    for lg in loggers:
        lg.disabled = True
    try:
        yield
    finally:
        for lg, disabled in zip(loggers, before):
            lg.disabled = disabled


def kill_workers(cluster: Any) -> None:
    """SIGKILL to the local cluster's worker processes. What they were writing stays a hidden
    temporary file, named with their pid, that remove_dead_temporaries removes."""
    # the cluster's lost connections to them are expected now: not a traceback on the terminal
    for logger in _dask_loggers():  # for good: this process is closing its cluster
        logger.disabled = True
    for nanny in list(getattr(cluster, "workers", {}).values()):
        # told first that the cluster is closing: a nanny restarts a worker that dies otherwise,
        # and closing the cluster then waits for the new one (the 10 s a second Ctrl-C sometimes took)
        with contextlib.suppress(Exception):
            nanny.close_gracefully(reason="patina: the work is over")
        pid = getattr(nanny, "pid", None)  # None: not started, or already gone
        if pid:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)


# ---------------------------------------------------------------- the batch


def run_batch(
    library: str,
    out_dir: str,
    settings: Settings,
    scheduler: str | None = None,
    workers: int | None = None,
    client: Any = None,
    progress: bool = True,
    say: Callable[[str], None] = print,
) -> dict[str, Any]:
    """Processes every table of `library` into `out_dir` and writes the library report; returns
    the summary (as summary.json). scheduler: None (a LocalCluster), an address, or IN_PROCESS;
    `client`: a Dask client to use instead (tests). ValueError for unusable options or a
    library with no table, before any task starts."""
    with terminate_as_interrupt():  # a batch system's or service manager's SIGTERM: as Ctrl-C
        return _run_batch(library, out_dir, settings, scheduler, workers, client, progress, say)


def _run_batch(
    library: str,
    out_dir: str,
    settings: Settings,
    scheduler: str | None,
    workers: int | None,
    client: Any,
    progress: bool,
    say: Callable[[str], None],
) -> dict[str, Any]:
    check_scheduler(scheduler)
    if workers is not None and not 1 <= workers <= 1024:
        raise ValueError(f"--workers: {workers} is not in 1 .. 1024")
    if workers is not None and scheduler == IN_PROCESS:
        raise ValueError(f"--workers: sets the size of the local cluster; {IN_PROCESS} runs one task at a time")
    if os.path.isdir(library) and os.path.realpath(out_dir) == os.path.realpath(library):
        # the library report's summary.csv would be read as a table by the next run
        raise ValueError(f"--out {out_dir}: the library folder itself; give the reports a folder of their own")
    materials, skipped = find_tables(library)
    if not materials:
        names = f" ({len(skipped)} other files)" if skipped else ""
        raise ValueError(f"{library}: no tables in this folder{names}; tables are .ptab, MERL .binary, ASTM, CSV")
    out_dir = os.path.abspath(out_dir)
    try:
        os.makedirs(os.path.join(out_dir, "materials"), exist_ok=True)
    except OSError as e:
        raise ValueError(f"--out {printable(out_dir)}: cannot make the report folder: {e.strerror}") from None
    try:  # an existing folder that cannot be written: said now, not after every task has run
        check_writable(os.path.join(out_dir, "summary.json"))
        check_writable(os.path.join(out_dir, "materials", "summary.json"))
    except OSError as e:
        raise ValueError(f"--out {e}") from None
    for name, why in skipped:
        say(f"skipped {printable(name)}: {why}")
    tasks = plan(materials, settings)
    say(f"{len(materials)} tables, {len(tasks)} tasks ({', '.join(settings.steps)})")

    def run(client: Any | None) -> list[dict[str, Any]]:
        with Progress(len(tasks), "batch", unit="task", enabled=progress) as bar:
            if client is None:
                return run_in_process(tasks, settings, out_dir, bar)
            return run_on_dask(tasks, settings, out_dir, client, bar)

    if client is not None:
        results = run(client)
    elif scheduler == IN_PROCESS:
        say("running in this process, one task at a time")
        results = run(None)
    elif not dask_available():
        say("Dask distributed is not installed (pip install .[cluster]): running in this process, one task at a time")
        results = run(None)
    else:
        try:
            with connect(scheduler, workers) as (dask_client, what):
                say(f"running on {what}; dashboard: {dashboard(dask_client)}")
                results = run(dask_client)
        finally:  # the temporaries of workers killed mid-write (connect kills them when done)
            remove_dead_temporaries(os.path.join(out_dir, "materials"))
    summary = summarise(library, out_dir, materials, skipped, results, settings)
    write_gallery(out_dir, summary)
    return summary
