"""The numbers of ``solve --rate relative_velocity`` and ``fixed-point --rate relative_velocity``
are read as typed, by the rules of every other option: digit-group underscores (``0_5``, which
Python's float reads as 5, and ``1_0e-1``, which it reads as 1.0) and a non-zero number that
underflows to 0 (``1e-400``) are refused naming the option and showing the text, as under
``--rate constant``; the library's range refusals show the text typed, not the value read.  A
tiny positive exponent reaches its gamma -> 0 limit in the reach check instead of "t <= 0"."""

from __future__ import annotations

import math
import time

import pytest
from helpers import run_error

from maxwell_kinetics.inelastic_boltzmann import SMALLEST_SCALE, check_reach
from maxwell_kinetics.model import RelativeVelocityModel
from maxwell_kinetics.velocity_grid import default_grid
from particles.validation import InvalidArgumentError

SOLVE = ["solve", "--rate", "relative_velocity", "--t", "0.1", "--json"]
FIXED_POINT = ["fixed-point", "--rate", "relative_velocity", "--json"]
UNDERSCORES = "without underscores"
UNDERFLOW = "this one reads as 0"


@pytest.mark.parametrize("extra, shown, why", [
    (["-r", "0_5"], "restitution='0_5'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "1_0e-1"], "exponent='1_0e-1'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "1e-400"], "exponent='1e-400'", UNDERFLOW),
    (["-r", "0.5", "--density", "1_0"], "density='1_0'", UNDERSCORES),
    (["-r", "0.5", "--density", "1e-400"], "density='1e-400'", UNDERFLOW),
    (["-r", "0.5", "--half-width", "6_0"], "half-width='6_0'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "0", "--core-spacing", "0_1"], "core-spacing='0_1'",
     UNDERSCORES),
    (["-r", "0.5", "--points", "2_01"], "points='2_01'", UNDERSCORES),
    # the ranges: the text typed, not the float read from it
    (["-r", "1.50"], "restitution='1.50'", "in [0, 1]"),
    (["-r", "0.5", "--exponent", "3"], "exponent='3'", "in [0, 2]"),
    (["-r", "0.5", "--half-width", "2"], "half-width='2'", "--half-width >="),
    (["-r", "0.5", "--exponent", "0", "--core-spacing", "0.30"], "core-spacing='0.30'",
     "below the uniform spacing"),
])
def test_solve_relative_velocity_reads_numbers_as_typed(capsys, extra, shown, why):
    err = run_error(capsys, [*SOLVE, *extra])
    assert f"argument {shown} is invalid" in err and why in err, err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_the_constant_rate_refuses_the_same_texts_the_same_way(capsys):
    # the reference: --rate constant refused them already
    for rate in (["--rate", "constant", "--tau", "1"], ["--rate", "relative_velocity", "--t",
                                                         "1"]):
        err = run_error(capsys, ["solve", "-r", "0_5", *rate])
        assert "argument restitution='0_5' is invalid" in err and UNDERSCORES in err


@pytest.mark.parametrize("extra, shown, why", [
    (["-r", "0_5"], "restitution='0_5'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "1_0e-1"], "exponent='1_0e-1'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "1e-400"], "exponent='1e-400'", UNDERFLOW),
    (["-r", "0.5", "--half-width", "2_0"], "half-width='2_0'", UNDERSCORES),
    (["-r", "0.5", "--exponent", "0"], "exponent='0'", "gamma > 0"),
    (["-r", "1.50"], "restitution='1.50'", "in [0, 1]"),
])
def test_fixed_point_relative_velocity_reads_numbers_as_typed(capsys, extra, shown, why):
    err = run_error(capsys, [*FIXED_POINT, *extra])
    assert f"argument {shown} is invalid" in err and why in err, err


def test_a_tiny_exponent_has_the_reach_of_its_limit_not_zero():
    # (S^-gamma - 1)/(gamma rate) cancelled to 0 for gamma below ~1e-16: "t <= 0" for any t
    log_scale = -math.log(SMALLEST_SCALE)
    lam, kappa = 3.0 / 16.0, 2.0  # r = 0.5; kappa -> 4 Gamma(3/2)/sqrt(pi) = 2 at gamma = 0
    limit = log_scale / (lam * kappa / 2.0)  # s = exp(-lam n kappa t/2): the Maxwell model's
    for gamma in (1e-300, 1e-20, 1e-12):
        model = RelativeVelocityModel(0.5, exponent=gamma)
        check_reach(model, 1.0, 0.999 * limit, default_grid(gamma), 10**6)
        with pytest.raises(InvalidArgumentError) as err:
            check_reach(model, 1.0, 1.001 * limit, default_grid(gamma), 10**6)
        assert err.value.name == "t"
    # continuous with a small but resolved gamma
    model = RelativeVelocityModel(0.5, exponent=1e-6)
    check_reach(model, 1.0, 0.999 * limit, default_grid(1e-6), 10**6)


def test_solve_with_a_tiny_exponent_is_refused_only_beyond_its_reach(capsys):
    start = time.perf_counter()
    err = run_error(capsys, [*SOLVE[:3], "--t", "0,1e6", "-r", "0.5", "--exponent", "1e-300"])
    assert "argument t='0,1e6' is invalid" in err and "t <= 184 here" in err, err
    assert time.perf_counter() - start < 5.0  # before any compilation
