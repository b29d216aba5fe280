"""The report as a browser shows it: `patina plot` of a bundled table with a fit, opened in headless
Chromium (Debian's, installed by tools/setup.sh). Its images load, fit the page width (no sideways
scrolling) and the screenshot is a page, not a blank one."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess

import pytest

from patina.cli import main

GGX = {"rho_r": 0.55, "rho_g": 0.08, "rho_b": 0.05, "alpha": 0.2, "f0_r": 0.04, "f0_g": 0.04, "f0_b": 0.04}
WIDTH, HEIGHT = 1280, 2000

# Appended to a copy of index.html: after the load event, what the browser made of each image and of the
# page's width, written into the DOM for --dump-dom to print.
PROBE = """<script>
window.addEventListener("load", () => {
  const images = [...document.images].map(i => ({src: i.getAttribute("src"), complete: i.complete,
    natural: [i.naturalWidth, i.naturalHeight], shown: i.width,
    right: Math.round(i.getBoundingClientRect().right), caption: !!i.closest("figure")?.querySelector("figcaption")}));
  const out = document.createElement("pre");
  out.id = "probe";
  out.textContent = JSON.stringify({images, scrollWidth: document.documentElement.scrollWidth,
    innerWidth: window.innerWidth});
  document.body.appendChild(out);
});
</script>"""


def _chromium() -> str:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if not found:
        pytest.skip("Chromium is not installed (tools/setup.sh installs Debian's: apt-get install chromium)")
    return found


def _run(browser: str, profile: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", f"--user-data-dir={profile}",
         f"--window-size={WIDTH},{HEIGHT}", *args],
        capture_output=True, text=True, timeout=180, check=False,
    )  # fmt: skip


@pytest.fixture(scope="module")
def report_dir(tmp_path_factory, bundled_ptab) -> str:
    d = tmp_path_factory.mktemp("browser")
    fit = d / "fit.json"
    fit.write_text(json.dumps({"model": "ggx+lambert", "parameters": GGX, "metrics": {"ciede2000_mean": 0.03}}))
    out = d / "report"
    assert main(["plot", bundled_ptab, "--fit", str(fit), "--out", str(out)]) == 0
    return str(out)


def test_the_report_in_headless_chromium(tmp_path, report_dir):
    import matplotlib.pyplot as plt

    browser = _chromium()
    page = open(os.path.join(report_dir, "index.html"), encoding="utf-8").read()
    probe = os.path.join(report_dir, "probe.html")  # beside index.html, so its images resolve the same way
    with open(probe, "w", encoding="utf-8") as f:
        f.write(page.replace("</body>", PROBE + "</body>"))
    dom = _run(browser, str(tmp_path / "profile"), "--virtual-time-budget=10000", "--dump-dom", f"file://{probe}")
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom.stdout, re.S)
    assert found, f"no probe output from chromium: {dom.stderr[-2000:]}"
    seen = json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    expected = ["slices.png", "polar.png"] + (["lobe3d.png"] if os.path.exists(f"{report_dir}/lobe3d.png") else [])
    assert [i["src"] for i in seen["images"]] == expected
    for image in seen["images"]:
        assert image["complete"] and min(image["natural"]) > 100, image  # loaded, decoded
        assert image["right"] <= seen["innerWidth"], image  # within the window
        assert image["shown"] <= image["natural"][0], image  # scaled down to fit, never up
        assert image["caption"], f"{image['src']} has no caption"
    assert seen["scrollWidth"] <= seen["innerWidth"], "the page scrolls sideways"

    shot = tmp_path / "report.png"
    run = _run(browser, str(tmp_path / "profile"), f"--screenshot={shot}", f"file://{report_dir}/index.html")
    assert shot.exists(), run.stderr[-2000:]
    pixels = plt.imread(str(shot))[..., :3]
    assert pixels.shape[:2] == (HEIGHT, WIDTH)
    ink = (pixels.min(axis=2) < 0.75).mean()  # text, rules and plots, against a white page
    assert 0.01 < ink < 0.5, f"the screenshot is {100 * ink:.2f} % ink: blank or broken"
    # The styled page: the verdict box is tinted (green for a clean table), not black-on-white only
    tinted = (pixels.max(axis=2) - pixels.min(axis=2) > 0.05).mean()
    assert tinted > 0.001
