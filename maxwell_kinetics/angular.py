"""The angular law of the d-dimensional isotropic Maxwell model: the law of η = (k̂·n)².

In d = 2, 3 a collision transfers momentum along a random direction n; the kinetic equation of
the characteristic function G(k) sees n only through η = (k̂·n)², the squared cosine between
the wave vector k and n.  η has the law Beta(a, (d − 1)/2), where the parameter a names the
angular model (:data:`ANGULAR_MODELS`: "uniform", n uniform on the sphere, a = 1/2; "hard", the
collision rate weighted by |k̂·n|, a = 1); in d = 1, η ≡ 1.  This module holds that law alone
(its moments, its mixed moments ⟨(1 − cη)^s⟩ and its Gauss–Jacobi quadrature); the collision
kernel that averages over it is :class:`maxwell_kinetics.model.MaxwellModel`
(Ernst & Brito, J. Stat. Phys. 2002; Krapivsky & Ben-Naim, J. Phys. A 2002).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from particles.ulam_kinematics import ANGULAR_MODELS as _ANGULAR_NAMES

__all__ = ["AngularLaw", "angular_law", "ANGULAR_MODELS"]

#: Angular models of the d-dimensional isotropic equation, each with the Beta parameter a of
#: η ~ Beta(a, (d − 1)/2) (see :func:`angular_law`).  Its names are those of the particle
#: engines (:data:`particles.ulam_kinematics.ANGULAR_MODELS`), in the same order.
ANGULAR_MODELS = dict(zip(_ANGULAR_NAMES, (0.5, 1.0), strict=True))


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

    def moment(self, s):
        """⟨η^s⟩ = B(a + s, b)/B(a, b) (1 in d = 1).

        Parameters
        ----------
        s : array_like
            Exponents s ≥ 0.

        Returns
        -------
        numpy.ndarray
            ⟨η^s⟩, of the shape of ``s`` (scipy's ``beta``).
        """
        s = np.asarray(s, dtype=float)
        if self.degenerate:
            return np.ones_like(s)
        from scipy.special import beta as beta_function

        return beta_function(self.a + s, self.b) / beta_function(self.a, self.b)

    def mixed_moment(self, c: float, s):
        """⟨(1 − c η)^s⟩ = ₂F₁(−s, a; a + b; c) for c ∈ [0, 1] ((1 − c)^s in d = 1).

        Parameters
        ----------
        c : float
            Coefficient in [0, 1].
        s : array_like
            Exponents s ≥ 0.

        Returns
        -------
        numpy.ndarray
            ⟨(1 − cη)^s⟩, of the shape of ``s`` (scipy's ``hyp2f1``).
        """
        s = np.asarray(s, dtype=float)
        if self.degenerate:
            return (1.0 - c) ** s
        from scipy.special import hyp2f1

        return hyp2f1(-s, self.a, self.a + self.b, c)

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
