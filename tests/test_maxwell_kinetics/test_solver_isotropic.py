"""The isotropic d-dimensional inelastic Maxwell model: solve(..., dimension=d).

Checks against what does not come from the solver's own quadrature: the angular laws by Monte
Carlo on the sphere, the stationary equation by adaptive quadrature (scipy.integrate.quad) of
the η integral, the Gauss–Jacobi rules against the Beta moments, the η rule per range of q
(angular_tiers) against quad and against Gauss–Jacobi with 32 nodes at every q, and d = 1
against the one-dimensional solver.
"""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad
from scipy.special import beta as beta_function

import maxwell_kinetics._kinetic_scheme as scheme
from maxwell_kinetics._kinetic_scheme import angular_tiers, transport_speed
from maxwell_kinetics.angular import angular_law
from maxwell_kinetics.grid import get_resolution
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.solver import solve
from maxwell_kinetics.stationary import fixed_point
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("angular", ["uniform", "hard"])
def test_energy_rate_matches_the_sphere(d, angular):
    # η = (k̂·n)² with n uniform on the sphere ("uniform"), or weighted by |k̂·n| ("hard").
    # 10⁶ samples; the standard error of the ratio estimate ⟨η⟩ = Σ wη/Σ w is computed from the
    # sample (delta method: std of w(η − ⟨η⟩)/⟨w⟩ over √N, 1.5e-4 to 3e-4 here), and the rate
    # 2λ⟨η⟩ must agree within 5 of them.
    rng = np.random.default_rng(17)
    n = rng.normal(size=(1_000_000, d))
    cos = n[:, 0] / np.linalg.norm(n, axis=1)
    weight = np.ones_like(cos) if angular == "uniform" else np.abs(cos)
    mean_eta = float(np.sum(weight * cos**2) / np.sum(weight))
    se_eta = float(np.std(weight * (cos**2 - mean_eta)) / np.mean(weight) / math.sqrt(cos.size))
    model = MaxwellModel(0.3)
    assert model.energy_rate(d, angular) == pytest.approx(2 * model.lam * mean_eta,
                                                          abs=5 * 2 * model.lam * se_eta)
    # closed forms: ⟨η⟩ = 1/d and 2/(d + 1); the quadrature reproduces them to round-off
    exact = 1 / d if angular == "uniform" else 2 / (d + 1)
    assert model.energy_rate(d, angular) == pytest.approx(2 * model.lam * exact, rel=1e-14)
    eta, w = angular_law(d, angular).quadrature(12)
    assert float(w @ eta) == pytest.approx(exact, rel=1e-13)
    assert MaxwellModel(0.3).energy_rate(1) == pytest.approx(2 * model.lam, rel=1e-15)


def test_dimension_one_is_the_one_dimensional_solver():
    taus = [0.0, 2.5, 20.0]
    plain = solve(0.4, "uniform", taus, "coarse")
    d1 = solve(0.4, "uniform", taus, "coarse", dimension=1, angular="hard")
    np.testing.assert_array_equal(plain.G, d1.G)
    assert d1.dimension == 1


def _stationary_residual(sol, d, angular, r, qs, k):
    """(Λ/2) q G' − G + ∫ w(η) G(q √(1 − (1 − q₁²)η)) G(p q √η) dη by quad with the Beta
    weight (weight='alg') and a five-point derivative of the interpolated G."""
    model = MaxwellModel(r)
    p, q1 = model.p, 1 - model.p
    a, b = angular_law(d, angular)
    half = model.energy_rate(d, angular) / 2

    def G(x):
        return sol.evaluate(np.atleast_1d(np.asarray(x, dtype=float)), k).real

    out = []
    for q in qs:
        h = 1e-3 * q
        dG = (G(q - 2 * h) - 8 * G(q - h) + 8 * G(q + h) - G(q + 2 * h))[0] / (12 * h)

        def f(eta, q=q):
            return (G(q * np.sqrt(1 - (1 - q1 * q1) * eta)) * G(p * q * np.sqrt(eta)))[0]

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IntegrationWarning)  # round-off at 1e-14 requested
            gain = quad(f, 0, 1, weight="alg", wvar=(a - 1, b - 1), epsabs=1e-14,
                        epsrel=1e-13, limit=200)[0] / beta_function(a, b)
        out.append(half * q * dG - G(q)[0] + gain)
    return np.abs(np.array(out)).max()


