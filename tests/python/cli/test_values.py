"""The option value types, property-tested: any text is taken as the number it plainly writes,
in range, or refused with ArgumentTypeError saying what is allowed; nothing else escapes."""

from __future__ import annotations

import argparse
import math
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina.cli.values import integer, number, number_or, numbers

SETTINGS = settings(max_examples=300, deadline=None)
WHOLE = integer(1, 1024)
REAL = number(-1e5, 1e5)
# text near numbers: digits, signs, points, exponents, spaces, underscores, full-width digits, letters
NEAR_NUMBERS = st.text(alphabet="0123456789+-.eE _\uff18\u0660xinfa,", max_size=12)


@SETTINGS
@given(NEAR_NUMBERS | st.text(max_size=8) | st.integers(-(10**6), 10**6).map(str))
def test_integer_takes_plain_ascii_whole_numbers_in_range_only(text):
    try:
        value = WHOLE(text)
    except argparse.ArgumentTypeError as e:
        assert str(e) == f"expected a whole number from 1 to 1024, got '{text}'"
        assert not (re.fullmatch(r"[+-]?[0-9]+", text) and 1 <= int(text) <= 1024)
        return
    assert re.fullmatch(r"[+-]?[0-9]+", text) and value == int(text) and 1 <= value <= 1024


@SETTINGS
@given(NEAR_NUMBERS | st.text(max_size=8) | st.floats(allow_nan=True, allow_infinity=True).map(repr))
def test_number_takes_finite_ascii_decimals_in_range_only(text):
    try:
        value = REAL(text)
    except argparse.ArgumentTypeError as e:
        assert str(e) == f"expected a number from -100000 to 100000, got '{text}'"
        return
    assert text.isascii() and text == text.strip() and "_" not in text
    assert math.isfinite(value) and -1e5 <= value <= 1e5 and value == float(text)


@pytest.mark.parametrize("text", ["1_0", " 8", "8 ", "\uff18", "0x10", "1e3", "8.0", "", "+"])
def test_what_int_takes_and_an_option_does_not(text):
    with pytest.raises(argparse.ArgumentTypeError):
        WHOLE(text)


@pytest.mark.parametrize("text", ["nan", "inf", "-inf", "1e999", "1_0.5", " 1", "\uff11.5", "1e", "."])
def test_what_float_takes_and_an_option_does_not(text):
    with pytest.raises(argparse.ArgumentTypeError):
        REAL(text)


def test_the_range_ends_are_allowed_and_big_bounds_read_as_powers_of_two():
    assert WHOLE("1") == 1 and WHOLE("+1024") == 1024 and REAL("-1e5") == -1e5 and REAL(".5") == 0.5
    assert integer(1, 1 << 20).allowed == "a whole number from 1 to 2^20"
    assert integer(0, 2**63 - 1).allowed == "a whole number from 0 to 2^63-1"


def test_a_number_above_its_low_end():
    eta = number(1, 3, above=True)
    assert eta("1.0001") == 1.0001 and eta("3") == 3
    with pytest.raises(argparse.ArgumentTypeError, match=r"expected a number above 1, at most 3, got '1'"):
        eta("1")


def test_a_word_or_a_number():
    stops = number_or("auto", -64, 64)
    assert stops("auto") == "auto" and stops("-1.5") == "-1.5"
    with pytest.raises(argparse.ArgumentTypeError, match=r"from -64 to 64, or auto, got 'bright'"):
        stops("bright")


@SETTINGS
@given(st.lists(NEAR_NUMBERS, min_size=1, max_size=7))
def test_comma_separated_values_name_the_part_that_is_wrong(words):
    grid = numbers((REAL,) * 2 + (WHOLE,), "X,Z,N")
    text = ",".join(words)
    try:
        assert grid(text) == text
    except argparse.ArgumentTypeError as e:
        message = str(e)
        assert message.startswith(("expected X,Z,N (3 values)", "X: ", "Z: ", "N: ")), message
        return
    x, z, n = text.split(",")
    assert REAL(x) == float(x) and REAL(z) == float(z) and WHOLE(n) == int(n)
