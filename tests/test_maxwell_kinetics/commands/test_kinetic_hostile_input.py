"""Hostile input to ``solve`` and ``tail-exponent``: duplicate values spelled differently, options
that mean nothing without another, and restitutions so close to 1 that float64 cannot resolve the
answer.  Each is refused in one line naming the user's option (exit 2), before any work."""

from __future__ import annotations

import pytest
from helpers import run_error

from maxwell_kinetics.tails import tail_exponent
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("extra, shown", [
    (["--speed", "1,1.0"], "argument speed='1,1.0'"),
    (["--speed", "0,-0"], "argument speed='0,-0'"),
    (["--speed", "2,1e0,1"], "argument speed='2,1e0,1'"),
    (["--q", "1,1.0"], "argument q='1,1.0'"),
    (["--q", "0,-0"], "argument q='0,-0'"),
    (["--angular", "hard"], "argument angular='hard'"),
    (["--angular", "uniform"], "argument angular='uniform'"),
    (["--angular-rule", "accurate"], "argument angular-rule='accurate'"),
    (["--dimension", "1", "--angular-rule", "fast"], "argument angular-rule='fast'"),
])
def test_solve_refuses_before_any_work(capsys, tmp_path, extra, shown):
    out = tmp_path / "s.npz"
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1", "--resolution", "coarse",
                             "--save", str(out), *extra])
    assert shown in err and err.count("\n") == 1
    assert not out.exists()


def test_tail_exponent_refuses_angular_in_one_dimension(capsys):
    err = run_error(capsys, ["tail-exponent", "--dimension", "1", "-r", "0.5", "--angular",
                             "hard"])
    assert "argument angular='hard'" in err and "--dimension 2 or 3" in err


def test_tail_exponent_in_one_dimension_is_three_halves_up_to_elastic():
    # s* = 3/2 for every r < 1 in d = 1 (1 − p³ − q³ = 3pq); the root found numerically was
    # 1.5024 at r = 1 − 1e-13 (an ill-conditioned balance of O(q²) terms)
    for r in (0.0, 0.5, 1 - 1e-8, 1 - 1e-13, 0.9999999999999999):
        assert tail_exponent(1, r).s == 1.5


@pytest.mark.parametrize("d", [2, 3])
def test_tail_exponent_too_close_to_elastic_is_refused_by_name(capsys, d):
    """s* ~ 1/(1 − r) in d >= 2: at r = 1 − 1e-8 its bracket is lost in float64 (the old code
    raised a RuntimeError with a traceback, exit 1)."""
    with pytest.raises(InvalidArgumentError, match="argument restitution=0.99999999 "):
        tail_exponent(d, 0.99999999)
    err = run_error(capsys, ["tail-exponent", "--dimension", str(d), "-r", "0.99999999"])
    assert "argument restitution='0.99999999'" in err and err.count("\n") == 1


@pytest.mark.parametrize(("argv", "first"), [
    (["solve", "--restitution", "5", "--restitution", "0.5", "--tau", "1"], "restitution='5'"),
    (["solve", "-r", "0.5", "--restitution", "0.6", "--tau", "1"], "restitution='0.5'"),
    (["simulate", "ulam", "--n", "-5", "--n", "100", "--restitution", "0.5", "--tau", "1"],
     "n='-5'"),
    (["reproduce", "--only", "driven_steady", "--only", "nope"], "only='driven_steady'"),
])
def test_an_option_given_twice_is_refused(capsys, argv, first):
    # Before: argparse kept the last value, so the first (even an invalid one, r = 5) was
    # ignored without being checked and the run went on.
    err = run_error(capsys, argv)
    assert f"argument {first} is invalid" in err and "once (it is given again" in err
    assert err.count("\n") == 1
