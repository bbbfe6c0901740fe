"""One evaluation of the kinetic scheme's right-hand side against the collision integral
computed independently, by quadrature of its definition.

For the constant-rate (pseudo-Maxwell) model the Fourier collision integral of a law f is

    Q[G](q) = ∫∫ f(v) f(w) e^{i q v'} dv dw − ∫ f(v) e^{i q v} dv,     v' = (1 − p) v + p w,

(gain: the post-collision velocity v' of a particle that keeps 1 − p of its velocity and gains
p of its partner's; loss: the law itself).  The scheme stores the deviation w = G − g from the
reference g(q) = e^{−q²/2}(1 − i m₃ q³/6) on comoving nodes, where the transport term λ q ∂q G
is absorbed in the motion of the nodes, so its right-hand side at the window start is

    ∂t w = Q[G](q) + λ q g'(q),      λ = p(1 − p).

Both integrals are computed here by tensor Gauss quadrature of the double (and single)
integral, never through the product G(pq) G((1 − p)q) the scheme uses.  The grid is chosen so
that the gain's shifts ln p / h and ln(1 − p) / h are integers: p = (√5 − 1)/2 (so 1 − p = p²,
r = √5 − 2) and h = −ln p / 20, shifts −20 and −40.  The Lagrange stencils are then exact
(a single weight 1), and the scheme's only error is round-off: the check is to the quadrature's
error (below 1e-12), and a change of 0.1 % in the gain term (≥ 1e-4 at q ~ 1) or in p fails
it by orders of magnitude.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from maxwell_kinetics import _kinetic_scheme as scheme
from maxwell_kinetics.grid import Resolution
from maxwell_kinetics.model import MaxwellModel
from maxwell_kinetics.solution import SolverOptions
from maxwell_kinetics.solver import Stepper
from particles.initial import InitialLaw, get_law

P = (math.sqrt(5.0) - 1.0) / 2.0  # root of p² + p − 1 = 0: 1 − p = p²
R = 2.0 * P - 1.0  # p = (1 + r)/2
H = -math.log(P) / 20.0
GRID = Resolution("integer-shift test grid", H, 8, -6.0)

# Tolerance: the quadrature's own error, estimated as the difference between N and 2N nodes
# (spectral convergence: the coarser rule's error bounds the finer's; asserted below
# QUADRATURE_TOL), twice over, plus ROUND_OFF for the scheme's float64 arithmetic on O(1)
# terms (measured: 7e-15 for the uniform law; the asymmetric law's 4.7e-13 is its quadrature's
# 4.0e-13).  Below q ≈ 0.05 the state is not φ − g itself but the solver's small-q fit of it
# (``initial_deviation``, a series in q), which differs from it by up to 3e-13 there: the gain
# and loss are not the question there, and the checks start at Q_MIN.
QUADRATURE_TOL = 1e-12
ROUND_OFF = 1e-13
Q_MIN = 0.05


def _scheme_rhs(law):
    """(q of the grid nodes, ∂t w at those nodes at τ = 0 as complex numbers, λ, m₃) for a law
    or a built-in law's name."""
    model = MaxwellModel(R)
    law = get_law(law) if isinstance(law, str) else law
    stepper = Stepper(model, law, GRID, SolverOptions())
    with jax.enable_x64(True):
        dw = np.asarray(scheme._rhs(stepper.static, 0.0, stepper.y0,
                                    (jnp.float64(0.0), stepper.dynamic)))
    dw = dw[:, :GRID.n]
    values = dw[0] + 1j * dw[1] if dw.shape[0] == 2 else dw[0].astype(complex)
    return np.exp(GRID.s), values, model.lam, stepper.m3


def _collision_integral(q, v, weights):
    """Gain − loss of Q[G](q) by tensor quadrature over (v, w) with the law's nodes and weights."""
    v_post = ((1.0 - P) * v[:, None] + P * v[None, :]).ravel()
    pair_weights = (weights[:, None] * weights[None, :]).ravel()
    gain = np.exp(1j * q[:, None] * v_post[None, :]) @ pair_weights
    loss = np.exp(1j * q[:, None] * v[None, :]) @ weights
    return gain - loss


def _transport_of_reference(q, lam, m3):
    """λ q g'(q) for g = e^{−q²/2}(1 − i m₃ q³/6)."""
    gauss = np.exp(-0.5 * q * q)
    g_prime = -q * gauss * (1.0 - 1j * m3 * q**3 / 6.0) + gauss * (-1j * m3 * q**2 / 2.0)
    return lam * q * g_prime


