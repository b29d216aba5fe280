"""docs/architecture.md and docs/design.md name only repository paths that exist.

Checked: every backticked span outside code blocks and every path inside code blocks that
starts with one of the repository's top-level folders (`core/`, `render/`, `python/`, ...;
`{a,b}` is expanded), and every relative Markdown link. A span followed by "(planned)" must *not* exist
yet, so the page is corrected when the planned part lands. Paths starting with `../` are
outside the repository (the shared thesis text) and are not checked. architecture.md's
table of Python parts must also list every folder and module of python/patina.
"""

import os
import re
import subprocess

import pytest

from repo_paths import ROOT

DOCS = ("docs/architecture.md", "docs/design.md")
TOP = ("core", "brdf", "fit", "render", "python", "tests", "tools", "docs", "materials")
FENCE = re.compile(r"^```.*?^```", re.M | re.S)
SPAN = re.compile(r"`([^`\n]+)`(\s*\*?\(planned\)\*?)?")
PATHLIKE = re.compile(r"[\w.\-/{},*]+")
IN_BLOCK = re.compile(r"(?<![\w./])((?:" + "|".join(TOP) + r")/[\w.\-/{},]*)")
LINK = re.compile(r"\]\(([^)#\s]+)\)")


def expand(path: str) -> list[str]:
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [p for alt in m.group(1).split(",") for p in expand(path[: m.start()] + alt + path[m.end() :])]


def named_paths(text: str) -> list[tuple[str, bool]]:
    """(path, planned) for every repository path the Markdown text names."""
    found: list[tuple[str, bool]] = []
    for block in FENCE.findall(text):
        for m in IN_BLOCK.finditer(block):
            found += [(p, False) for p in expand(m.group(1).rstrip(",.;:"))]
    prose = FENCE.sub("", text)
    for m in SPAN.finditer(prose):
        span = m.group(1).strip()
        if span.split("/")[0] not in TOP or "/" not in span or not PATHLIKE.fullmatch(span) or "*" in span:
            continue
        found += [(p, m.group(2) is not None) for p in expand(span)]
    return found


def problems(doc: str, text: str) -> list[str]:
    out = []
    for path, planned in named_paths(text):
        exists = os.path.exists(os.path.join(ROOT, path))
        if planned and exists:
            out.append(f"{doc}: {path} is marked planned but exists")
        elif not planned and not exists:
            out.append(f"{doc}: {path} does not exist")
    for target in LINK.findall(FENCE.sub("", text)):
        if "://" not in target and not os.path.exists(os.path.join(ROOT, os.path.dirname(doc), target)):
            out.append(f"{doc}: link {target} does not exist")
    return out


def read(doc: str) -> str:
    with open(os.path.join(ROOT, doc), encoding="utf-8") as f:
        return f.read()


@pytest.mark.parametrize("doc", DOCS)
def test_every_named_path_exists(doc):
    assert problems(doc, read(doc)) == []


def test_the_checker_sees_missing_planned_and_braced_paths():
    text = (
        "`core/simd/fastmath.h` `core/no_such.h` `render/photons/` *(planned)* `brdf/search.h` (planned)\n"
        "`brdf/kernels_w{1,4,9}.cpp` `../shared/x.txt` `patina.scene.types` [x](no-such.md)\n"
        "```\ncore/simd/gone.h, render/accel/traverse.h\n```\n"
    )
    assert sorted(problems("docs/x.md", text)) == [
        "docs/x.md: brdf/kernels_w9.cpp does not exist",
        "docs/x.md: brdf/search.h is marked planned but exists",
        "docs/x.md: core/no_such.h does not exist",
        "docs/x.md: core/simd/gone.h does not exist",
        "docs/x.md: link no-such.md does not exist",
    ]


def test_the_python_parts_table_lists_every_folder_and_module():
    rows = {}
    for line in read("docs/architecture.md").splitlines():
        m = re.match(r"\| `(python/patina/[\w/]*)`[^|]*\|[^|]*\|([^|]*)\|", line)
        if m:
            rows[m.group(1).rstrip("/")] = set(re.findall(r"\w+", re.sub(r"\([^)]*\)", "", m.group(2))))
    package = os.path.join(ROOT, "python", "patina")
    missing = []
    for folder, _dirs, files in os.walk(package):
        if "__init__.py" not in files:
            continue
        key = os.path.relpath(folder, ROOT).replace(os.sep, "/")
        if key not in rows:
            missing.append(f"folder {key}")
            continue
        for f in files:
            stem = f[:-3]
            if f.endswith(".py") and not stem.startswith("__") and stem not in rows[key]:
                missing.append(f"module {key}/{f}")
    assert missing == []


def test_every_cited_tool_exists():
    """Comments and pages cite generators by path (core/simd/fastmath.h once cited a
    generator, fit_fastmath.py, that tools/ never had): every tools/ script any tracked file names exists."""
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=False)
    if listed.returncode != 0:
        pytest.skip("not a git checkout")
    cited = re.compile(rb"(?<![\w./])tools/[\w.-]+\.(?:py|sh|txt)")
    missing = set()
    for name in listed.stdout.decode().split("\0"):
        path = os.path.join(ROOT, name)
        if not name or not os.path.isfile(path) or os.path.getsize(path) > 1 << 20:
            continue
        with open(path, "rb") as f:
            for tool in cited.findall(f.read()):
                if not os.path.exists(os.path.join(ROOT, tool.decode())):
                    missing.add(f"{name}: {tool.decode()}")
    assert sorted(missing) == []


SOURCE_FOLDERS = ("core", "brdf", "fit", "render", "python/bindings")


def tracked(*folders: str) -> list[str]:
    listed = subprocess.run(["git", "ls-files", "-z", *folders], cwd=ROOT, capture_output=True, check=False)
    if listed.returncode != 0:
        pytest.skip("not a git checkout")
    return [name for name in listed.stdout.decode().split("\0") if name]


def test_every_cpp_source_is_named_in_the_architecture_page():
    """A newcomer finds every C++ file of the engine in docs/architecture.md: one added without
    its line there fails here."""
    named = {path for path, _planned in named_paths(read("docs/architecture.md"))}
    sources = [name for name in tracked(*SOURCE_FOLDERS) if name.endswith((".h", ".cpp"))]
    assert sources, "no C++ sources found"
    assert sorted(name for name in sources if name not in named) == []


def test_the_cpp_tests_mirror_the_source_tree():
    """tests/cpp/X/test_y.cpp tests a part in X/: the folder exists in the source tree (the
    shared harness stays at the top of tests/cpp)."""
    misplaced = []
    for name in tracked("tests/cpp"):
        folder = os.path.dirname(os.path.relpath(name, "tests/cpp"))
        if folder and not os.path.isdir(os.path.join(ROOT, folder)):
            misplaced.append(name)
        elif (
            not folder and re.fullmatch(r"test_\w+\.cpp", os.path.basename(name)) and name != "tests/cpp/test_main.cpp"
        ):
            misplaced.append(name)
    assert misplaced == []
