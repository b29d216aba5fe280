"""EN 13201-2 classes and EN 12464-1 requirements checked with their margins."""

from __future__ import annotations

import pytest

from patina.errors import FormatError
from patina.lighting.classes import ROAD_CLASSES, check, indoor_requirements, road_class


def test_every_class_of_the_standard_exists_and_is_ordered_by_strictness():
    assert sorted(ROAD_CLASSES) == sorted(
        [f"M{i}" for i in range(1, 7)] + [f"C{i}" for i in range(6)] + [f"P{i}" for i in range(1, 7)]
    )
    lav = [ROAD_CLASSES[f"M{i}"]["L_av"][1] for i in range(1, 7)]
    assert lav == sorted(lav, reverse=True) and lav[0] == 2.0 and lav[-1] == 0.3


def test_pass_fail_and_margin():
    checks = {
        c.figure: c for c in check(road_class("m3"), {"L_av": 1.1, "U0": 0.35, "Ul": 0.6, "TI": 12.0, "EIR": None})
    }
    assert checks["L_av"].passed and checks["L_av"].margin == pytest.approx(0.1)
    assert checks["U0"].passed is False and checks["U0"].margin == pytest.approx(-0.125)
    assert checks["Ul"].passed  # equal to the limit passes
    assert checks["TI"].passed and checks["TI"].margin == pytest.approx(0.2)
    assert checks["EIR"].passed is None


def test_a_class_that_does_not_exist_is_refused_naming_the_option():
    with pytest.raises(FormatError) as e:
        road_class("M7")
    assert e.value.where == "--class" and "M1-M6, C0-C5, P1-P6" in e.value.problem


def test_indoor_requirements_are_checked_for_names_and_values():
    assert indoor_requirements({"Em": 500, "UGR": 19}, "p.json") == {"Em": ("min", 500.0), "UGR": ("max", 19.0)}
    with pytest.raises(FormatError, match=r"requirements\.Lux"):
        indoor_requirements({"Lux": 500}, "p.json")
    with pytest.raises(FormatError, match=r"requirements\.U0"):
        indoor_requirements({"U0": -1}, "p.json")
