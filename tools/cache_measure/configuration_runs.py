"""What the cache_measure scripts share about one configuration: its with_overrides keywords
from a command-line argument ("cache_resolution=16,cache_block=4"; "defaults" for none) and
its cost, one thread's CPU seconds in work items (`RenderJob.stage_times()`, stage_clock
"cpu": robust to the other sessions' load on the shared machine)."""

from patina.bench.cache import FULL
from patina.render.run import PreparedScene, job_settings, new_job


def number(text: str) -> int | float | str:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def overrides(text: str) -> dict:
    """with_overrides keywords of "key=value,key=value" ("defaults": none)."""
    if text == "defaults":
        return {}
    return {k: number(v) for k, v in (pair.split("=") for pair in text.split(","))}


def cpu_seconds(scene) -> float:
    """One thread's CPU seconds in work items, rendering `scene` at the bench's SIMD width."""
    options = job_settings(scene, FULL.candidate_spp, None, None, None)
    options.stage_clock = "cpu"
    job = new_job(PreparedScene(scene), options, threads=1)
    job.start()
    job.wait()
    return job.stage_times().item_seconds
