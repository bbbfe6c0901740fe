"""The small numerical helpers (rates of the model, Chebyshev operators, Lagrange weights, the
sphere moments, the deviation's reference and source) on hostile input: booleans, complex
numbers, NaN, repeated nodes.  Each raises ``InvalidArgumentError`` naming the argument (before:
a complex or NaN rate returned as if valid, ``True`` taken as 1, or IndexError, TypeError and
NumPy warnings from inside)."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics import chebyshev as cheb
from maxwell_kinetics.deviation import reference, source
from maxwell_kinetics.grid import lagrange_weights
from maxwell_kinetics.linear_rates import linear_decay_rates, linearised_operator
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.moments import moments_of, series_estimate, sphere_cos_moment
from particles.validation import InvalidArgumentError

NAN = float("nan")
M = MaxwellModel(0.5)
Q = np.geomspace(1e-3, 10.0, 200)


@pytest.mark.parametrize("call, name", [
    (lambda: M.contraction_rate(NAN), "s"),  # returned nan
    (lambda: M.contraction_rate(1j), "s"),  # returned a complex rate
    (lambda: M.growth_rate(True), "s"),  # returned g(1)
    (lambda: M.moment_rate(np.complex128(4.0)), "n"),
    (lambda: M.energy(-1.0), "tau"),
    (lambda: cheb.chebyshev_nodes(0, 1.0), "n"),  # 0/0 warning
    (lambda: cheb.chebyshev_nodes(True, 1.0), "n"),
    (lambda: cheb.chebyshev_nodes(4, NAN), "length"),
    (lambda: cheb.barycentric_weights(-1), "n"),  # IndexError
    (lambda: cheb.barycentric_matrix(cheb.chebyshev_nodes(4, 1.0), [NAN]), "targets"),
    (lambda: cheb.barycentric_matrix([0.0, 0.0, 1.0], [0.5]), "nodes"),  # repeated node
    (lambda: cheb.differentiation_matrix([0.0]), "nodes"),  # TypeError
    (lambda: cheb.differentiation_matrix([0.0, 0.5, 0.5]), "nodes"),
    (lambda: lagrange_weights(NAN, 4), "offset"),  # ValueError from math.floor
    (lambda: lagrange_weights(0.5, True), "order"),
    (lambda: lagrange_weights(0.5, 3), "order"),  # the stencil is for even orders
    (lambda: sphere_cos_moment(True, 2), "dimension"),
    (lambda: sphere_cos_moment(3, 2.5), "n"),  # was taken as 2
    (lambda: reference([0.0, 1.0], NAN), "m3"),  # TypeError: list times float
    (lambda: reference([0.0, NAN], 0.1), "q"),
    (lambda: source([1.0], 0.1j, 0.1), "lam"),
    (lambda: series_estimate(Q, np.where(Q > 1, NAN, Q**4), 3), "w"),  # NaN went into the fits
    (lambda: series_estimate(Q, Q**4, 2.5), "n_max"),  # was taken as 2
    (lambda: series_estimate(Q[::-1], Q**4, 3), "q"),
    (lambda: series_estimate(Q, Q[:-1] ** 4, 3), "w"),
    (lambda: moments_of(Q, [Q**4], [1.0], 1 + 0j, [2, 4]), "dimension"),
    (lambda: moments_of(Q, [Q**4], [1.0, 2.0], 1, [2, 4]), "w_rows"),
])
def test_hostile_arguments_are_invalid_arguments(call, name):
    with pytest.raises(InvalidArgumentError) as info:
        call()
    assert info.value.name == name


def test_valid_calls_are_unchanged():
    assert M.contraction_rate(2.0) == pytest.approx(0.0, abs=1e-15)
    assert sphere_cos_moment(3, 1) == pytest.approx(1 / 3)
    first, w = lagrange_weights(0.25, 4)
    assert first == -1 and w.sum() == pytest.approx(1.0)
    q = cheb.chebyshev_nodes(8, 2.0)
    assert cheb.differentiation_matrix(q) @ q == pytest.approx(np.ones(9))
    assert reference([0.0], 0.0).tolist() == [1.0]


@pytest.mark.parametrize(("offset", "order"), [(0.25, 4), (-1.5, 6), (2.75, 8)])
def test_lagrange_weights_reproduce_polynomials_of_degree_order_minus_one(offset, order):
    # The stencil's weights interpolate every polynomial of degree < order exactly: P(x) =
    # Σ_k w_k P(first + k) at x = offset, here for P(x) = (x − 1/3)^{order−1} + x² − 2 (the sum
    # of the weights alone is 1 at any point, so it cannot see a shifted target).  Round-off:
    # terms up to |x|^7 ~ 1e5, 1e-12.
    first, w = lagrange_weights(offset, order)
    nodes = first + np.arange(order, dtype=float)

    def poly(x):
        return (x - 1 / 3) ** (order - 1) + x * x - 2.0

    assert w @ poly(nodes) == pytest.approx(poly(offset), rel=1e-12, abs=1e-12)


def test_chebyshev_operators_are_exact_for_polynomials():
    # On the n + 1 = 9 Lobatto points of [0, 2], q_j = 1 − cos(jπ/8): the interpolant of a
    # polynomial of degree ≤ 8 is the polynomial itself, so D differentiates q^7 − 3q² exactly to
    # 7q^6 − 6q and B evaluates it at any point.  Round-off: 1e-11 of terms up to 2^7 = 128.
    q = cheb.chebyshev_nodes(8, 2.0)
    np.testing.assert_allclose(q, 1.0 - np.cos(np.pi * np.arange(9) / 8), rtol=0, atol=1e-15)
    values = q**7 - 3 * q**2
    targets = np.array([0.1, 0.77, 1.9])
    np.testing.assert_allclose(cheb.differentiation_matrix(q) @ values, 7 * q**6 - 6 * q,
                               rtol=1e-11, atol=1e-10)
    np.testing.assert_allclose(cheb.barycentric_matrix(q, targets) @ values,
                               targets**7 - 3 * targets**2, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("call, name", [
    # n = 1e9: 1e19 bytes of dense matrices; it was a MemoryError (or the process killed)
    (lambda: linear_decay_rates(0.5, n=10**9), "n"),
    (lambda: linearised_operator(0.5, n=10**9), "n"),
    (lambda: linear_decay_rates(0.5, n=16, count=1000), "count"),  # gave fewer rates silently
    (lambda: linear_decay_rates(0.5, sigma=2.5j), "sigma"),
])
def test_linear_rates_refuse_what_they_cannot_compute(call, name):
    with pytest.raises(InvalidArgumentError, match="estimate|n \\+ 1|real") as info:
        call()
    assert info.value.name == name
