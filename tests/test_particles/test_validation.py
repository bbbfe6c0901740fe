"""The shared argument checks of :mod:`particles.validation` on hostile values: booleans,
complex numbers, huge integers, non-finite values inside lists, equal values spelled
differently, and values whose ``repr`` is very long.  Every case raises ``InvalidArgumentError``
naming the argument, never ``TypeError``, ``OverflowError`` or a NumPy warning."""

from __future__ import annotations

import numpy as np
import pytest

from particles.parsing import parse_float_list
from particles.validation import (
    SHOWN_CHARACTERS,
    InvalidArgumentError,
    check_count,
    check_dimension,
    check_nonnegative,
    check_positive,
    check_restitution,
    check_times,
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


@pytest.mark.parametrize("text", ["1_000", "1_0e-1", "1e-400", "-1e-999"])
def test_a_number_with_underscores_or_that_reads_as_zero_is_refused(text):
    from particles.parsing import parse_float_list, parse_int
    from particles.validation import check_real

    with pytest.raises(InvalidArgumentError, match="restitution"):
        check_real(text, "restitution")
    with pytest.raises(InvalidArgumentError, match="tau"):
        parse_float_list(f"1,{text}", "tau")
    if "_" in text:
        with pytest.raises(InvalidArgumentError, match="seed"):
            parse_int(text, "seed")


@pytest.mark.parametrize("text,value", [("0", 0.0), ("-0.0", 0.0), ("0e5", 0.0), ("1e-300", 1e-300),
                                        ("5e-324", 5e-324)])
def test_zero_and_small_numbers_are_still_read(text, value):
    from particles.validation import check_real

    assert check_real(text, "x") == value


def test_a_name_too_long_is_shown_with_its_own_length(tmp_path):
    # Before, the path was cut to 200 characters and then cut again by the message, which
    # then gave the length of the cut text ("(205 characters)") for a path of ~300.
    import re

    from particles.persistence import check_name_length

    path = tmp_path / ("b" * 300 + ".npz")
    with pytest.raises(InvalidArgumentError) as err:
        check_name_length(path, "save")
    message = str(err.value)
    assert err.value.name == "save" and "at most" in message
    shown_length = int(re.search(r"\((\d+) characters\)", message).group(1))
    assert shown_length >= len(str(path))
    assert message.count("...") == 1


# --------------------------------------------------------------------------- booleans


def _ulam():
    import particles

    return particles.Ulam(n=100, restitution=0.5)


def _simulate_force(value):
    import particles

    particles.simulate(_ulam(), [1.0], 0, progress=False, force=value)


def _simulate_progress(value):
    import particles

    particles.simulate(_ulam(), [1.0], 0, progress=value)


def _budget_force(value):
    from particles.budget import check_budget, estimate_run

    check_budget(estimate_run(_ulam(), 1.0), force=value)


def _workers_force(value):
    from particles.workers import check_workers

    check_workers(1, force=value)


def _progress_bar_enabled(value):
    from particles.progress import progress_bar

    progress_bar(1.0, enabled=value).close()


@pytest.mark.parametrize("value", ["no", "False", 0, 1, 0.0, [], np.array([True])])
@pytest.mark.parametrize("name, call", [
    ("force", _simulate_force), ("progress", _simulate_progress), ("force", _budget_force),
    ("force", _workers_force), ("enabled", _progress_bar_enabled),
])
def test_force_and_progress_are_booleans(name, call, value):
    """``force='no'`` bypassed the budget and ``progress='no'`` showed the
    bar (any truthy value was taken).  A value that is not a bool is refused naming the
    argument and showing the value."""
    import re

    from particles.validation import shown

    with pytest.raises(InvalidArgumentError, match=re.escape(f"argument {name}={shown(value)} ")):
        call(value)


@pytest.mark.parametrize("call", [_simulate_force, _budget_force, _workers_force])
def test_force_is_never_none(call):
    with pytest.raises(InvalidArgumentError, match=r"argument force=None .*True or False"):
        call(None)


def test_true_and_false_still_work_as_force_and_progress():
    from particles.validation import check_bool

    for flag in (True, False, np.True_, np.False_):
        _simulate_force(flag)
        _simulate_progress(flag)
        _budget_force(flag)
        _workers_force(flag)
        assert check_bool(flag, "x") is bool(flag)
    _simulate_progress(None)  # None is "auto"
    _progress_bar_enabled(None)
    _progress_bar_enabled(False)
    assert check_bool(None, "x", none=True) is None
    with pytest.raises(InvalidArgumentError, match=r"argument x=None .*True or False"):
        check_bool(None, "x")
    with pytest.raises(InvalidArgumentError, match=r"argument x='no' .*True, False or None"):
        check_bool("no", "x", none=True)
