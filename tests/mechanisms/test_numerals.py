"""Numbers written as text read as written (mechanisms._numerals): plain ASCII decimal notation only."""

import math

import pytest

from mechanisms._numerals import decimal_integer, decimal_number


@pytest.mark.parametrize("text, value", [("3", 3.0), ("-2.5e3", -2500.0), (" .5 ", 0.5), ("1.", 1.0),
                                         ("+4E-2", 0.04), ("0e-999", 0.0), ("1e400", math.inf)])
def test_decimal_notation_reads_as_float_does(text, value):
    assert decimal_number(text) == value


def test_the_words_for_infinity_and_nan_are_left_to_the_callers_finite_checks():
    assert decimal_number("-Infinity") == -math.inf and math.isnan(decimal_number("nan"))


@pytest.mark.parametrize("text", ["٣", "1_0", "0x10", "", "1e", "--1", "1,5", "½"])
def test_what_float_would_read_otherwise_is_refused(text):
    """float('٣') is 3 and float('1_0') is 10: not what was written."""
    with pytest.raises(ValueError, match="expected a number, got"):
        decimal_number(text)


def test_a_nonzero_number_below_the_smallest_float_is_refused():
    with pytest.raises(ValueError, match="below the smallest float"):
        decimal_number("1e-400")


@pytest.mark.parametrize("text, ok", [("12", True), (" -3 ", True), ("٣", False), ("1_0", False), ("1.0", False)])
def test_decimal_integers(text, ok):
    if ok:
        assert decimal_integer(text) == int(text)
    else:
        with pytest.raises(ValueError):
            decimal_integer(text)