def test_grid_makes_the_gain_stencils_exact():
    """The premise of the tests below: the shifts are integers to round-off."""
    shift_a, shift_b = MaxwellModel(R).gain_shifts(1.0)
    assert shift_a / H == pytest.approx(-20.0, abs=1e-12)
    assert shift_b / H == pytest.approx(-40.0, abs=1e-12)


def test_rhs_is_the_collision_integral_uniform_law():
    """U(−√3, √3), real G, every node q ∈ [0.05, 36]: Gauss–Legendre in v and w (64 and 128
    nodes per axis)."""
    q, rhs, lam, m3 = _scheme_rhs("uniform")
    assert m3 == 0.0 and np.all(rhs.imag == 0.0)
    keep = q >= Q_MIN
    q, rhs = q[keep], rhs[keep]

    def integral(n):
        x, wt = np.polynomial.legendre.leggauss(n)
        return _collision_integral(q, math.sqrt(3.0) * x, wt / 2.0)

    coarse, fine = integral(64), integral(128)
    quadrature_error = np.abs(coarse - fine).max()
    assert quadrature_error < QUADRATURE_TOL
    expected = fine + _transport_of_reference(q, lam, m3)
    assert np.abs(rhs - expected).max() < 2 * quadrature_error + ROUND_OFF
    # the check has teeth: the gain alone is O(0.1–1) over much of the grid
    assert np.abs(fine).max() > 0.1


def test_rhs_is_the_collision_integral_asymmetric_law():
    """Shifted exponential X − 1 (m₃ = 2), complex G, nodes 0.05 ≤ q ≤ 2: Gauss–Laguerre in
    v + 1 and w + 1 (120 and 180 nodes per axis; beyond q ≈ 2 the Laguerre rules of this size
    no longer resolve e^{iqv} to 1e-12)."""
    q, rhs, lam, m3 = _scheme_rhs("asymmetric")
    assert m3 == pytest.approx(2.0)
    keep = (q >= Q_MIN) & (q <= 2.0)

    def integral(n):
        x, wt = np.polynomial.laguerre.laggauss(n)
        return _collision_integral(q[keep], x - 1.0, wt)

    coarse, fine = integral(120), integral(180)
    quadrature_error = np.abs(coarse - fine).max()
    assert quadrature_error < QUADRATURE_TOL
    expected = fine + _transport_of_reference(q[keep], lam, m3)
    assert np.abs(rhs[keep] - expected).max() < 2 * quadrature_error + ROUND_OFF
    assert np.abs(fine.imag).max() > 0.05  # the imaginary part is tested, not only zeros


def test_rhs_of_an_asymmetric_law_with_zero_third_moment():
    """An asymmetric law whose third moment is exactly 0 (so the reference g is real while G is
    not): ⅓ of the shifted exponential X − 1 (m₃ = 2) and ⅔ of 2 − Y/2, Y ~ Gamma(4) (mean 0,
    variance 1, m₃ = −1), φ(k) = ⅓ e^{−ik}/(1 − ik) + ⅔ e^{2ik}(1 + ik/2)^{−4}.  Quadrature:
    Gauss–Laguerre in X and generalised Gauss–Laguerre (weight y³e^{−y}) in Y, 120 and 180
    nodes each, nodes 0.05 ≤ q ≤ 2, tolerance as above."""
    from scipy.special import roots_genlaguerre

    def phi(k, xp):
        return (xp.exp(-1j * k) / (1.0 - 1j * k) / 3.0
                + 2.0 / 3.0 * xp.exp(2j * k) * (1.0 + 0.5j * k) ** -4)

    law = InitialLaw("skew-free asymmetric mixture", phi, None, 0.0)
    assert not law.symmetric
    q, rhs, lam, m3 = _scheme_rhs(law)
    assert m3 == 0.0
    keep = (q >= Q_MIN) & (q <= 2.0)

    def integral(n):
        x, wx = np.polynomial.laguerre.laggauss(n)
        y, wy = roots_genlaguerre(n, 3.0)
        v = np.concatenate([x - 1.0, 2.0 - 0.5 * y])
        weights = np.concatenate([wx / 3.0, 2.0 / 3.0 * wy / 6.0])  # ∫y³e^{−y} = Γ(4) = 6
        return _collision_integral(q[keep], v, weights)

    coarse, fine = integral(120), integral(180)
    quadrature_error = np.abs(coarse - fine).max()
    assert quadrature_error < QUADRATURE_TOL
    expected = fine + _transport_of_reference(q[keep], lam, 0.0)
    assert np.abs(rhs[keep] - expected).max() < 2 * quadrature_error + ROUND_OFF
    assert np.abs(fine.imag).max() > 0.01  # the imaginary part is tested, not only zeros


