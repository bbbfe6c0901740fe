"""``fixed-point`` (and :func:`maxwell_kinetics.stationary.fixed_point`) refuse the degrees where
the 1D collocation is too ill-conditioned to find f̂, and still converge below them."""

from __future__ import annotations

import json

import pytest
from helpers import run_error

from maxwell_kinetics.app.cli import main
from maxwell_kinetics.stationary import MAX_DEGREE_1D, fixed_point
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("n", ["800", "1000", "257"])
def test_a_degree_beyond_the_well_conditioned_range_is_refused(capsys, n):
    # Measured before the cap: --n 800 and 1000 gave max |G - f_hat| = 0.224 at r = 0.5 with
    # "converged": true and exit 0 (a wrong function with a residual of 4e-9).
    err = run_error(capsys, ["fixed-point", "-r", "0.5", "--n", n, "--json"])
    assert f"n='{n}'" in err and f"--n <= {MAX_DEGREE_1D}" in err and "Traceback" not in err
    with pytest.raises(InvalidArgumentError, match=f"n={int(n)}"):
        fixed_point(0.5, n=int(n))


def test_the_largest_allowed_degree_still_converges_to_f_hat(capsys):
    # At n = 256 the measured max errors are 2e-10 (r = 0.5) and 1.9e-9 (r = 0.99); 1e-8 leaves
    # a margin of 5 over the worse one.  The refused n = 700 gave 0.22 at r = 0.5.
    assert main(["fixed-point", "-r", "0.99", "--n", str(MAX_DEGREE_1D), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] is True and out["max_error"] <= 1e-8


def test_angular_without_a_dimension_above_one_is_refused(capsys):
    err = run_error(capsys, ["fixed-point", "-r", "0.5", "--angular", "hard"])
    assert "angular='hard'" in err and "--dimension 2 or 3" in err
    err = run_error(capsys, ["fixed-point", "-r", "0.5", "--angular", "nosuch", "--dimension",
                             "2"])
    assert "angular='nosuch'" in err


def test_a_near_elastic_restitution_that_meets_a_wrong_function_is_not_converged(capsys):
    # r = 1 - 1e-9 (lambda = 5e-10): Newton stopped after 5 steps on a function 0.27 from f_hat
    # with residual 2.4e-16 and reported "converged": true, exit 0.  The residual is small only
    # against 1, not against lambda.
    fp = fixed_point(0.999999999)
    assert fp.max_error > 0.1 and not fp.converged
    assert main(["fixed-point", "-r", "0.999999999", "--json"]) == 3
    captured = capsys.readouterr()
    assert json.loads(captured.out)["converged"] is False and "did not converge" in captured.err
    # r = 0.9995 still converges (measured max error 2.6e-8, residual 1e-12 lambda)
    good = fixed_point(0.9995)
    assert good.converged and good.max_error < 1e-7
