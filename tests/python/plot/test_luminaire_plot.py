"""The polar intensity diagram of a luminaire: rings labelled with their values in cd, a legend of the planes."""

from __future__ import annotations

import pytest

import patina.plot.luminaire as luminaire_plot
from patina.bundled import materials_path
from patina.photometry import load_luminaire


@pytest.mark.parametrize("name", ["floodlight.ies", "downlight.ies", "streetlight.ldt"])
def test_rings_carry_their_candela_and_the_planes_a_legend(monkeypatch, name):
    figures = []
    monkeypatch.setattr(luminaire_plot, "save_figure", lambda fig, path: figures.append(fig))
    luminaire_plot.plot_luminaire(load_luminaire(materials_path("luminaires", name)), "unused.png")
    (fig,) = figures
    ax = fig.axes[0]
    ax.figure.canvas.draw()  # the formatter fills the labels in when drawn
    rings = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
    assert len(rings) >= 3 and all(r.endswith(" cd") for r in rings), rings
    assert all(t.get_text().endswith("°") for t in ax.get_xticklabels())
    assert len(ax.get_legend().get_texts()) >= 2
