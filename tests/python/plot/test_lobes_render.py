"""The 3-D lobe view's labels: none drawn over another or over the incidence arrow."""

from __future__ import annotations

import numpy as np
import pytest

from patina.plot.lobes import incidence_direction
from patina.plot.lobes_render import LABEL_CLEARANCE, WI_ARROW, distance_to_segment, label_anchors, screen_position


@pytest.mark.parametrize("theta_i", range(0, 90, 5))
def test_labels_stand_clear_of_each_other_and_of_the_wi_arrow(theta_i):
    wi = incidence_direction(theta_i).astype(np.float64)
    labels = label_anchors(wi)
    assert {"n (z)", "x", "y", "wi"} <= set(labels) and ("mirror" in labels) == (theta_i > 0)
    names = list(labels)
    on_screen = screen_position(np.array([labels[n] for n in names]))
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            gap = np.linalg.norm(on_screen[i] - on_screen[j])
            assert gap > LABEL_CLEARANCE, (theta_i, names[i], names[j], gap)
    head, tail = screen_position(np.array([WI_ARROW[0] * wi, WI_ARROW[1] * wi]))
    for name in names:
        if name != "wi":
            gap = distance_to_segment(on_screen[names.index(name)], head, tail)
            assert gap > LABEL_CLEARANCE / 2, (theta_i, name, "on the wi arrow", gap)


def test_the_normal_label_keeps_its_place_above_the_normal_when_nothing_covers_it():
    assert np.allclose(label_anchors(incidence_direction(45).astype(np.float64))["n (z)"], (0, 0, 1.3))
    assert not np.allclose(label_anchors(incidence_direction(0).astype(np.float64))["n (z)"], (0, 0, 1.3))
