"""The gallery's sorting script in a real browser (Debian's headless Chromium, installed by
tools/setup.sh): a click on a heading sorts the rows by that column, numbers as numbers, a
second click reverses, and materials without a value (a failed table) stay last."""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import pytest
from batch_library import BAD

DE_MEAN_COLUMN = 4  # material, status, validation, best model, ΔE00 mean, ...


def _sorted_names(browser: str, page: str, clicks: int, folder: str) -> list[str]:
    with open(page, encoding="utf-8") as f:
        html = f.read()
    click = f'document.querySelectorAll("#materials th")[{DE_MEAN_COLUMN}].click();' * clicks
    probe = os.path.join(folder, f"probe{clicks}.html")  # the sorting needs no image: anywhere will do
    with open(probe, "w", encoding="utf-8") as f:
        f.write(html.replace("</body>", f"<script>{click}</script></body>"))
    dom = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={folder}/profile", "--dump-dom",
         "file://" + probe],
        capture_output=True, text=True, timeout=180, check=True,
    ).stdout  # fmt: skip
    body = dom[dom.index("<tbody>") : dom.index("</tbody>")]
    return re.findall(r'<tr class="\w+">\s*<td data-sort="([^"]+)"', body)


def test_the_gallery_sorts_by_a_column(finished_once, tmp_path):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        pytest.skip("Chromium is not installed (tools/setup.sh installs Debian's: apt-get install chromium)")
    summary = finished_once.summary
    de = {m["name"]: m["ciede2000_mean"] for m in summary["materials"] if m["ciede2000_mean"] is not None}
    page = os.path.join(finished_once.out, "index.html")
    ascending = _sorted_names(browser, page, 1, str(tmp_path))
    assert ascending == [*sorted(de, key=de.get), BAD]
    descending = _sorted_names(browser, page, 2, str(tmp_path))
    assert descending == [*sorted(de, key=de.get, reverse=True), BAD]
