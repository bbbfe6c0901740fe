"""The collision rule and the constants of the pseudo-Maxwell (Ulam) model.

A colliding pair (i, j), Δ = v_i − v_j, becomes v_i' = v_i − pΔ, v_j' = v_j + pΔ with
p = (1 + r)/2.  Constants: β = 1/p (the paper's β = 2/(1+r)) and λ = p(1 − p) = (1 − r²)/4.
Time τ counts collisions per particle.  With unit initial variance the energy decays as
⟨v²⟩(τ) = e^{−2λτ}.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from particles.validation import check_nonnegative, check_real, check_restitution

__all__ = ["MaxwellModel", "AngularLaw", "angular_law", "ANGULAR_MODELS"]

#: Angular models of the d-dimensional isotropic equation, each with the Beta parameter a of
#: η ~ Beta(a, (d − 1)/2) (see :func:`angular_law`).
ANGULAR_MODELS = {"uniform": 0.5, "hard": 1.0}


@dataclass(frozen=True)
class AngularLaw:
    """The law of η = (k̂·n)² of the d-dimensional isotropic Maxwell model.

    k̂ is the wave vector's direction and n the collision direction.  η has the law
    Beta(a, b) with b = (d − 1)/2 in d = 2, 3, and is the point mass η ≡ 1 in d = 1 (stored as
    a = 1, b = 0).  ``a, b = law`` unpacks the two parameters.  Build it with
    :func:`angular_law`, which checks the arguments (Ernst & Brito, J. Stat. Phys. 2002;
    Krapivsky & Ben-Naim, J. Phys. A 2002).

    Attributes
    ----------
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    angular : str
        Name of the angular model, a key of ``ANGULAR_MODELS`` ("uniform" or "hard").
    a, b : float
        The Beta parameters of η (a = 1, b = 0 in d = 1).
    """

    dimension: int
    angular: str
    a: float
    b: float

    @property
    def degenerate(self) -> bool:
        """True in d = 1 (η ≡ 1)."""
        return self.dimension == 1

    @property
    def mean(self) -> float:
        """⟨η⟩ = a / (a + b): 1/d ("uniform"), 2/(d + 1) ("hard"), 1 in d = 1."""
        return self.a / (self.a + self.b)

    def __iter__(self):
        yield self.a
        yield self.b

    def quadrature(self, nodes: int) -> tuple[np.ndarray, np.ndarray]:
        """Gauss–Jacobi quadrature of this Beta law.

        Returns nodes η_i and weights ω_i (Σ ω_i = 1) of ``nodes`` points: exact for
        polynomials in η of degree 2 nodes − 1, in particular ⟨η⟩.  d = 1: the single node
        η = 1 whatever ``nodes``.

        The gain integrand G(q √(1 − (1 − q₁²)η)) G(p q √η) varies with η on a scale ~1/q²,
        so few nodes suffice at small q; the solver picks the count per range of q
        (``maxwell_kinetics._kinetic_scheme.angular_tiers``).

        Parameters
        ----------
        nodes : int
            Number of quadrature points (ignored in d = 1).

        Returns
        -------
        eta, weights : numpy.ndarray
            Nodes in (0, 1) and normalised weights, both of shape (nodes,) (shape (1,) in
            d = 1).  Computed with :func:`scipy.special.roots_jacobi`.
        """
        if self.degenerate:
            return np.ones(1), np.ones(1)
        from scipy.special import roots_jacobi

        # weight (1 − x)^α (1 + x)^β on [−1, 1]; η = (1 + x)/2 gives η^β (1 − η)^α.
        x, w = roots_jacobi(int(nodes), self.b - 1.0, self.a - 1.0)
        return 0.5 * (1.0 + x), w / w.sum()


def angular_law(dimension: int, angular: str = "uniform") -> AngularLaw:
    """The checked :class:`AngularLaw` of η = (k̂·n)² for a dimension and an angular model.

    "uniform": n uniform on the sphere, η ~ Beta(1/2, (d − 1)/2); "hard": the collision rate
    weighted by |k̂·n| (uniform impact parameter), η ~ Beta(1, (d − 1)/2); d = 1: η ≡ 1
    (Ernst & Brito, J. Stat. Phys. 2002).

    Parameters
    ----------
    dimension : int
        Space dimension d ∈ {1, 2, 3} (a bool is refused).
    angular : str, default "uniform"
        Angular model, a key of ``ANGULAR_MODELS``.

    Returns
    -------
    AngularLaw
        The law of η (a = 1, b = 0 in d = 1).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``dimension`` is not 1, 2 or 3, or ``angular`` is not a known model.
    """
    from particles.validation import check_choice, check_dimension

    d = check_dimension(dimension)
    angular = check_choice(angular, "angular", ANGULAR_MODELS)
    if d == 1:
        return AngularLaw(1, angular, 1.0, 0.0)
    return AngularLaw(d, angular, ANGULAR_MODELS[angular], 0.5 * (d - 1))


@dataclass(frozen=True)
class MaxwellModel:
    """Constants of the 1D pseudo-Maxwell (Ulam) model with restitution coefficient r.

    A colliding pair exchanges the fraction p = (1 + r)/2 of its velocity difference; every
    particle collides at rate 1 with a random partner, so τ counts collisions per particle
    (not physical time t).  The derived constants are p, β = 1/p and λ = p(1 − p) =
    (1 − r²)/4, and the rates of the moment hierarchy and of the Fourier-space linearisation
    near q = 0 (Ben-Naim & Krapivsky, Phys. Rev. E 2000; Bobylev, Cercignani & Toscani,
    J. Stat. Phys. 2003).

    Attributes
    ----------
    restitution : float
        Restitution coefficient r ∈ [0, 1], checked at construction (r = 1 elastic).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not a number in [0, 1] (from
        :func:`particles.validation.check_restitution`).
    """

    restitution: float

    def __post_init__(self):
        object.__setattr__(self, "restitution", check_restitution(self.restitution))

    @property
    def p(self) -> float:
        """Momentum-transfer fraction p = (1 + r)/2 ∈ [1/2, 1]."""
        return 0.5 * (1.0 + self.restitution)

    @property
    def beta(self) -> float:
        """β = 2/(1 + r) = 1/p, as in the paper's velocity-space master equation."""
        return 1.0 / self.p

    @property
    def lam(self) -> float:
        """λ = p(1 − p) = (1 − r²)/4: the energy decays as e^{−2λτ}."""
        return 0.25 * (1.0 - self.restitution**2)

    def moment_rate(self, n: float) -> float:
        """Leading decay rate a_n = 1 − pⁿ − (1 − p)ⁿ of the moment M_n (Ben-Naim & Krapivsky).

        Parameters
        ----------
        n : float
            Moment order (need not be an integer).

        Returns
        -------
        float
            a_n, per unit τ: M_n ∝ e^{−a_n τ} at late times.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``n`` is not a finite real number (booleans and complex numbers refused).
        """
        n = check_real(n, "n")
        return 1.0 - self.p**n - (1.0 - self.p) ** n

    def growth_rate(self, s: float) -> float:
        """g(s) = λs − 1 + p^s + (1 − p)^s: growth rate of a perturbation ∝ q^s of G near q = 0.

        G is the rescaled characteristic function G(q, τ) = P̂(q / v0(τ), τ); g(2) = g(3) = 0
        and g < 0 on (2, 3) for r < 1.

        Parameters
        ----------
        s : float
            Power of the perturbation.

        Returns
        -------
        float
            g(s), per unit τ.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``s`` is not a finite real number (booleans and complex numbers refused).
        """
        s = check_real(s, "s")
        return self.lam * s - 1.0 + self.p**s + (1.0 - self.p) ** s

    def contraction_rate(self, s: float) -> float:
        """γ(s) = −g(s) = 1 − λs − p^s − (1 − p)^s, positive for s ∈ (2, 3) when r < 1.

        d_s(G(τ), f̂) ≤ e^{−γ(s)τ} d_s(G(0), f̂) (Bobylev–Cercignani–Toscani), with
        d_s(F, H) = sup_q |F(q) − H(q)| / |q|^s.

        Parameters
        ----------
        s : float
            Exponent of the Fourier metric d_s.

        Returns
        -------
        float
            γ(s), per unit τ.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``s`` is not a finite real number (booleans and complex numbers refused).
        """
        return -self.growth_rate(s)

    def energy_rate(self, dimension: int = 1, angular: str = "uniform") -> float:
        """Λ = 2 p (1 − p) ⟨η⟩ of the d-dimensional isotropic model: ⟨|v|²⟩ ∝ e^{−Λτ}.

        η = (k̂·n)² has the law of :func:`angular_law` (⟨η⟩ = 1/d "uniform", 2/(d + 1)
        "hard"; η ≡ 1 for d = 1, where Λ = 2λ).

        Parameters
        ----------
        dimension : int, default 1
            Space dimension d ∈ {1, 2, 3}.
        angular : str, default "uniform"
            Angular model, "uniform" or "hard".

        Returns
        -------
        float
            Λ, per unit τ.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``dimension`` or ``angular`` is invalid (from :func:`angular_law`).
        """
        return 2.0 * self.lam * angular_law(dimension, angular).mean

    def energy(self, tau: float) -> float:
        """⟨v²⟩(τ) = e^{−2λτ} for unit initial variance and zero mean (1D).

        Parameters
        ----------
        tau : float
            Collisions per particle τ.

        Returns
        -------
        float
            The mean energy ⟨v²⟩ at τ.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``tau`` is not a finite real number >= 0.
        """
        tau = check_nonnegative(tau, "tau")
        return math.exp(-2.0 * self.lam * tau)
