"""Mitsuba's warnings during the bench: gathered, summed up in one line (listed with --verbose),
and Mitsuba's own log restored after."""

from __future__ import annotations

import pytest

from patina.bench.mitsuba_log import gathered_mitsuba_warnings

mi = pytest.importorskip("mitsuba")


@pytest.fixture(autouse=True)
def variant():
    mi.set_variant("scalar_rgb")


def _warn(text: str) -> None:
    mi.Log(mi.LogLevel.Warn, text)


def test_warnings_are_gathered_and_summed_up_in_one_line(capfd):
    with gathered_mitsuba_warnings() as warnings:
        for _ in range(3):
            _warn("Sample count rounded up to 132")
        _warn("something else")
        during = capfd.readouterr()
    assert during.out == "" and during.err == ""  # nothing while the bench runs
    assert sum(warnings.values()) == 4
    after = capfd.readouterr()
    lines = after.err.strip().splitlines()
    assert after.out == "" and len(lines) == 1, after
    assert "Mitsuba warned 4 times, 3 x" in lines[0] and "Sample count rounded up to 132" in lines[0]
    assert "1 other kinds" in lines[0] and "--verbose" in lines[0] and "\x1b[" not in lines[0]


def test_verbose_lists_each_warning_once_with_its_count(capfd):
    with gathered_mitsuba_warnings(verbose=True):
        for _ in range(2):
            _warn("twice")
        _warn("once")
    err = capfd.readouterr().err
    assert err.count("twice") == 1 and err.count("once") == 1 and "2 x" in err and "1 x" in err


def test_mitsubas_log_is_restored_after(capfd):
    with gathered_mitsuba_warnings():
        pass
    assert capfd.readouterr().err == ""  # no warning, no line
    _warn("after the bench")
    captured = capfd.readouterr()
    assert "after the bench" in captured.out + captured.err
