"""The driven steady state near the elastic limit and hostile arguments: the density's grid
covers the law however wide it is (variance D/(pq) → ∞ as r → 1), at a cost that stays bounded,
and arguments that cannot be computed are refused by name."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from helpers import ROOT

from maxwell_kinetics.driven import cumulants, moments, steady_state, steady_variance
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("r", [0.9, 0.99, 0.999, 1 - 1e-8, 1 - 1e-14])
def test_density_has_the_exact_norm_variance_and_kurtosis_near_elastic(r):
    """Sums over the returned grid against the exact variance D/(pq) and kurtosis: to 1e-10
    (the FFT's round-off is ~1e-14 here).  The old ±60√D grid, narrower than the law for
    r → 1, returned 55% of the variance at r = 0.999 and ran for days near 1 − 1e-8."""
    st = steady_state(r, 2.0)
    x, P = st.velocity, st.density
    dx = x[1] - x[0]
    assert P.sum() * dx == pytest.approx(1.0, abs=1e-10)
    assert (x * x * P).sum() * dx == pytest.approx(st.variance, rel=1e-10)
    assert (x**4 * P).sum() * dx / st.variance**2 == pytest.approx(st.kurtosis, rel=1e-10)
    assert np.isclose(st.variance, steady_variance(r, 2.0), rtol=0)


def test_steady_near_elastic_finishes_quickly_from_the_command_line():
    """r = 1 − 1e-8: the old tree expansion had ~4e8 levels (about a day); now < 1 s of work."""
    done = subprocess.run(
        [sys.executable, "-m", "maxwell_kinetics.app.cli", "steady", "-r", "0.99999999", "-D", "1",
         "--json"], capture_output=True, text=True, timeout=30, cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": ""})
    assert done.returncode == 0, done.stderr
    # D/(pq) = 2e8 (to the round-off of q = 1 − p = 5e-9 in float64, 1e-8 relative)
    assert json.loads(done.stdout)["variance"] == pytest.approx(2e8, rel=1e-7)


def test_restitution_whose_p_rounds_to_one_is_refused():
    r = float(np.nextafter(1.0, 0.0))  # (1 + r)/2 rounds to 1: pq = 0
    with pytest.raises(InvalidArgumentError, match="argument restitution="):
        steady_state(r, 1.0)
    with pytest.raises(InvalidArgumentError, match="argument restitution="):
        moments([1.0], r, 0.0)


@pytest.mark.parametrize("count", [0, -1, 2.5, True, 86, 10**6, "4"])
def test_cumulant_count_is_checked(count):
    """(2j)! overflows float64 beyond 2j = 170 (old: a raw OverflowError at 100, an empty
    array for 0, True taken as 1)."""
    with pytest.raises(InvalidArgumentError, match="argument count="):
        cumulants(0.5, 1.0, count)
    with pytest.raises(InvalidArgumentError, match="argument count="):
        steady_state(0.5, 1.0, count)


def test_largest_cumulant_count_is_finite():
    assert np.all(np.isfinite(cumulants(0.5, 1.0, 85)))