def test_rhs_later_in_a_window_is_the_collision_integral_at_the_moved_nodes():
    """At local time t of a window the comoving nodes sit at q = e^{s_j − λ t}.  Given the
    uniform law's deviation there, w = sin(√3 q)/(√3 q) − e^{−q²/2} (exact), the right-hand side
    is again Q[G](q) + λ q g'(q) at those q (same quadrature and tolerance as above): this pins
    the motion of the nodes, which τ = 0 alone cannot (e^{−λ·0} = 1)."""
    t = 0.3
    model = MaxwellModel(R)
    stepper = Stepper(model, get_law("uniform"), GRID, SolverOptions())
    st = stepper.static
    q_all = np.exp(GRID.s_min + GRID.h * np.arange(st.n_state) - model.lam * t)
    w = np.sin(math.sqrt(3.0) * q_all) / (math.sqrt(3.0) * q_all) - np.exp(-0.5 * q_all**2)
    with jax.enable_x64(True):
        dw = np.asarray(scheme._rhs(st, t, jnp.asarray(w[None, :]),
                                    (jnp.float64(0.0), stepper.dynamic)))
    q, rhs = q_all[:GRID.n], dw[0, :GRID.n]
    keep = q >= Q_MIN
    q, rhs = q[keep], rhs[keep]
    assert math.exp(-model.lam * t) < 0.95  # the nodes moved by more than 5 %: not a no-op

    def integral(n):
        x, wt = np.polynomial.legendre.leggauss(n)
        return _collision_integral(q, math.sqrt(3.0) * x, wt / 2.0)

    coarse, fine = integral(64), integral(128)
    quadrature_error = np.abs(coarse - fine).max()
    assert quadrature_error < QUADRATURE_TOL
    expected = fine + _transport_of_reference(q, model.lam, 0.0)
    assert np.abs(rhs - expected).max() < 2 * quadrature_error + ROUND_OFF


def test_inflow_is_the_free_decay_of_the_initial_law_beyond_the_active_nodes():
    """Beyond the active nodes the state is set, not integrated: at τ = τ_w + t the node at
    q = e^{s_j − λt} holds e^{−τ} φ(q e^{λτ}) − g(q) (the collisionless decay of the initial
    law, φ(k) = e^{−ik}/(1 − ik) for the shifted exponential; g(q) = e^{−q²/2}(1 − i m₃ q³/6)),
    real and imaginary parts.  Evaluated here in closed form; the agreement is to round-off."""
    tau_w, t = 1.0, 0.2
    model = MaxwellModel(R)
    stepper = Stepper(model, get_law("asymmetric"), GRID, SolverOptions())
    st, dy = stepper.static, stepper.dynamic
    with jax.enable_x64(True):
        inflow = np.asarray(scheme._inflow(st, dy, jnp.float64(t), jnp.float64(tau_w)))
    j = int(dy.n_active) + np.arange(st.n_right)
    q = np.exp(GRID.s_min + GRID.h * j - model.lam * t)
    tau = tau_w + t
    k = q * math.exp(model.lam * tau)
    free = math.exp(-tau) * np.exp(-1j * k) / (1.0 - 1j * k)
    reference = np.exp(-0.5 * q * q) * (1.0 - 1j * stepper.m3 * q**3 / 6.0)
    expected = free - reference
    assert inflow.shape == (2, st.n_right)
    assert np.abs(inflow[0] + 1j * inflow[1] - expected).max() < 1e-14
    assert np.abs(free).max() > 1e-3 and np.abs(expected.imag).max() > 1e-3  # both terms count


def _two_gaussians(q):
    """An isotropic law of unit variance per direction that is not Gaussian: G(q) = ½ e^{−q²/4}
    + ½ e^{−3q²/4} (a half-half mixture of Gaussians of variances ½ and 3/2)."""
    return 0.5 * np.exp(-0.25 * q * q) + 0.5 * np.exp(-0.75 * q * q)