# d = 2 "hard" runs with the default 16 η nodes: the compilation of the default-rule solve of
# test_default_eta_rule_converges_to_many_nodes_at_every_q (the same static scheme; r is data),
# so this file compiles that scheme once.
@pytest.mark.parametrize(("d", "angular", "nodes"), [(3, "uniform", 12), (2, "hard", 16)])
def test_isotropic_solution_keeps_mass_and_variance_and_reaches_the_fixed_point(d, angular,
                                                                                nodes):
    taus = [0.0, 100.0, 300.0]
    sol = solve(0.0, "gaussian", taus, "coarse", dimension=d, angular=angular,
                angular_nodes=nodes)
    assert np.all(np.isfinite(sol.G))
    q = sol.q
    small = (q > 1e-5) & (q < 1e-4)
    for k in range(len(taus)):
        # G(0) = 1 and unit variance per component: 1 − G = q²/2 + O(q⁴) (O(q³) at late
        # times, < 1e-12 relative here).  A wrong transport speed Λ/2 would scale the
        # variance by e^{δτ}.
        assert np.max(np.abs((1 - sol.G[k][small].real) / (q[small] ** 2 / 2) - 1)) < 1e-6
    # Measured residuals (coarse grid, 12 nodes): ~2e-2 at τ = 0, 2e-6 at τ = 100, 2e-8 at
    # τ = 300 (2D hard, 16 nodes: 4.9e-2, 1.7e-6, 3.8e-8): it falls toward the discretisation
    # level as G approaches the scaling solution.
    res = [_stationary_residual(sol, d, angular, 0.0, [0.3, 1.0, 2.0, 4.0], k)
           for k in range(len(taus))]
    assert res[0] > 1e-3
    assert res[2] < 1e-6 and res[2] < 0.1 * res[1]
    # The same fixed point solved directly (Chebyshev n = 128, the same η nodes): the solve
    # approaches it.  Measured max |G − G_fp| on q ≤ 40: 3.8e-5 → 2.5e-7 (3D uniform) and
    # 7.3e-5 → 4.5e-5 (2D hard, the resonance s* = 2, where G has q⁴ ln q: slow in τ and in n;
    # the same with 12 and 16 nodes) from τ = 100 to 300.
    fp = fixed_point(0.0, n=128, dimension=d, angular=angular, angular_nodes=nodes)
    assert fp.converged and fp.residual < 1e-8
    inside = q <= fp.q_max
    dist = [np.abs(sol.G[k][inside].real - fp(q[inside])).max() for k in (1, 2)]
    assert dist[1] < dist[0]
    assert dist[1] < (1e-6 if d == 3 else 1e-4)


def test_isotropic_input_checks():
    with pytest.raises(InvalidArgumentError, match="dimension"):
        solve(0.5, "gaussian", [1.0], "coarse", dimension=4)
    with pytest.raises(InvalidArgumentError, match="angular"):
        solve(0.5, "gaussian", [1.0], "coarse", dimension=2, angular="soft")
    with pytest.raises(InvalidArgumentError, match="angular_rule"):
        solve(0.5, "gaussian", [1.0], "coarse", dimension=2, angular_rule="exact")
    with pytest.raises(InvalidArgumentError, match="initial"):
        solve(0.5, "asymmetric", [1.0], "coarse", dimension=3)
    with pytest.raises(InvalidArgumentError, match="restitution"):
        solve(1.0, "gaussian", [1.0], "coarse", dimension=3)


@pytest.mark.parametrize(("d", "angular"), [(2, "uniform"), (2, "hard"), (3, "uniform"),
                                            (3, "hard")])
def test_gauss_jacobi_rule_integrates_the_beta_moments_of_its_degree(d, angular):
    # n nodes: exact for η^k, k ≤ 2n − 1 (the Beta moments B(a + k, b)/B(a, b)), not for 2n
    # (its relative error is 7e-7 for n = 6, below round-off for n = 16: checked for n ≤ 6).
    a, b = angular_law(d, angular)
    for n in (1, 2, 3, 6, 16):
        eta, w = angular_law(d, angular).quadrature(n)
        assert np.all((eta > 0) & (eta < 1)) and np.all(w > 0)
        assert w.sum() == pytest.approx(1.0, abs=1e-15)
        for k in range(2 * n + 1):
            exact = beta_function(a + k, b) / beta_function(a, b)
            if k < 2 * n:
                assert float(w @ eta**k) == pytest.approx(exact, rel=1e-12), (n, k)
            elif n <= 6:
                assert abs(float(w @ eta**k) / exact - 1) > 1e-7, (n, k)


