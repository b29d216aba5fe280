"""Draws the adaptive antialiasing's fixed pattern (docs/antialiasing.md) from the data the
renderer uses (patina.native._core.aa_pattern, i.e. render/antialiasing/adaptive_pattern.h), so the
drawings cannot drift from the code.

    .venv/bin/python tools/draw_antialiasing.py [--out docs/images]

Writes aa-levels.png (the three levels and the zones), aa-comparisons.png (the three fours
of comparisons), aa-rotation.png (a vertical discontinuity: the pattern turned 90 degrees
counter-clockwise), aa-weights.png (the Voronoi cells within each strip that are the
weights) and aa-direct-weights.png (the same without level 2: a pixel whose edges the
geometric pre-pass placed in one run of zones).
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from patina.atomic import atomic_output
from patina.native import _core

NAMES = "ABCDEFGH"
ZONES = 5
DPI = 90


def _frame(ax, title: str) -> None:
    ax.plot([0, 1, 1, 0, 0], [0, 0, 1, 1, 0], color="black", lw=1.2)
    ax.set_xlim(-0.12, 1.12)
    ax.set_ylim(1.12, -0.12)  # v (image y) down
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)


def _zones(ax, zones: range | list[int]) -> None:
    for z in zones:
        ax.axvspan(z / ZONES, (z + 1) / ZONES, ymin=0.0968, ymax=0.9032, color=f"C{z}", alpha=0.13, lw=0)
        ax.text((z + 0.5) / ZONES, 1.08, f"z{z}", ha="center", va="center", fontsize=7, color=f"C{z}")


def _points(ax, pos: np.ndarray, which: range | list[int], labels: bool = True) -> None:
    for s in which:
        u, v = pos[s]
        if s < 4:
            ax.plot(u, v, "s", color="black", ms=6)
        elif s < 8:
            ax.plot(u, v, "o", color="tab:red", ms=6)
        else:
            ax.plot(u, v, ".", color=f"C{(s - 8) // 4}", ms=6)
        if labels and s < 8:
            du, dv = (-0.07 if u < 0.5 else 0.05), (-0.05 if v < 0.5 else 0.07)
            ax.text(u + du, v + dv if s < 4 else v - 0.06, NAMES[s], fontsize=8, ha="center")


def _zigzags(ax, pos: np.ndarray, zones: range | list[int]) -> None:
    for z in zones:
        pts = pos[8 + 4 * z : 12 + 4 * z]
        ax.plot(pts[:, 0], pts[:, 1], "-", color=f"C{z}", lw=0.8)


def _save(fig, path: str) -> None:
    atomic_output(path, lambda tmp: fig.savefig(tmp, dpi=DPI, format="png", bbox_inches="tight"))
    print(f"wrote {path} ({os.path.getsize(path) // 1024} KB)")


def draw(out: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pat = _core.aa_pattern()
    pos = np.asarray(pat["positions"], dtype=float)
    pairs = np.asarray(pat["comparisons"])
    weights = np.asarray(pat["weights"])
    os.makedirs(out, exist_ok=True)

    fig, axes = plt.subplots(1, 3, figsize=(9, 3.3))
    _frame(axes[0], "level 1: corners A-D\n(shared with the neighbours)")
    _points(axes[0], pos, range(4))
    _frame(axes[1], "level 2: E-H on the middle row;\nzones z0-z4 along the gradient u")
    _zones(axes[1], range(ZONES))
    _points(axes[1], pos, range(8))
    _frame(axes[2], "level 3: one zigzag of four a zone\n(4 % apart along u)")
    _zones(axes[2], range(ZONES))
    _zigzags(axes[2], pos, range(ZONES))
    _points(axes[2], pos, range(28), labels=False)
    _save(fig, os.path.join(out, "aa-levels.png"))
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(9, 3.3))
    for f, (ax, name) in enumerate(zip(axes, ("b0-b3", "c00-c03", "c10-c13"))):
        _frame(ax, f"{name}: " + ", ".join(f"{NAMES[p]}-{NAMES[q]}" for p, q in pairs[f]))
        _zones(ax, range(ZONES))
        for lane, (p, q) in enumerate(pairs[f]):
            bend = 0.08 * (lane - 1.5) if f == 0 else 0.0  # the row's links would overlap: bow them
            mid = 0.5 * (pos[p] + pos[q]) + np.array([0.0, bend if f == 0 and lane == 3 else 0.0])
            ax.annotate(
                "",
                xy=pos[q],
                xytext=pos[p],
                arrowprops=dict(arrowstyle="-", color="tab:blue", lw=1.2, connectionstyle=f"arc3,rad={bend}"),
            )
            ax.text(mid[0], mid[1] - 0.04, str(lane), fontsize=7, color="tab:blue", ha="center")
        _points(ax, pos, range(8))
    _save(fig, os.path.join(out, "aa-comparisons.png"))
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(6, 3.3))
    rotated = np.stack([pos[:, 1], 1.0 - pos[:, 0]], axis=1)  # (x, y) = (v, 1 - u)
    for ax, p, title in (
        (axes[0], pos, "horizontal (high A-B or C-D)"),
        (axes[1], rotated, "vertical: turned 90° CCW"),
    ):
        _frame(ax, title)
        for z in range(ZONES):
            pts = p[8 + 4 * z : 12 + 4 * z]
            ax.plot(pts[:, 0], pts[:, 1], ".-", color=f"C{z}", lw=0.8, ms=5)
        _points(ax, p, range(8))
    _save(fig, os.path.join(out, "aa-rotation.png"))
    plt.close(fig)

    _draw_weights(plt, pos, weights, (0, 0b00110, 0b11111), False, os.path.join(out, "aa-weights.png"))
    direct = np.asarray(pat["direct_weights"])
    _draw_weights(plt, pos, direct, (0b00010, 0b00110, 0b01110), True, os.path.join(out, "aa-direct-weights.png"))


def _strip_members(members: np.ndarray, pos: np.ndarray, zones: int, direct: bool, strip: int) -> np.ndarray:
    """Which of `members` share strip `strip` (adaptive_pattern.h: in_strip, in_direct_strip): those
    on it or its sides; without level 2 a strip outside the run is the corners' on its side."""
    u = pos[members, 0]
    on_strip = (u >= 0.2 * strip - 1e-9) & (u <= 0.2 * (strip + 1) + 1e-9)
    if not direct or zones >> strip & 1:
        return on_strip
    left = (zones >> strip) != 0  # the run lies right of this strip: A, C
    return (members < 4) & (members % 2 == (0 if left else 1))