def _isotropic_rhs_of_two_gaussians(d, angular, rule, t=0.3):
    """(q of the first GRID.n nodes moved to local time ``t``, the scheme's right-hand side
    there, λ) for the two-Gaussian law's deviation given exactly at every state node."""
    model = MaxwellModel(R)
    stepper = Stepper(model, get_law("gaussian"), GRID, SolverOptions(), dimension=d,
                       angular=angular, angular_nodes=16, angular_rule=rule)
    st, dy = stepper.static, stepper.dynamic
    lam = float(dy.lam)
    q_all = np.exp(GRID.s_min + GRID.h * np.arange(st.n_state) - lam * t)
    w = _two_gaussians(q_all) - np.exp(-0.5 * q_all**2)
    with jax.enable_x64(True):
        dw = np.asarray(scheme._rhs(st, t, jnp.asarray(w[None, :]), (jnp.float64(0.0), dy)))
    return q_all[:GRID.n], dw[0, :GRID.n], lam


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("angular, cos_power", [("uniform", 0), ("hard", 1)])
def test_isotropic_rhs_is_the_collision_integral_by_quadrature_over_the_angle(d, angular,
                                                                             cos_power):
    """d = 2, 3: the right-hand side at local time t = 0.3 of a window, on the state of an
    isotropic law that is not Gaussian (its deviation from e^{−q²/2} given exactly at the moved
    nodes q = e^{s_j − λt}), against

        Q[G](q) + λ q g'(q),   Q[G](q) = ⟨G(|k − p(k·n)n|) G(p|k·n|)⟩_n − G(q),

    the Fourier collision integral of the rule v' = v − p((v − w)·n)n, with the average over
    the direction n computed here by Gauss–Legendre quadrature in the angle θ between k and n
    (weight sin^{d−2}θ for the uniform model, sin^{d−2}θ |cos θ| for the hard one: 200 and 400
    nodes on [0, π/2]), not through the scheme's Gauss–Jacobi rule in η = cos²θ.  Every node is
    checked, down to the first: the stencils of the nodes below q₀/p read the continuation of
    w below the grid, which is checked with them.

    Tolerance: the angle quadrature's own error (200 against 400 nodes, asserted below 1e-14)
    plus the scheme's interpolation of w at the non-integer shifts ln(p√η)/h (order-8 Lagrange
    stencils, h = 0.024; measured at most 1.8e-12 over these four cases, at q ≈ 3.6): bound
    1e-11.  The collision integral itself is 0.05–0.11 at its largest here, so a change of
    0.1 % in the gain or the loss is 5e-5, far above the bound.
    """
    t = 0.3
    q, rhs, lam = _isotropic_rhs_of_two_gaussians(d, angular, "accurate", t)  # every node
    assert math.exp(-lam * t) < 0.98  # the nodes moved: not the window start

    def gain(n):
        x, wt = np.polynomial.legendre.leggauss(n)
        theta = (x + 1.0) * math.pi / 4.0
        weight = np.sin(theta) ** (d - 2) * np.abs(np.cos(theta)) ** cos_power * wt
        weight /= weight.sum()
        cos_theta = np.cos(theta)
        k_minus = np.sqrt(1.0 - 2.0 * P * cos_theta**2 + (P * cos_theta) ** 2)  # |k − p(k·n)n|/k
        k_along = P * cos_theta  # |p(k·n)n|/k
        pairs = _two_gaussians(np.outer(q, k_minus)) * _two_gaussians(np.outer(q, k_along))
        return pairs @ weight

    coarse, fine = gain(200), gain(400)
    assert np.abs(coarse - fine).max() < 1e-14
    integral = fine - _two_gaussians(q)
    expected = integral + _transport_of_reference(q, lam, 0.0).real
    assert np.abs(rhs - expected).max() < 1e-11
    assert np.abs(integral).max() > 0.05  # the check has teeth
    # the transport speed is the model's Λ/2 = p(1 − p)⟨η⟩, ⟨η⟩ the mean of the angular law
    mean_eta = {"uniform": 1.0 / d, "hard": 2.0 / (d + 1)}[angular]
    assert lam == pytest.approx(P * (1.0 - P) * mean_eta, rel=1e-14)


