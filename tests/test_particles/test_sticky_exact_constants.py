"""The sticky gas's late-time constants (particles.sticky_exact.exact_moments) against
derivations that share none of the module's code.

The module computes the constants as one-dimensional quadratures of its densities, with Airy
functions on steepest-descent contours, tables of ψ and a Hankel contour for k.  Here they come
from the shock density J(a, b) = ¼ (a + b) k(a + b) ψ(a) ψ(b) (Frachebourg and Martin 2000, in
the scaled variables of the module docstring) built from two other representations:

* ψ from Groeneboom's Fourier formula (Probab. Th. Rel. Fields 81, 79 (1989)): his g has
  ĝ(λ) = 2^{1/3}/Ai(i 2^{−1/3} λ) and ψ(τ) = 2^{−1/3} g(2^{−2/3} τ), computed by a cosine-type
  quadrature of the real line (the only special function used is ``scipy.special.airy``);
* k(μ) = 2 Σ_j exp(2^{−1/3} a_j μ) over the zeros a_j of Ai (the Dirichlet spectrum of
  −½∂² + x): the first 2000 zeros from ``scipy.special.ai_zeros``, the rest by the asymptotic
  zeros |a_j| ≈ T^{2/3}, T = 3π(4j − 1)/8, summed as an integral (midpoint rule, in closed form
  by the incomplete Gamma function), which also carries the μ^{−3/2} singularity at μ → 0;

and a two-dimensional Gauss–Legendre rule over (μ = u², w = (a − b)/2), where da db = dμ dw.
The moments are then: clusters ∫∫ J, mass ∫∫ μ J = 1 (every particle is in one cluster),
mean_mass ∫∫ μ² J, velocity_variance ∫∫ μ w² J (a particle's velocity is its cluster's).

A second, exact identity ties the velocity variance to Chernoff's variance: a particle of a
cluster of scaled mass μ and velocity w, at a uniform place in the cluster's labels, has the
scaled displacement w + U, U uniform on [−μ/2, μ/2] independent of w given the cluster, so
⟨D²⟩ = ⟨w²⟩ + ⟨μ²⟩/12 (particle averages), and ⟨D²⟩ = 2^{4/3} Var Z with Var Z = 0.26355964
(Groeneboom and Wellner 2001, 8 digits).  Agreement found: 1e-10 relative or better.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ai_zeros, airy, gamma, gammaincc

from particles.sticky_exact import exact_mass_density, exact_moments

_C = 2.0 ** (-1.0 / 3.0)
_ZEROS = 2000


def _psi(tau, cutoff: float = 26.0, nodes: int = 500) -> np.ndarray:
    # |ĝ(λ)| < 1e-30 beyond λ = 26; 500 nodes resolve the phase λ|z| for |τ| ≲ 15, beyond
    # which ψ(τ) < 1e-8 · e^{−…} contributes nothing at 1e-12.
    x, weight = np.polynomial.legendre.leggauss(nodes)
    lam = 0.5 * cutoff * (x + 1.0)
    weight = 0.5 * cutoff * weight
    ghat = 2.0 ** (1.0 / 3.0) / airy(1j * _C * lam)[0]
    z = 2.0 ** (-2.0 / 3.0) * np.asarray(tau, dtype=float)
    g = (np.exp(-1j * np.multiply.outer(z, lam)) * ghat).real @ weight / math.pi
    return 2.0 ** (-1.0 / 3.0) * g


def _k(mu) -> np.ndarray:
    a = ai_zeros(_ZEROS)[0]
    mu = np.asarray(mu, dtype=float)
    beta = _C * mu
    head = np.exp(np.multiply.outer(beta, a)).sum(axis=-1)
    # Σ_{j > J} exp(−β T_j^{2/3}) ≈ ∫_{J+½}^∞ dj = (2/(3π)) ∫_T^∞ exp(−β s^{2/3}) ds
    t_j = 3.0 * math.pi * (4.0 * (_ZEROS + 0.5) - 1.0) / 8.0
    tail = (2.0 / (3.0 * math.pi)) * 1.5 * beta**-1.5 * gamma(1.5) \
        * gammaincc(1.5, beta * t_j ** (2.0 / 3.0))
    return 2.0 * (head + tail)


@pytest.fixture(scope="module")
def independent():
    # μ = u² on u ∈ [0, 3.6] (k(μ)ψ∗ψ < e^{−80} beyond μ = 13; the factor 2u du smooths the
    # μ^{−1/2} of small clusters), w ∈ [0, 8] doubled (the integrand is even in w and below
    # e^{−90} beyond); 50 × 50 nodes (64 × 64 changes no moment by more than 1e-13).
    x, weight = np.polynomial.legendre.leggauss(50)
    u, wu = 1.8 * (x + 1.0), 1.8 * weight
    w, ww = 4.0 * (x + 1.0), 4.0 * weight
    mu = u * u
    j = (0.25 * mu * _k(mu))[:, None] * _psi(np.add.outer(mu / 2, w)) \
        * _psi(np.subtract.outer(mu / 2, w))
    j *= (2.0 * u * wu)[:, None] * (2.0 * ww)[None, :]
    m, v = mu[:, None], w[None, :]
    return {"clusters": float(np.sum(j)), "mass": float(np.sum(m * j)),
            "mean_mass": float(np.sum(m * m * j)),
            "velocity_variance": float(np.sum(m * v * v * j)),
            "mass_squared": float(np.sum(m**3 * j))}


def test_the_independent_kernels_have_their_known_limits():
    # k(μ) → √(2/π) μ^{−3/2} − 1/2 as μ → 0 (free Brownian bridge), k ≈ 2 e^{−λ₁ μ} at large μ;
    # ψ's transform at λ = 0: ∫ ψ = 2^{2/3}/Ai(0).
    small = np.array([1e-8, 1e-6])
    np.testing.assert_allclose(_k(small), math.sqrt(2 / math.pi) * small**-1.5 - 0.5, rtol=1e-11)
    lam1 = -_C * ai_zeros(1)[0][0]
    assert _k(np.array([12.0]))[0] == pytest.approx(2 * math.exp(-lam1 * 12.0), rel=1e-9)
    x, wt = np.polynomial.legendre.leggauss(400)
    tau = 14.0 * x - 4.0
    assert float(14.0 * wt @ _psi(tau)) == pytest.approx(2 ** (2 / 3) / airy(0.0)[0], rel=1e-9)


def test_every_particle_is_in_one_cluster(independent):
    assert independent["mass"] == pytest.approx(1.0, abs=1e-10)


@pytest.mark.parametrize("name", ["clusters", "mean_mass", "velocity_variance"])
def test_exact_moments_equal_the_independent_quadrature(independent, name):
    # Both sides are good to ~1e-11 (module docstrings; the two node counts above): 1e-9.
    assert exact_moments()[name] == pytest.approx(independent[name], rel=1e-9)


def test_displacements_are_velocity_plus_place_in_the_cluster(independent):
    m = exact_moments()
    chernoff = 2 ** (4 / 3) * 0.26355964  # 8 published digits: rel 2e-8
    assert independent["velocity_variance"] + independent["mass_squared"] / 12 \
        == pytest.approx(chernoff, rel=2e-8)
    assert m["eulerian_variance"] == pytest.approx(chernoff, rel=2e-8)
    # the module's own mass law, by adaptive quadrature, in the same identity: ⟨μ²⟩ = ∫ μ³ F
    mu2 = quad(lambda x: x**3 * exact_mass_density(x), 0, 30, limit=200, epsabs=1e-13)[0]
    assert m["velocity_variance"] + mu2 / 12 == pytest.approx(m["eulerian_variance"], rel=1e-9)


def test_mean_mass_is_the_mass_weighted_mean_of_the_mass_law():
    # ∫ μ² F by adaptive quadrature of exact_mass_density (the module uses Gauss–Legendre in
    # √μ), against exact_moments, and the ordering ⟨μ⟩_particle ≥ 1/⟨1⟩_cluster (Jensen:
    # Σ μ²F · Σ F ≥ (Σ μF)² = 1).
    m = exact_moments()
    direct = quad(lambda x: x * x * exact_mass_density(x), 0, 30, limit=200, epsabs=1e-13)[0]
    assert m["mean_mass"] == pytest.approx(direct, rel=1e-9)
    assert m["mean_mass"] * m["clusters"] > 1.0