def _draw_weights(plt, pos: np.ndarray, weights: np.ndarray, patterns: tuple, direct: bool, path: str) -> None:
    """Each pattern's weights as the cells they are: every point of the pixel coloured by the
    weight of the sample nearest to it among those that share its strip."""
    fig, axes = plt.subplots(1, 3, figsize=(9, 3.3))
    n = 240
    uu, vv = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n)
    strip = np.minimum((uu / 0.2).astype(int), ZONES - 1)
    for ax, zones in zip(axes, patterns):
        members = np.asarray([s for s in range(28) if weights[zones, s] > 0])
        d = (uu[..., None] - pos[members, 0]) ** 2 + (vv[..., None] - pos[members, 1]) ** 2
        for j in range(ZONES):
            d[strip == j] = np.where(_strip_members(members, pos, zones, direct, j), d[strip == j], np.inf)
        cell = members[np.argmin(d, axis=-1)]
        # one scale for the figure (without level 2 a far corner weighs up to 0.3: 1.5 strips)
        vmax = max(0.2, float(weights[list(patterns)].max()))
        ax.imshow(weights[zones][cell], extent=(0, 1, 1, 0), cmap="viridis", vmin=0, vmax=vmax)
        for z in range(1, ZONES):  # the strips' boundaries: no cell crosses one
            ax.plot([z / ZONES] * 2, [0, 1], color="white", lw=0.6)
        shown = ", ".join(f"z{z}" for z in range(ZONES) if zones >> z & 1)
        title = f"level 2 skipped, zones: {shown}" if direct else "refined zones: " + (shown or "none (level 2 only)")
        _frame(ax, title)
        _points(ax, pos, members, labels=False)
    _save(fig, path)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "images"))
    draw(os.path.normpath(ap.parse_args().out))


if __name__ == "__main__":
    main()
