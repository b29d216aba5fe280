"""The README runs as written: every shell command and every Python block in README.md.

The commands run in README order (later ones read what earlier ones write: the MERL table,
fit.json) in a scratch copy of materials/ and tools/ with `.venv` linked to this test's
environment, so outputs land in a temporary directory and the checkout stays clean. A
command this test does not run is in EXCLUDED with the reason, and every README command is
either run or excluded: a new README line is tested from the day it is written. A command
run with arguments added (fewer timing repeats) is in SHORTENED with the reason.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from repo_paths import ROOT

README = Path(ROOT) / "README.md"
RUNNERS = ("patina", ".venv/bin/python", ".venv/bin/patina", "make")

# Command (as in the README, without its comment) -> why this test does not run it.
EXCLUDED = {
    "make demo": "runs tools/setup.sh (pip, apt-get) and the full 64-spp preview; the README's "
    "`patina render materials/scenes/preview-ball.json` line runs the same render at fewer samples",
    "make test": "make test runs this test",
    **{
        f"patina bench --only {group}": "a full benchmark group takes minutes; `patina bench --quick` runs it"
        for group in ("brdf --json bench.json", "trace", "fit", "render", "lights", "cache", "cache --large")
    },
}

# Command -> the arguments this test adds to it, and why that leaves what the test checks (the
# command runs every step and writes what it says) as it was.
SHORTENED = {
    "patina bench --quick": (
        ["--repeat", "1"],
        "every group still runs in quick mode and prints its records; the default medians of 7 time "
        "the same runs 6 more times, which checks nothing (tests/python/bench checks each group's records)",
    ),
}

TIMEOUT_S = 900  # one command; the slowest (fit --compare on the MERL table) takes about a minute


def _readme_text() -> str:
    return README.read_text(encoding="utf-8")


def readme_commands() -> list[str]:
    """Shell commands: lines of the README's indented code blocks that start with a runner."""
    commands = []
    in_fence = False
    for line in _readme_text().splitlines():
        if line.startswith("```"):
            in_fence = not in_fence
            continue
        if in_fence or not line.startswith("    ") or line.split()[0] not in RUNNERS:
            continue
        # a comment starts at a '#' that begins a word, as the shell has it (SCENE.json#name is one word)
        commands.append(shlex.join(shlex.split(re.sub(r"(^|\s)#.*$", "", line))))
    return commands


def readme_python_blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", _readme_text(), re.S | re.M)


COMMANDS = readme_commands()
RUN = [c for c in COMMANDS if c not in EXCLUDED]


def test_the_readme_has_commands_and_snippets():
    assert len(RUN) >= 20 and len(readme_python_blocks()) >= 4


def test_every_exclusion_is_a_readme_command():
    """An exclusion (or a shortening) that no longer matches a README line would hide nothing but mislead."""
    assert set(EXCLUDED) <= set(COMMANDS), set(EXCLUDED) - set(COMMANDS)
    assert set(SHORTENED) <= set(RUN), set(SHORTENED) - set(RUN)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    """A scratch top of a clone: materials/ and tools/ copied (without generated MERL files, which
    the README's first command makes), `.venv` this Python's environment."""
    work = tmp_path_factory.mktemp("readme")
    shutil.copytree(Path(ROOT) / "materials", work / "materials", ignore=shutil.ignore_patterns("*.binary"))
    shutil.copytree(Path(ROOT) / "tools", work / "tools", ignore=shutil.ignore_patterns("__pycache__"))
    os.symlink(sys.prefix, work / ".venv", target_is_directory=True)
    return work


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = os.path.join(sys.prefix, "bin") + os.pathsep + env.get("PATH", "")
    env["MPLBACKEND"] = "Agg"
    return env


def _outputs(words: list[str]) -> list[str]:
    """The files or folders a command says it writes (--out, --png, --json FILE, convert's OUT)."""
    out = [words[i + 1] for i, w in enumerate(words[:-1]) if w in ("--out", "--png")]
    if words[:2] == ["patina", "bench"] and "--json" in words:
        out.append(words[words.index("--json") + 1])
    if words[:2] == ["patina", "convert"]:
        out.append(words[3])
    return out


@pytest.mark.parametrize("command", RUN, ids=RUN)
def test_readme_command(command: str, workdir: Path):
    words = shlex.split(command) + SHORTENED.get(command, ([], ""))[0]
    r = subprocess.run(
        words, cwd=workdir, env=_environment(), capture_output=True, text=True, timeout=TIMEOUT_S, check=False
    )
    assert r.returncode == 0, f"{command}\nexit {r.returncode}\n{r.stderr[-3000:]}"
    assert "Traceback" not in r.stderr, r.stderr[-3000:]
    for path in _outputs(words):
        assert (workdir / path).exists(), f"{command}: {path} was not written"


@pytest.mark.parametrize("index", range(len(readme_python_blocks())))
def test_readme_python_block(index: int, workdir: Path):
    code = readme_python_blocks()[index]
    r = subprocess.run(
        [sys.executable, "-c", code],
        cwd=workdir,
        env=_environment(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        check=False,
    )
    assert r.returncode == 0, f"README Python block {index + 1}:\n{code}\n{r.stderr[-3000:]}"