@pytest.mark.parametrize("rule", ["fast", "accurate"])
@pytest.mark.parametrize("nodes", [3, 16, 32])
def test_angular_tiers_cover_the_grid_grow_with_q_and_keep_the_transport_speed(nodes, rule):
    grid = get_resolution("default")
    model = MaxwellModel(0.3)
    for d, angular in [(2, "uniform"), (3, "hard")]:
        tiers = angular_tiers(d, angular, nodes, grid, rule)
        firsts = [t.first for t in tiers]
        assert firsts[0] == 0 and firsts == sorted(set(firsts)) and firsts[-1] < grid.n
        counts = [t.eta.size for t in tiers]
        assert max(counts) == nodes and min(counts) >= 1
        q_first = np.exp(grid.s_min + grid.h * np.array(firsts))
        # more nodes at larger q up to q = 10 (above, G(q) is small and fewer suffice)
        below_10 = [c for c, q in zip(counts, q_first, strict=True) if q < 10]
        assert below_10 == sorted(below_10)
        exact = 1 / d if angular == "uniform" else 2 / (d + 1)
        for t in tiers:
            assert t.weights.sum() == pytest.approx(1.0, abs=1e-14)
            assert float(t.weights @ t.eta) == pytest.approx(exact, rel=1e-13)
        # Λ/2 = p(1 − p)⟨η⟩ (energy ∝ e^{−Λτ}) from the rule the solver takes for it
        speed = transport_speed(model, tiers[0].eta, tiers[0].weights)
        assert speed == pytest.approx(model.energy_rate(d, angular) / 2, rel=1e-13)
    more = angular_tiers(2, "uniform", 2 * nodes, grid, rule)
    assert sum(t.eta.size for t in more) > sum(t.eta.size for t in angular_tiers(
        2, "uniform", nodes, grid, rule))


def _model_phi(x):
    """(1 + √3|x| + x²) e^{−√3|x|}: unit variance, an |x|⁵ term (s = 5/2 at η = 0, like the
    d ≥ 2 scaling solutions' |x|^{2s*}, s* ≥ 2) and exponential decay: the characteristic
    function of a Student t law with 5 degrees of freedom, rescaled."""
    ax = np.sqrt(3.0) * np.abs(x)
    return (1 + ax + ax * ax / 3) * np.exp(-ax)


@pytest.mark.parametrize("rule", ["fast", "accurate"])
@pytest.mark.parametrize(("d", "angular", "r"), [(2, "uniform", 0.0), (3, "hard", 0.5)])
def test_tiered_eta_rule_is_as_accurate_as_the_full_rule_at_every_q(d, angular, r, rule):
    # ∫ w(η) Φ(a q) Φ(b q) dη by quad against the tier's rule and against 16 nodes at every q
    # (coarse grid, q ≥ e^{−6}; below, every rule is at round-off).  Measured with the 4.76-node
    # ladder of angular_tiers' docstring: it loses at most 7e-11 (2 nodes below q = 0.1: 6e-2).
    grid = get_resolution("coarse")
    model = MaxwellModel(r)
    p, q1 = model.p, 1 - model.p
    a, b = angular_law(d, angular)
    full_eta, full_w = angular_law(d, angular).quadrature(16)
    tiers = angular_tiers(d, angular, 16, grid, rule)
    for k, tier in enumerate(tiers):
        end = tiers[k + 1].first if k + 1 < len(tiers) else grid.n
        for j in range(max(tier.first, 180), end):
            q = np.exp(grid.s_min + grid.h * j)

            def f(eta, q=q):
                return _model_phi(q * np.sqrt(1 - (1 - q1 * q1) * eta)) * _model_phi(
                    p * q * np.sqrt(eta))

            with warnings.catch_warnings():
                warnings.simplefilter("ignore", IntegrationWarning)  # round-off at 1e-15
                exact = quad(f, 0, 1, weight="alg", wvar=(a - 1, b - 1), epsabs=1e-15,
                             epsrel=1e-14, limit=200)[0] / beta_function(a, b)
            tier_error = abs(float(tier.weights @ f(tier.eta)) - exact)
            full_error = abs(float(full_w @ f(full_eta)) - exact)
            assert tier_error <= full_error + 1e-10, (q, tier.eta.size)


def test_default_eta_rule_converges_to_many_nodes_at_every_q(monkeypatch):
    # Coarse grid, r = 0, d = 2 "hard" (s* = 2, the slowest tail mode; the hardest case
    # measured), G at τ = 100 and 300: the default ("fast") tiers against Gauss–Jacobi with 32
    # nodes at every q.  Measured: 16 nodes at every q 2.3e-9; the "fast" 4.76-node ladder
    # 5.1e-9; 2 nodes up to q = 0.1, 4 to 0.4 and 8 to 1: 1.2e-6 (an error at small q that
    # grows with τ through the slow modes).  Tolerance 1e-8.
    taus = [100.0, 300.0]
    sol = solve(0.0, "gaussian", taus, "coarse", dimension=2, angular="hard")
    assert sol.angular_rule == "fast"
    monkeypatch.setitem(scheme.ANGULAR_RULES, "accurate", ((0.0, None),))
    ref = solve(0.0, "gaussian", taus, "coarse", dimension=2, angular="hard", angular_nodes=32,
                angular_rule="accurate")
    assert np.abs(sol.G - ref.G).max() < 1e-8
    q = sol.q
    small = (q > 1e-5) & (q < 1e-4)
    # G(0) = 1 and G''(0) = −1 kept by the tiers (1 − G = q²/2 + O(q⁴))
    assert np.max(np.abs((1 - sol.G[-1][small].real) / (q[small] ** 2 / 2) - 1)) < 1e-6
