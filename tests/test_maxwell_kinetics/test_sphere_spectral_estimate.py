"""The spectral hard-sphere solve's estimate of its steps and time, before any integration
(maxwell_kinetics.sphere_spectral.estimate_solve): a solve that cannot finish within
``max_steps``, or (unless forced) would take more than a day, is refused at once by name."""

from __future__ import annotations

import math
import time

import pytest

from maxwell_kinetics.sphere_spectral import SphereOperator, estimate_solve, solve_spheres
from particles.sphere_kernels import HardSpheres, VariableHardSpheres
from particles.validation import InvalidArgumentError

ALPHA = 0.5


def test_the_estimate_follows_the_integrators_time():
    # τ = n t for the Maxwell kernel (γ = 0); for hard disks τ = ln(1 + |σ₀| n t)/|σ₀|, with
    # σ₀ = −ζ₀/2 = −(1 − α²) 4√π/(2·2) at the unit Maxwellian (Haff's cooling rate, exact)
    maxwell = SphereOperator(VariableHardSpheres(ALPHA, exponent=0.0), 2, "coarse")
    F0 = maxwell.initial("gaussian")[0]
    assert estimate_solve(maxwell, F0, 2.0, 3.0)["tau"] == pytest.approx(6.0, rel=1e-12)
    disks = SphereOperator(HardSpheres(ALPHA), 2, "coarse")
    F0 = disks.initial("gaussian")[0]
    sigma = (1 - ALPHA**2) * 4 * math.sqrt(math.pi) / 4
    cost = estimate_solve(disks, F0, 1.0, 1000.0)
    # the grid's σ₀ is the exact one to the truncation of the kernel at the cutoff R = 7 and
    # the grid's error (measured: |σ₀| 1.329255 against 1.329340, 6e-5 relative)
    assert cost["tau"] == pytest.approx(math.log1p(sigma * 1000.0) / sigma, rel=2e-4)
    assert cost["steps"] > estimate_solve(disks, F0, 1.0, 10.0)["steps"]
    assert estimate_solve(disks, F0, 1.0, 0.0) == {"tau": 0.0, "steps": 15.0, "seconds":
                                                   pytest.approx(15.0 * cost["seconds"]
                                                                 / cost["steps"])}


@pytest.mark.parametrize("kernel, t", [(HardSpheres(ALPHA), 10.0),
                                       (VariableHardSpheres(ALPHA, exponent=0.0), 5.0)])
def test_the_estimated_steps_are_within_a_factor_two_of_a_solve(kernel, t):
    # the constants were measured on this grid (and on two others): a solve takes between
    # half and twice the estimated steps
    operator = SphereOperator(kernel, 2, "coarse")
    estimate = estimate_solve(operator, operator.initial("gaussian")[0], 1.0, t)
    steps = solve_spheres(kernel, [t], dimension=2, grid="coarse").steps
    assert 0.5 < steps / estimate["steps"] < 2.0, (steps, estimate)


def test_a_solve_past_max_steps_or_a_day_is_refused_before_it_runs():
    maxwell = VariableHardSpheres(ALPHA, exponent=0.0)
    start = time.perf_counter()
    with pytest.raises(InvalidArgumentError, match=r"argument t=30000\.0.*max_steps = 100000"):
        solve_spheres(maxwell, [30000.0], dimension=2, grid="coarse")
    # about 1.5·10⁵ steps of 0.03-0.3 s on "default": days; refused unless forced
    with pytest.raises(InvalidArgumentError, match=r"argument t=.*one day|argument t=.*86400"):
        solve_spheres(maxwell, [60000.0], dimension=2, grid="default", max_steps=10**6)
    with pytest.raises(InvalidArgumentError, match="force"):
        solve_spheres(maxwell, [1.0], dimension=2, grid="coarse", force="no")
    assert time.perf_counter() - start < 60.0  # refused before any integration
