"""Power-law tails and multiscaling of d-dimensional inelastic Maxwell models.

Model.  Collision rule v₁' = v₁ − p (g·n) n, v₂' = v₂ + p (g·n) n, g = v₁ − v₂, p = (1 + r)/2,
q = 1 − p; each particle collides at rate 1 whatever |g| (τ counts collisions per particle).
With k̂ the direction of the Fourier variable and n the collision direction, the isotropic
Fourier equation only needs the law w of η = (k̂·n)²:

* ``"uniform"``: n uniform on the sphere S^{d−1}, η ~ Beta(1/2, (d − 1)/2);
* ``"hard"``: n drawn with weight ∝ |ĝ·n| (uniform impact parameter), η ~ Beta(1, (d − 1)/2);
* d = 1: η ≡ 1 for both (the 1D Ulam model).

Growth function.  λ(s) = 1 − ⟨(1 − (1 − q²) η)^s⟩ − p^{2s} ⟨η^s⟩, with the closed forms
⟨η^s⟩ = B(a + s, b)/B(a, b) and ⟨(1 − cη)^s⟩ = ₂F₁(−s, a; a + b; c) for η ~ Beta(a, b)
(:func:`eta_moment`, :func:`mixed_moment`).  The coefficient of |k|^{2s} of Φ(k) decays at rate
λ(s), so the energy ⟨|v|²⟩ decays as e^{−Λτ} with Λ = λ(1) = 2pq⟨η⟩ (:func:`decay_rate`).

Tail.  The non-analytic term |k|^{2s} of the scaling solution balances only where
λ(s) = s λ(1); the tail root s* > 1 (:func:`tail_exponent`) gives a d-dimensional density
∝ c^{−d−2s*} and a speed or a Cartesian component density ∝ c^{−1−2s*}.  In d = 1, s* = 3/2 for
every r < 1 (1 − p³ − q³ = 3pq).

Root bracket.  F(s) = λ(s) − s λ(1) is concave in s (each ⟨X^s⟩ = ⟨e^{s ln X}⟩ is convex),
F(0) = −1 (η > 0 almost surely), F(1) = 0, and F(s) < 1 − s λ(1), so F < 0 for
s ≥ 1/λ(1).  A concave F therefore has at most one root above 1, and it has one exactly when F
rises after s = 1; we locate the maximum s_m of F on [1, s_hi], s_hi = max(2, 1/λ(1)) + 1, by
bounded minimisation (F is unimodal there) and run ``brentq`` on [s_m, s_hi], where F(s_m) > 0 and
F(s_hi) < 0.

r = 1 (elastic) is refused by :func:`tail_exponent`: in d ≥ 2 the elastic scaling law is the
Maxwellian (no power law; s* → ∞ as r → 1), and in d = 1 an elastic collision swaps the two
velocities, so the law never changes and λ ≡ 0 has no isolated root.  :func:`decay_rate` and
:func:`moment_rates` accept r = 1 (all rates are then exact, Λ = 0).

Multiscaling.  ⟨|v|^{2n}⟩ ∝ e^{−min(λ(n), n λ(1)) τ} for integers n ≥ 1 (:func:`moment_rates`):
moments with n > s* decay more slowly than ⟨|v|²⟩ⁿ.

The paper's 2D remark (a tail "compatible with α = 5" at r = 0).  At r = 0, d = 2:

* ``"hard"``: s* = 2 exactly (⟨η⟩ = 2/3, ⟨η²⟩ = 8/15, λ(1) = 1/3, λ(2) = 2/3), so the speed and
  a single Cartesian component decay as c^{−5}, the 2D density as c^{−6};
* ``"uniform"``: s* = 2.1438, i.e. c^{−5.29} (speed / component) and c^{−6.29} (density).

α = 5 is therefore the speed or component exponent of the hard (|ĝ·n|-weighted) model exactly; the
density exponent is 6 there, and the uniform model gives no exponent equal to 5 (5.29 is the
closest).  Caveat: s* = 2 is resonant (λ(2) = 2λ(1), so by the moment hierarchy M₄/M₂² grows
linearly in τ, and |k|⁴ being analytic, the singular term of Φ is presumably |k|⁴ ln|k|): expect
a logarithmic correction to the c^{−5} law.  Measured with :class:`particles.ulam.Ulam`
(d = 2, r = 0, N = 10⁶, Gaussian start; Hill estimator of the exponent of P(|v| > c) from the
largest k speeds, averaged over τ = 40, 50, …, 80; ± = standard error over 3 seeds):
hard 4.013 ± 0.028 (k = 10³), 3.931 ± 0.009 (k = 3·10³), theory 2s* = 4;
uniform 4.353 ± 0.036 (k = 10³), 4.215 ± 0.019 (k = 3·10³), theory 2s* = 4.2875.
The spread between k = 10³ and 3·10³ shows the threshold bias of the estimator (~0.1).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from particles.validation import InvalidArgumentError, check_restitution

from .angular import AngularLaw, angular_law
from .model import MaxwellModel

__all__ = [
    "TailExponent",
    "eta_moment",
    "mixed_moment",
    "growth_rate",
    "decay_rate",
    "moment_rates",
    "tail_exponent",
]

def eta_moment(law: AngularLaw, s):
    """⟨η^s⟩ = B(a + s, b)/B(a, b) (1 in d = 1), for s ≥ 0 (array-like).

    Parameters
    ----------
    law : maxwell_kinetics.angular.AngularLaw
        The law Beta(a, b) of η = (k̂·n)².
    s : array_like
        Exponents s ≥ 0.

    Returns
    -------
    numpy.ndarray
        ⟨η^s⟩, of the shape of ``s``.
    """
    return law.moment(s)


def mixed_moment(law: AngularLaw, c: float, s):
    """⟨(1 − c η)^s⟩ = ₂F₁(−s, a; a + b; c) for c ∈ [0, 1] ((1 − c)^s in d = 1).

    Parameters
    ----------
    law : maxwell_kinetics.angular.AngularLaw
        The law Beta(a, b) of η.
    c : float
        Coefficient in [0, 1].
    s : array_like
        Exponents s ≥ 0.

    Returns
    -------
    numpy.ndarray
        ⟨(1 − cη)^s⟩, of the shape of ``s`` (scipy's ``hyp2f1``).
    """
    return law.mixed_moment(c, s)


def growth_rate(dimension, restitution, s, angular="uniform"):
    """λ(s) = 1 − ⟨(1 − (1 − q²)η)^s⟩ − p^{2s}⟨η^s⟩: the decay rate of the |k|^{2s}
    coefficient of the isotropic characteristic function Φ(k).

    p = (1 + r)/2, q = 1 − p; rates are per unit τ (collisions per particle).  λ(1) = Λ is the
    energy decay rate and λ(n) that of ⟨|v|^{2n}⟩ (Ernst & Brito, J. Stat. Phys. 2002;
    Krapivsky & Ben-Naim, J. Phys. A 2002).

    Parameters
    ----------
    dimension : int
        1, 2 or 3.
    restitution : float
        r ∈ [0, 1].
    s : array_like
        Exponents s ≥ 0.
    angular : {"uniform", "hard"}
        Law of the collision direction.

    Returns
    -------
    numpy.ndarray
        λ(s), of the shape of ``s``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For a dimension, restitution or angular law out of range (from
        :func:`maxwell_kinetics.angular.angular_law` and ``check_restitution``).
    """
    law = angular_law(dimension, angular)
    return MaxwellModel(restitution, law.dimension, law.angular).coefficient_rate(s)


def decay_rate(dimension, restitution, angular="uniform") -> float:
    """Λ = 2pq⟨η⟩: ⟨|v|²⟩(τ) = ⟨|v|²⟩(0) e^{−Λτ} (zero mean, infinite N).

    Parameters
    ----------
    dimension : int
        1, 2 or 3.
    restitution : float
        r ∈ [0, 1].
    angular : {"uniform", "hard"}
        Law of the collision direction.

    Returns
    -------
    float
        Λ; in d = 1 it is 2λ = (1 − r²)/2.

    Raises
    ------
    particles.InvalidArgumentError
        For an argument out of range.
    """
    law = angular_law(dimension, angular)
    return float(MaxwellModel(restitution, law.dimension, law.angular).energy_rate())


def moment_rates(dimension, restitution, orders, angular="uniform") -> np.ndarray:
    """Decay rates min(λ(n), n λ(1)) of ⟨|v|^{2n}⟩ for the integers ``orders`` n ≥ 1.

    Parameters
    ----------
    dimension, restitution, angular
        As for :func:`decay_rate`.
    orders : array_like of int
        The n ≥ 1.

    Returns
    -------
    numpy.ndarray
        One rate per order; a rate below n λ(1) means multiscaling (Ben-Naim and Krapivsky).

    Raises
    ------
    particles.InvalidArgumentError
        For orders that are not integers ≥ 1, or another argument out of range.
    """
    law = angular_law(dimension, angular)
    model = MaxwellModel(restitution, law.dimension, law.angular)
    try:
        n = np.asarray(orders, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgumentError("orders", orders, "integers >= 1") from None
    if n.size == 0 or np.any(~np.isfinite(n)) or np.any(n < 1) or np.any(n != np.round(n)):
        raise InvalidArgumentError("orders", orders, "integers >= 1")
    lam1 = float(model.coefficient_rate(1.0))
    return np.minimum(model.coefficient_rate(n), n * lam1)


@dataclass(frozen=True)
class TailExponent:
    """The tail root s* > 1 of λ(s) = s λ(1) and the exponents it implies.

    Returned by :func:`tail_exponent`.

    Attributes
    ----------
    dimension : int
        Space dimension d.
    restitution : float
        r ∈ [0, 1).
    angular : str
        Angular model, "uniform" or "hard".
    s : float
        The tail root s*.
    decay_rate : float
        λ(1) = Λ, the energy decay rate per unit τ.
    exponents : dict of str to float
        ``"density"``: d + 2s* (the d-dimensional density ∝ c^{−d−2s*}); ``"speed"`` and
        ``"component"``: 1 + 2s*.
    """

    dimension: int
    restitution: float
    angular: str
    s: float
    decay_rate: float
    exponents: dict[str, float] = field(default_factory=dict)


def tail_exponent(dimension, restitution, angular="uniform") -> TailExponent:
    """The tail root s* of λ(s) = s λ(1) for r ∈ [0, 1) (bracket: module docstring).

    Parameters
    ----------
    dimension : int
        1, 2 or 3.
    restitution : float
        r ∈ [0, 1).
    angular : {"uniform", "hard"}
        Law of the collision direction: uniform on the sphere, or weighted by |ĝ·n|.

    Returns
    -------
    TailExponent
        The root s* and the exponents of the density (d + 2s*) and of the speed and one
        component (1 + 2s*); in d = 1, s* = 3/2 for every r (Ernst and Brito; Krapivsky and
        Ben-Naim).

    Raises
    ------
    particles.InvalidArgumentError
        For a dimension, restitution (r = 1 included: no power-law tail) or angular law out of
        range.
        Naming ``restitution`` also when r is so close to 1 (1 − 1e-8 in d = 3) that the root,
        s* ~ 1/(1 − r), cannot be bracketed in float64 (the concavity argument of the module
        docstring holds in exact arithmetic).
    """
    law = angular_law(dimension, angular)
    r = check_restitution(restitution)
    if r == 1.0:
        raise InvalidArgumentError(
            "restitution", restitution, "r < 1 (elastic collisions have no power-law tail)"
        )
    model = MaxwellModel(r, law.dimension, law.angular)
    lam1 = float(model.coefficient_rate(1.0))

    def balance(s):
        return float(model.coefficient_rate(s)) - s * lam1

    if law.degenerate:
        # d = 1: 1 − p³ − q³ = 3pq exactly (p + q = 1), so s* = 3/2 for every r; found
        # numerically the root is ill-conditioned as r → 1 (balance and its slope are O(q²):
        # s* = 1.50005 at r = 1 − 1e-13)
        s_star = 1.5
        return TailExponent(1, r, law.angular, s_star, lam1,
                            {"density": 1 + 2 * s_star, "speed": 1 + 2 * s_star,
                             "component": 1 + 2 * s_star})
    s_hi = max(2.0, 1.0 / lam1) + 1.0
    peak = minimize_scalar(
        lambda s: -balance(s), bounds=(1.0, s_hi), method="bounded", options={"xatol": 1e-10}
    )
    s_lo = float(peak.x)
    if not balance(s_lo) > 0.0 or not balance(s_hi) < 0.0:
        # s* grows like 1/(1 − r) in d >= 2; near r = 1 (1 − 1e-8 in d = 3) the moments
        # ⟨(1 − cη)^s⟩ at s ~ 1e8 are beyond scipy's hyp2f1 in float64
        raise InvalidArgumentError(
            "restitution", restitution,
            f"r further from 1: the tail root s* (> {s_lo:.3g}) cannot be bracketed in float64 "
            f"here ({law.dimension} dimensions, {law.angular})")
    s_star = brentq(balance, s_lo, s_hi, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    d = law.dimension
    return TailExponent(
        d,
        r,
        law.angular,
        float(s_star),
        lam1,
        {"density": d + 2 * s_star, "speed": 1 + 2 * s_star, "component": 1 + 2 * s_star},
    )
