"""The shared argument checks of :mod:`particles.validation` on hostile values: booleans,
complex numbers, huge integers, non-finite values inside lists, equal values spelled
differently, and values whose ``repr`` is very long.  Every case raises ``InvalidArgumentError``
naming the argument, never ``TypeError``, ``OverflowError`` or a NumPy warning."""

from __future__ import annotations

import numpy as np
import pytest

from particles.validation import (
    SHOWN_CHARACTERS,
    InvalidArgumentError,
    check_count,
    check_dimension,
    check_nonnegative,
    check_positive,
    check_restitution,
    check_times,
    parse_float_list,
)


@pytest.mark.parametrize("call", [
    lambda: check_positive(True, "x"),
    lambda: check_positive(np.True_, "x"),
    lambda: check_positive(np.complex128(1.0), "x"),
    lambda: check_positive(10**400, "x"),
    lambda: check_nonnegative(False, "x"),
    lambda: check_restitution(np.True_, "x"),
    lambda: check_count(np.True_, "x", 1),
    lambda: check_count(np.complex128(8.0), "x", 1),
    lambda: check_count("8", "x", 1),
    lambda: check_dimension(1 + 0j, "x"),
    lambda: check_dimension(np.True_, "x"),
    lambda: check_dimension("2", "x"),
    lambda: check_times([False, True], "x"),
    lambda: check_times([10**400], "x"),
    lambda: check_times(["1", "2"], "x"),
    lambda: parse_float_list([None], "x"),
    lambda: parse_float_list([1j], "x"),
    lambda: parse_float_list([True], "x"),
    lambda: parse_float_list(5, "x"),
    lambda: parse_float_list([], "x"),
])
def test_booleans_complex_and_huge_values_are_refused_as_invalid_arguments(call):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == "x"


@pytest.mark.parametrize("text, word", [
    ("nan", "finite"), ("1,inf", "finite"), ("1e400", "finite"), ("-inf,2", "finite"),
    ("0,-0", "0 is repeated"), ("1000,1000.0", "1000 is repeated"), ("1e3,1000", "repeated"),
    ("2, 2", "repeated"), ([3.0, 3], "repeated"),
])
def test_float_lists_refuse_non_finite_and_repeated_values(text, word):
    with pytest.raises(InvalidArgumentError, match=word) as info:
        parse_float_list(text, "t")
    assert info.value.name == "t"


def test_valid_values_are_still_taken():
    assert parse_float_list("1, 10,1e2", "t") == [1.0, 10.0, 100.0]
    assert parse_float_list([0.5, np.float32(1.5), 2], "t") == [0.5, 1.5, 2.0]
    assert check_positive("2.5", "x") == 2.5 and check_count(np.int64(8), "n", 1) == 8
    assert check_count(8.0, "n", 1) == 8 and check_dimension(2.0) == 2
    assert check_times(np.array([1, 2])).tolist() == [1.0, 2.0]


def test_a_long_value_is_cut_in_the_message():
    value = "x" * 5000
    with pytest.raises(InvalidArgumentError) as info:
        check_positive(value, "density")
    message = str(info.value)
    assert message.startswith("argument density='xxx") and "5002 characters" in message
    assert len(message) < SHOWN_CHARACTERS + 100  # the cut value and the words around it
    assert info.value.value == value  # the attribute keeps it whole
    with pytest.raises(InvalidArgumentError) as info:
        check_times(list(range(10_000, 0, -1)), "t")
    assert len(str(info.value)) < SHOWN_CHARACTERS + 100


def test_minus_zero_is_zero():
    # "--driving -0" was stored and shown as -0.0; "--tau -0" as the time -0
    assert str(check_nonnegative("-0", "driving")) == "0.0"
    assert [str(x) for x in parse_float_list("-0,1", "tau")] == ["0.0", "1.0"]