@pytest.mark.parametrize("d, angular", [(2, "uniform"), (3, "hard")])
def test_isotropic_rhs_applies_each_tiers_angular_rule_to_its_own_nodes(d, angular):
    """The "fast" rule: seven tiers of 3 to 16 η nodes over the grid (:func:`angular_tiers`),
    each node's gain summed over its own tier's rule.  Expected here from that rule, node by
    node, with G evaluated exactly at a_i q and b_i q (not through the stencils):
    Σ_i ω_i G(a_i q) G(b_i q) − G(q) + λ q g'(q) at the moved nodes of local time t = 0.3.  The
    angle quadrature itself is tested above; this pins which rule serves which node, the
    source's series and direct branches of every tier, and the tiers' order.  Bound as above
    (the stencils' interpolation, measured at most 1.7e-12 here)."""
    tiers = scheme.angular_tiers(d, angular, 16, GRID, "fast")
    assert len(tiers) >= 5  # several tiers, and the first ones at q where X = p(1 − p) q² < 1/2
    q, rhs, lam = _isotropic_rhs_of_two_gaussians(d, angular, "fast")
    nodes = np.arange(GRID.n)
    bounds = [tier.first for tier in tiers] + [GRID.n]
    expected = np.full(GRID.n, np.nan)
    for k, tier in enumerate(tiers):
        mine = (nodes >= bounds[k]) & (nodes < bounds[k + 1])
        a = np.sqrt(1.0 - (2.0 * P - P * P) * tier.eta)
        b = P * np.sqrt(tier.eta)
        qk = q[mine]
        gain = (_two_gaussians(np.outer(qk, a)) * _two_gaussians(np.outer(qk, b))) @ tier.weights
        expected[mine] = gain - _two_gaussians(qk) + _transport_of_reference(qk, lam, 0.0).real
    assert not np.isnan(expected).any()
    assert np.abs(rhs - expected).max() < 1e-11


SMALL_GRID = Resolution("small grid", H, 8, -6.0, 1.0)  # q up to e: the ghosts' g(q) is not 0


def test_padded_state_is_continuation_state_and_inflow_and_the_inflow_ends():
    """The array the gain stencils read: w(q₀) e^{3hj} for the n_left nodes j < 0, the state
    itself up to the last active node, then the inflow (on a grid ending at q = e, whose first
    ghosts sit at q ≈ 4, where g(q) = e^{−q²/2} ≈ 1.5e-4 is not 0 in float64).  The inflow is
    e^{−τ} φ − g before τ = 40 and −g after (the free decay of the initial law is dropped); a
    law the scheme cannot trace (a user's NumPy characteristic function) gets −g throughout."""
    from particles.initial import law_from_characteristic

    model = MaxwellModel(R)
    for law, tau_w in ((get_law("uniform"), 1.0), (get_law("uniform"), 50.0),
                       (law_from_characteristic(lambda k: np.exp(-0.5 * k * k), 1.0,
                                                name="mine"), 1.0)):
        stepper = Stepper(model, law, SMALL_GRID, SolverOptions())
        st, dy = stepper.static, stepper.dynamic
        t = 0.2
        w = np.linspace(0.5, 1.5, st.n_state)[None, :]
        with jax.enable_x64(True):
            padded = np.asarray(scheme._padded(st, dy, jnp.asarray(w), jnp.float64(t),
                                               jnp.float64(tau_w)))
        n_left, n_active = st.n_left, int(dy.n_active)
        j = np.arange(-n_left, 0)
        np.testing.assert_allclose(padded[0, :n_left], w[0, 0] * np.exp(3.0 * H * j),
                                   rtol=1e-14)
        np.testing.assert_array_equal(padded[0, n_left:n_left + n_active], w[0, :n_active])
        ghosts = padded[0, n_left + n_active:n_left + n_active + st.n_right]
        q = np.exp(SMALL_GRID.s_min + H * (n_active + np.arange(st.n_right)) - model.lam * t)
        tau = tau_w + t
        free = (math.exp(-tau) * np.sin(math.sqrt(3.0) * q * math.exp(model.lam * tau))
                / (math.sqrt(3.0) * q * math.exp(model.lam * tau))
                if law.traceable and tau < 40.0 else 0.0)
        assert padded.shape == (1, n_left + st.n_state + st.n_right)
        np.testing.assert_allclose(ghosts, free - np.exp(-0.5 * q * q), rtol=1e-12, atol=1e-15)
        assert np.exp(-0.5 * q[0] * q[0]) > 1e-4  # the first ghosts' g is not 0 here
