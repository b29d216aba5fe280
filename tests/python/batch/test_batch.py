"""patina batch in this process: the library report, reruns that skip, a changed input that
reruns only its own tasks, a corrupt table reported while the others complete, bad options."""

from __future__ import annotations

import csv
import dataclasses
import json
import os
import struct
import time
from html.parser import HTMLParser

import pytest
from batch_library import BAD, GOOD, PLASTICS, QUICK, write_plastic

from patina.batch import IN_PROCESS, run_batch
from patina.batch import scheduling as batch_scheduling
from patina.batch import tasks as batch_tasks
from patina.cli import main


def run(library: str, out: str, settings=QUICK, **options) -> dict:
    lines: list[str] = []
    summary = run_batch(library, out, settings, scheduler=IN_PROCESS, progress=False, say=lines.append, **options)
    summary["_lines"] = lines
    return summary


def png_size(path: str) -> tuple[int, int]:
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


class _Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.rows = 0
        self.links: list[str] = []
        self.images: list[str] = []
        self.script = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr":
            self.rows += 1
        if tag == "a":
            self.links.append(a["href"])
        if tag == "img":
            self.images.append(a["src"])
        if tag == "script":
            self.script = True


def by_name(summary: dict) -> dict:
    return {m["name"]: m for m in summary["materials"]}


def mtimes(out: str) -> dict[str, int]:
    found = {}
    for folder, _, names in os.walk(out):
        for n in names:
            found[os.path.join(folder, n)] = os.stat(os.path.join(folder, n)).st_mtime_ns
    return found


