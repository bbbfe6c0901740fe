"""The exact results at late times and on hostile input.

``rescaled_moments`` divided two columns of the raw hierarchy, whose M_2 ∝ e^{−2λτ} underflows:
⟨x⁴⟩ came out inf at τ = 1000 and NaN at τ = 3000 (r = 0.5).  It now integrates the rescaled
moments directly; at late times ln⟨x⁴⟩ grows at the exact rate 4λ − (1 − p⁴ − (1 − p)⁴)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from maxwell_kinetics.exact import f_density, f_hat, moment_hierarchy, rescaled_moments
from maxwell_kinetics.model import MaxwellModel
from particles.validation import InvalidArgumentError

NAN, INF = float("nan"), float("inf")


def test_rescaled_moments_stay_finite_and_exact_at_late_times():
    model = MaxwellModel(0.5)
    taus = [100.0, 1000.0, 3000.0]
    mu = rescaled_moments(model, [1.0, 0.0, 1.0, 0.0, 3.0], taus)
    assert np.all(np.isfinite(mu)) and np.all(mu[:, 2] == pytest.approx(1.0, abs=1e-10))
    p, lam = model.p, model.lam
    rate = 4.0 * lam - (1.0 - p**4 - (1.0 - p) ** 4)  # 0.0703 per unit τ at r = 0.5
    slope = math.log(mu[2, 4] / mu[1, 4]) / 2000.0
    # the subleading modes have died out by τ = 1000 (they decay at least like e^{-0.3 τ});
    # what is left is the integrator's rtol 1e-12 accumulated over the run
    assert slope == pytest.approx(rate, rel=1e-8)
    # and the early values are the ratio of the raw hierarchy's columns, as before
    raw = moment_hierarchy(model, [1.0, 0.0, 1.0, 0.0, 3.0], [10.0])[0]
    assert rescaled_moments(model, [1.0, 0.0, 1.0, 0.0, 3.0], [10.0])[0, 4] == pytest.approx(
        raw[4] / raw[2] ** 2, rel=1e-9)


@pytest.mark.parametrize("call, name", [
    (lambda: f_hat(1j), "q"),
    (lambda: f_hat([0.0, NAN]), "q"),
    (lambda: f_hat(True), "q"),
    (lambda: f_density("x"), "x"),
    (lambda: f_density([NAN]), "x"),
    (lambda: moment_hierarchy(0.5, [1.0, 0.0, 1.0], 1.0), "model"),
    (lambda: moment_hierarchy(MaxwellModel(0.5), [1.0, NAN, 1.0], 1.0), "initial_moments"),
    (lambda: moment_hierarchy(MaxwellModel(0.5), [1.0, 0.0, 1.0], -1e6), "tau"),
    (lambda: moment_hierarchy(MaxwellModel(0.5), [1.0, 0.0, 1.0], [2.0, 1.0]), "tau"),
    (lambda: moment_hierarchy(MaxwellModel(0.5), [], 1.0), "initial_moments"),
    (lambda: rescaled_moments(MaxwellModel(0.5), [1.0, 0.0], 1.0), "initial_moments"),
    (lambda: rescaled_moments(MaxwellModel(0.5), [1.0, 0.0, 0.0], 1.0), "initial_moments"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_infinite_arguments_give_the_limits():
    assert f_hat([INF, -INF]).tolist() == [0.0, 0.0]
    assert f_density([INF, 1e200]).tolist() == [0.0, 0.0]
