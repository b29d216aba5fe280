"""The plan figure: cells centred on their sensors, a colour bar no taller than the plot,
iso-lux lines and the luminaires drawn."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from patina.lighting.plan import PlanLuminaire, cell_edges, plan_figure, write_plan


@given(st.lists(st.floats(-100, 100), min_size=2, max_size=30, unique=True))
def test_every_cell_is_centred_on_its_sensor_for_evenly_spaced_sensors(values):
    lo, hi = min(values), max(values)
    if hi - lo < 1e-3:
        return
    centres = np.linspace(lo, hi, len(values))
    edges = cell_edges(centres)
    np.testing.assert_allclose((edges[1:] + edges[:-1]) / 2, centres, atol=1e-9 * (1 + abs(hi) + abs(lo)))


def test_the_street_example_of_the_issue_draws_the_sensor_at_minus_15_in_the_middle_of_its_cell():
    z = np.linspace(-15, 15, 31)
    edges = cell_edges(z)
    assert edges[0] == -15.5 and edges[1] == -14.5


def test_plan_has_contours_luminaires_and_a_colour_bar_as_tall_as_the_plot(tmp_path):
    x, z = np.linspace(-3, 3, 13), np.linspace(-2, 2, 9)
    lux = 300 / (1 + np.add.outer(z**2, x**2))
    fig = plan_figure(lux, x, z, "test", [PlanLuminaire(0, 0, 2.8, (0.5, -1, 0))])
    fig.canvas.draw()
    plot, bar = fig.axes
    assert bar.get_position().height <= plot.get_position().height + 1e-9
    assert any(c.__class__.__name__ == "QuadContourSet" for c in plot._children + plot.collections)
    assert "luminaires" in [t.get_text() for t in fig.legends[0].get_texts()]
    out = tmp_path / "plan.png"
    write_plan(str(out), lux, x, z, "test")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