def test_a_library_in_process(finished_once):
    out, summary = finished_once.out, finished_once.summary
    rows = by_name(summary)
    assert sorted(rows) == sorted([*GOOD, BAD])
    # a note beside the tables, though it names ASTM in its first line (content sniffing alone took it)
    assert summary["skipped_files"] == [{"file": "README.md", "reason": "not a table (a .md file)"}]
    assert any(line.startswith("skipped README.md:") for line in finished_once.lines)
    for name in GOOD:
        row = rows[name]
        assert row["status"] == "ok" and row["validation"] == "passed", row
        assert row["best_model"] == "ggx+lambert" and 0 <= row["ciede2000_mean"] < 5
        # the table and its fit side by side, with a rule between
        width, height = png_size(os.path.join(out, row["preview"]))
        assert (height, width) == (QUICK.height, 2 * QUICK.width + 2)
    # the whole summary, as files: JSON, CSV and the gallery
    with open(os.path.join(out, "summary.json")) as f:
        assert json.load(f)["counts"] == summary["counts"]
    assert summary["counts"]["ok"] == 3 and summary["counts"]["failed"] == 1
    with open(os.path.join(out, "summary.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    assert [r["name"] for r in table] == [m["name"] for m in summary["materials"]]
    assert {r["name"]: r["status"] for r in table}[BAD] == "failed"
    page = _Page()
    with open(os.path.join(out, "index.html"), encoding="utf-8") as f:
        page.feed(f.read())
    assert page.rows == 1 + 4 and page.script  # a heading row, a row a table, the sorting script
    assert len(page.images) == 3
    for src in page.images + [h for h in page.links if not h.startswith("summary")]:
        assert os.path.isfile(os.path.join(out, src)), src
    assert "summary.json" in page.links and "summary.csv" in page.links


def test_a_corrupt_table_fails_alone_with_its_one_line_message(finished_once):
    summary = finished_once.summary
    bad = by_name(summary)[BAD]
    assert bad["status"] == "failed" and bad["validation"] == "failed"
    assert bad["error"].startswith(f"validate: {os.path.join(finished_once.library, BAD)} (byte ")
    assert "\n" not in bad["error"]
    assert bad["steps"]["preview"]["status"] == "blocked"  # it needs the fit, which failed
    assert all(by_name(summary)[n]["status"] == "ok" for n in GOOD)


def test_the_longest_chains_start_first_and_the_validations_fill_the_end():
    materials = [batch_scheduling.Material(f"m{i}", f"/m{i}") for i in range(2)]
    tasks = batch_scheduling.plan(materials, dataclasses.replace(QUICK, steps=("validate", "fit", "preview", "report")))
    priority = {(t.material.name, t.step): p for t, p in zip(tasks, batch_scheduling.priorities(tasks))}
    for m in ("m0", "m1"):
        assert priority[m, "fit"] > max(priority[m, "preview"], priority[m, "report"]) > priority[m, "validate"]
    assert priority["m0", "fit"] == priority["m1", "fit"]  # a tie: Dask keeps the order of the plan


def test_a_rerun_skips_everything(finished):
    library, out = finished.library, finished.out
    before = mtimes(os.path.join(out, "materials"))
    again = run(library, out)
    counts = again["counts"]
    assert counts["tasks_run"] == 0 and counts["tasks_reused"] == counts["tasks"] - counts["tasks_blocked"]
    assert mtimes(os.path.join(out, "materials")) == before  # nothing rewritten
    # and the failure is still reported, from its manifest
    assert by_name(again)[BAD]["error"] == by_name(run(library, out))[BAD]["error"]


def test_a_changed_input_reruns_only_its_tasks(finished):
    library, out, first = finished.library, finished.out, finished.summary
    write_plastic(os.path.join(library, "green.ptab"), (0.3, 0.3, 0.1), 0.25)  # re-measured
    second = run(library, out)
    run_now = {
        (s, m["name"])
        for m in second["materials"]
        for s, r in m["steps"].items()
        if not r["reused"] and r["status"] != "blocked"  # blocked: not run, whatever the run
    }
    assert run_now == {("validate", "green.ptab"), ("fit", "green.ptab"), ("preview", "green.ptab")}
    assert by_name(second)["green.ptab"]["ciede2000_mean"] != by_name(first)["green.ptab"]["ciede2000_mean"]


def test_changed_settings_rerun_only_the_steps_they_touch(finished):
    second = run(finished.library, finished.out, dataclasses.replace(QUICK, spp=2))  # the previews only
    ran = {s for m in second["materials"] for s, r in m["steps"].items() if not r.get("reused")}
    assert ran == {"preview"}


def test_a_half_written_task_runs_again(finished):
    """A task killed after its output but before its manifest (the manifest is written last):
    the rerun does it again; an output changed after its manifest is redone too."""
    library, out = finished.library, finished.out
    red = os.path.join(out, "materials", "red.ptab")
    os.unlink(os.path.join(red, "fit.manifest.json"))
    with open(os.path.join(red, "preview.png"), "ab") as f:
        f.write(b"\0")
    ran = {s for s, r in by_name(run(library, out))["red.ptab"]["steps"].items() if not r["reused"]}
    assert ran == {"fit", "preview"}


def test_without_dask_it_runs_here_and_says_so_once(library, tmp_path, monkeypatch):
    monkeypatch.setattr(batch_scheduling, "dask_available", lambda: False)
    lines: list[str] = []
    one = os.path.join(library, "red.ptab")
    lib = tmp_path / "lib"
    lib.mkdir()
    os.link(one, lib / "red.ptab")
    summary = run_batch(str(lib), str(tmp_path / "out"), QUICK, progress=False, say=lines.append)
    assert summary["counts"]["ok"] == 1
    assert sum("not installed" in line for line in lines) == 1


@pytest.mark.parametrize(
    "options, message",
    [
        (["--steps", "validate,paint"], "unknown step 'paint'"),
        (["--steps", "preview"], "needs the fit step"),
        (["--models", "glossy"], "unknown model 'glossy'"),
        (["--spp", "0"], "(--spp): expected a whole number from 1 to 65536, got '0'"),
        (["--scheduler", "nowhere"], "expected an address like tcp://host:8786"),
        (["--scheduler", "tcp://127.0.0.1:99999"], "the port"),
    ],
)
def test_bad_options_give_one_line_and_exit_2(library, tmp_path, capsys, options, message):
    code = main(["batch", library, "--out", str(tmp_path / "out"), *options])
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert not os.path.exists(tmp_path / "out" / "summary.json")


def test_the_library_folder_as_out_or_workers_in_process_exit_2(library, capsys):
    assert main(["batch", library, "--out", library + "/."]) == 2
    assert "the library folder itself" in capsys.readouterr().err
    assert main(["batch", library, "--out", library + "/out", "--scheduler", IN_PROCESS, "--workers", "2"]) == 2
    assert "--workers: sets the size of the local cluster" in capsys.readouterr().err
    assert not os.path.exists(library + "/out")


def test_a_missing_or_empty_folder_exits_2(tmp_path, capsys):
    assert main(["batch", str(tmp_path / "nothing"), "--out", str(tmp_path / "out")]) == 2
    assert "no such folder" in capsys.readouterr().err
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.md").write_text("no tables here")
    assert main(["batch", str(empty), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "no tables in this folder" in err and len(err.strip().splitlines()) == 1


def test_an_unreachable_scheduler_exits_2_within_seconds(library, tmp_path, capsys):
    pytest.importorskip("distributed")
    started = time.monotonic()
    code = main(["batch", library, "--out", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2 and "tcp://127.0.0.1:9" in err and len(err.strip().splitlines()) == 1, err
    assert time.monotonic() - started < 30


def test_the_command_exits_0_when_some_tables_were_processed(library, tmp_path, capsys):
    out = str(tmp_path / "out")
    code = main(
        [
            "batch", library, "--out", out, "--scheduler", IN_PROCESS, "--steps", "validate",
            "--quiet",
        ]
    )  # fmt: skip
    err = capsys.readouterr().err
    assert code == 0
    with open(os.path.join(out, "summary.json")) as f:
        error = by_name(json.load(f))[BAD]["error"]
    assert err.strip().splitlines() == [f"patina batch: {BAD}: {error}"]
    only_bad = tmp_path / "bad"
    only_bad.mkdir()
    os.link(os.path.join(library, BAD), only_bad / BAD)
    assert main(["batch", str(only_bad), "--out", str(tmp_path / "o2"), "--scheduler", IN_PROCESS, "--quiet"]) == 1


def test_the_report_and_a_failed_fit_that_blocks_the_preview_but_not_the_report(tmp_path):
    """Each material's report, with its fits; then the table re-measured too small to fit: the
    preview (table beside fit) cannot be made, the report is, without fits -- not with the
    fit.json the earlier run left for the same file."""
    lib = tmp_path / "lib"
    lib.mkdir()
    diffuse, roughness = PLASTICS["red.ptab"]
    write_plastic(str(lib / "red.ptab"), diffuse, roughness)
    out = str(tmp_path / "out")
    settings = dataclasses.replace(QUICK, steps=("validate", "fit", "preview", "report"))
    row = by_name(run(str(lib), out, settings))["red.ptab"]
    assert row["status"] == "ok" and row["report"] == "materials/red.ptab/report/index.html"
    with open(os.path.join(out, row["report"]), encoding="utf-8") as f:
        assert "ggx+lambert" in f.read()  # the fit is in the material's report
    write_plastic(str(lib / "red.ptab"), diffuse, roughness, theta_knots=3, phi_knots=2)  # 18 samples
    row = by_name(run(str(lib), out, settings))["red.ptab"]
    assert row["status"] == "failed" and "too few to fit" in row["error"], row
    assert row["steps"]["preview"]["status"] == "blocked" and row["steps"]["report"]["status"] == "ok"
    with open(os.path.join(out, row["report"]), encoding="utf-8") as f:
        assert "ggx+lambert" not in f.read()


def test_an_output_folder_that_cannot_be_made_exits_2(library, tmp_path, capsys):
    (tmp_path / "file").write_text("not a folder")
    assert main(["batch", library, "--out", str(tmp_path / "file" / "out"), "--scheduler", IN_PROCESS]) == 2
    err = capsys.readouterr().err
    assert "cannot make the report folder: Not a directory" in err and len(err.strip().splitlines()) == 1


def test_a_task_that_raises_is_reported_and_the_others_complete(finished, monkeypatch):
    """Not bad input but an exception (here a MemoryError, as a huge table may raise): that
    material's step is failed with the exception's one line, the batch goes on."""
    real = batch_tasks.STEP_FUNCTIONS["preview"]

    def preview(material, *args):
        if material.name == "blue.ptab":
            raise MemoryError("cannot allocate the film")
        return real(material, *args)

    monkeypatch.setitem(batch_tasks.STEP_FUNCTIONS, "preview", preview)
    summary = run(finished.library, finished.out, dataclasses.replace(QUICK, spp=2))  # the previews run again
    rows = by_name(summary)
    assert rows["blue.ptab"]["error"] == "preview: MemoryError: cannot allocate the film"
    assert rows["red.ptab"]["status"] == "ok" and rows["green.ptab"]["status"] == "ok"
