"""The homogeneous cooling state of hard disks by Newton–Krylov (maxwell_kinetics.sphere_steady,
cooling_state(method="newton")) against the long march of the scaled equation on the same grid,
and the operator's tables built once per (grid, kernel, α) in a process.

Grid: the named "coarse" grid of d = 2 (32² modes), α = 0.5, as in test_hard_sphere_spectral.
"""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import _sphere_spectral_scheme as scheme
from maxwell_kinetics import sphere_spectral
from maxwell_kinetics.sphere_grid import SphereGrid
from maxwell_kinetics.sphere_solution import sonine
from maxwell_kinetics.sphere_spectral import SphereOperator, cooling_state
from maxwell_kinetics.sphere_steady import SteadyStateError, steady_state
from particles.sphere_kernels import HardSpheres, VariableHardSpheres
from particles.validation import InvalidArgumentError

ALPHA = 0.5


@pytest.fixture(scope="module")
def marched():
    # the reference: the march alone to the residual 1e-8 (τ = 3.25; its a₂ moves by 1.2e-9
    # from there to the steady state, measured)
    return cooling_state(HardSpheres(ALPHA), dimension=2, grid="coarse", method="march",
                         tolerance=1e-8, max_tau=20.0)


@pytest.fixture(scope="module")
def newton():
    return cooling_state(HardSpheres(ALPHA), dimension=2, grid="coarse")


def test_newton_reaches_the_marched_cooling_state(marched, newton):
    # a₂, a₃ to 1e-6 of the long march (measured: 1.2e-9 and 4e-9), the residual 1e-10
    # reported, and mass, momentum and ⟨|c|²⟩ = d exact on the grid
    assert newton.method == "newton" and newton.newton_steps >= 1
    assert newton.residual < 1e-10
    assert abs(newton.a2 - marched.a2) < 1e-6, (newton.a2, marched.a2)
    assert abs(newton.a3 - marched.a3) < 1e-6, (newton.a3, marched.a3)
    assert newton.cooling_rate == pytest.approx(marched.cooling_rate, rel=1e-6)
    operator = SphereOperator(HardSpheres(ALPHA), 2, "coarse")
    c, w = operator.nodes, operator.weight
    assert abs(newton.F.sum() * w - 1.0) < 1e-12
    assert np.all(np.abs(np.tensordot(newton.F, c, axes=2) * w) < 1e-12)
    assert abs(np.sum(newton.F * np.sum(c * c, axis=-1)) * w - 2.0) < 1e-11
    rhs, _ = operator.scaled_rhs(newton.F)
    assert np.max(np.abs(rhs)) / np.max(newton.F) == pytest.approx(newton.residual, rel=0.5,
                                                                  abs=1e-12)
    assert newton.history[-1, 3] == newton.residual
    assert sonine(newton.F, c, w) == (newton.a2, newton.a3)


def test_newton_refuses_a_state_it_does_not_reach(newton):
    # one Newton step from the Maxwellian cannot reach 1e-10: refused, naming the residual
    operator = SphereOperator(HardSpheres(ALPHA), 2, "coarse")
    with pytest.raises(SteadyStateError, match=r"did not reach the residual 1e-10: .* after 1 "
                                                r"Newton steps"):
        steady_state(operator, operator.initial("gaussian")[0], max_newton=1)
    # λF of the cooling state has a right-hand side λ² × round-off but the wrong mass: not
    # steady until Newton restores the moments (to the tolerance 1e-10)
    solved = steady_state(operator, (1.0 + 1e-6) * newton.F)
    assert solved.newton_steps >= 1
    assert abs(solved.F.sum() * operator.weight - 1.0) < 1e-10
    assert np.max(np.abs(solved.F - newton.F)) < 1e-8 * np.max(newton.F)
    with pytest.raises(InvalidArgumentError, match="start"):
        steady_state(operator, newton.F[:-1])
    with pytest.raises(InvalidArgumentError, match="method"):
        cooling_state(HardSpheres(ALPHA), dimension=2, grid="coarse", method="secant")
    with pytest.raises(InvalidArgumentError, match="march_tau"):
        cooling_state(HardSpheres(ALPHA), dimension=2, grid="coarse", march_tau=-1.0)


def test_an_operator_of_the_same_parameters_does_not_rebuild_its_tables(monkeypatch):
    # a small grid of its own, so that the count sees only this test's builds
    builds = []
    original = scheme.build_tables

    def counting(*args, **kwargs):
        builds.append(args)
        return original(*args, **kwargs)

    monkeypatch.setattr(scheme, "build_tables", counting)
    grid = SphereGrid(10, 8.0, 5.5, 8, 4)
    first = SphereOperator(HardSpheres(0.7), 2, grid)
    again = SphereOperator(HardSpheres(0.7), 2, SphereGrid(10, 8.0, 5.5, 8, 4))
    assert len(builds) == 1 and again.tables is first.tables
    for other in (SphereOperator(HardSpheres(0.71), 2, grid),  # α
                  SphereOperator(HardSpheres(0.7), 2, SphereGrid(10, 8.0, 5.0, 8, 4)),  # R
                  SphereOperator(VariableHardSpheres(0.7, exponent=0.0), 2, grid)):  # kernel
        assert other.tables is not first.tables
    assert len(builds) == 4
    assert again.nodes is first.nodes and again.weight == first.weight
    with pytest.raises(ValueError):
        first.nodes[0, 0, 0] = 1.0  # shared: read-only
    sphere_spectral.clear_operator_cache()
    SphereOperator(HardSpheres(0.7), 2, grid)
    assert len(builds) == 5


def test_a_cold_start_at_small_alpha_reaches_the_state_of_the_longer_march():
    # α = 0.1 from the Maxwellian, the hardest start (a₂ = 0.21 on the default grid, against
    # 0 at the start): the shorter march before Newton (τ = 0.5, the default above α = 0.3)
    # and the longer march of τ = 1 (the default at α ≤ 0.3) reach the same cooling state.
    # Tolerance 1e-8 in a₂ and a₃: Newton stops at the residual 1e-10, and the two starts'
    # a₂, a₃ agreed to 4e-11 and 7e-10 on the default grid
    # (benchmarks/README.md, "The march before Newton").
    short = cooling_state(HardSpheres(0.1), dimension=2, grid="coarse", march_tau=0.5)
    longer = cooling_state(HardSpheres(0.1), dimension=2, grid="coarse")
    assert short.tau == 0.5 and longer.tau == 1.0
    assert short.residual < 1e-10 and longer.residual < 1e-10
    assert abs(short.a2 - longer.a2) < 1e-8, (short.a2, longer.a2)
    assert abs(short.a3 - longer.a3) < 1e-8, (short.a3, longer.a3)
    assert short.a2 > 0.15  # far from the Maxwellian's 0: the march did not end near it


def test_the_default_march_is_longer_at_small_alpha(newton):
    # τ = 1 where the shorter march cost Newton twice the Jacobian products (α ≤ 0.3), τ = 0.5
    # above; the module's fixture at α = 0.5 marched 0.5
    from maxwell_kinetics.sphere_steady import default_march_tau

    assert [default_march_tau(a) for a in (0.05, 0.1, 0.2, 0.3)] == [1.0] * 4
    assert [default_march_tau(a) for a in (0.31, 0.5, 0.9, 0.99)] == [0.5] * 4
    assert newton.tau == 0.5
