"""Values a measurement leaves below zero (python/patina/table/formats/measurement_noise.py):
noise down to 1 % of the largest value set to 0 and counted; anything further below, or not
finite, refused at its index."""

from __future__ import annotations

import numpy as np
import pytest

from patina.table.formats.measurement_noise import checked_measurement


class Refused(Exception):
    pass


def refuse(flat: int, problem: str):
    raise Refused(flat, problem)


def test_noise_set_to_zero_and_counted():
    values = np.array([[2.0, -0.01], [-0.02, 0.5]])
    kept, note = checked_measurement(values, refuse)
    assert kept.tolist() == [[2.0, 0.0], [0.0, 0.5]]
    assert note.startswith("2 values slightly below 0 set to 0") and "-0.02, 1 % of the largest" in note


def test_clean_values_kept_as_they_are():
    values = np.array([0.0, 0.3, 1.0])
    kept, note = checked_measurement(values, refuse)
    assert kept is values and note == ""


@pytest.mark.parametrize(
    "values, index, problem",
    [
        ([1.0, -0.0101, 0.5], 1, "negative beyond measurement noise (below -0.01)"),
        ([-0.001, -0.002], 0, "negative beyond measurement noise (below 0)"),  # nothing above zero: no noise floor
        ([1.0, 0.2, np.nan, -5.0], 2, "not finite"),
    ],
)
def test_values_beyond_the_noise_refused_at_their_index(values, index, problem):
    with pytest.raises(Refused) as e:
        checked_measurement(np.array(values), refuse)
    assert e.value.args == (index, problem)
