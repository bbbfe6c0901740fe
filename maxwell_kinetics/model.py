"""The kinetic collision models, in one place: every kinetic module reads its kernel from here.

The pseudo-Maxwell (Ulam) kernel.  A colliding pair (i, j), Δ = v_i − v_j, becomes
v_i' = v_i − pΔ, v_j' = v_j + pΔ with p = (1 + r)/2 (:func:`particles.collision.transfer_fraction`,
the particle engines' own rule).  Constants: β = 1/p (the paper's β = 2/(1+r)) and
λ = p(1 − p) = (1 − r²)/4.  Time τ counts collisions per particle.  With unit initial variance
the energy decays as ⟨v²⟩(τ) = e^{−2λτ} (d = 1) and as e^{−Λτ}, Λ = 2λ⟨η⟩, in d = 2, 3.

What a kernel holds (and no other kinetic module writes out):

* :class:`MaxwellModel` — the Maxwell kernel in d = 1, 2, 3 averaged over its angular law
  (the law of η, :class:`~maxwell_kinetics.angular.AngularLaw`, in its own module
  :mod:`maxwell_kinetics.angular`): p, λ, the complement 1 − p, the factors of the gain
  G(b q) G(a q) (d = 1: b = p, a = 1 − p; d ≥ 2: b = p √η, a = √(1 − (1 − (1 − p)²) η) averaged
  over η), their logarithms (the solver's stencil shifts), the moment rates 1 − p^s − (1 − p)^s
  for any order s and the rates λ(s) of the |k|^{2s} coefficients, the energy decay rate Λ, the
  transport speed Λ/2 of the rescaled equation, and the sums p^k + (1 − p)^k in terms of λ that
  the source of the deviation equation uses.  The static methods ending in ``_of`` take p (or
  λ) as an argument and use only arithmetic, so the compiled scheme calls them on traced JAX
  values and gets the same graph as the expressions written in place.
* :class:`DrivenMaxwellModel` — the same kernel heated by white noise of strength D.
* :class:`RelativeVelocityModel` — the 1D kernel whose pairs collide at rate n|v − w|^γ
  (γ = 1: hard rods, the kinetic equation of molecular dynamics under molecular chaos; γ = 0:
  the Maxwell model in physical time t = τ/n), solved in velocity space by
  :mod:`maxwell_kinetics.inelastic_boltzmann`.

Kernels are listed in :data:`KINETIC_MODELS`.  Each is a :class:`CollisionModel`, whose class
attribute ``fourier_closed`` says whether the kernel's Fourier-space equation closes (a Maxwell
kernel: the collision rate does not depend on the relative velocity, so the gain is a product of
characteristic functions) or whether the kernel lives in velocity space only (a rate that
depends on |v − w|, e.g. hard rods with rate ∝ |v − w|).

How to add a kernel: write a frozen dataclass subclassing :class:`CollisionModel` in this module,
set ``name`` and ``fourier_closed``, implement :meth:`CollisionModel.rate` (the collision rate
of a pair with velocities v, w, relative to the Maxwell rate 1) and
:meth:`CollisionModel.energy_rate`.  A Fourier-closed kernel also provides the gain factors and
moment rates of :class:`MaxwellModel` that the Fourier solvers read; a velocity-space kernel
provides what its velocity-space solver needs (its post-collision velocities are those of
``transfer_fraction``; only the rate differs).  Then add one line to :data:`KINETIC_MODELS`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from particles import kernels as _kernels
from particles.collision import transfer_fraction
from particles.validation import check_nonnegative, check_real, check_restitution

from . import angular as _angular

__all__ = ["maxwell_restitution", "CollisionModel", "MaxwellModel", "DrivenMaxwellModel",
           "RelativeVelocityModel",
           "KINETIC_MODELS", "RATE_EXPONENTS"]

# Names moved out of this module, by new home: importing one from here raises an ImportError
# naming the new home (they are not re-exported: each name has one home).
_MOVED = {name: "maxwell_kinetics.angular" for name in ("AngularLaw", "angular_law",
                                                         "ANGULAR_MODELS")}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"maxwell_kinetics.model.{name} moved to {_MOVED[name]}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")



def maxwell_restitution(value, argument: str = "kernel"):
    """The restitution r of the Maxwell kernel, from r itself (returned as given, checked by its
    reader) or a kernel whose Fourier-space equation closes
    (:class:`particles.kernels.ConstantRate`, or a model holding one): what the Fourier-space
    fixed point, linear rates and driven steady state take.

    Parameters
    ----------
    value : float or particles.kernels.Kernel
        r, or the kernel.
    argument : str, optional
        The argument's name in errors.

    Returns
    -------
    float or object
        r (a kernel's, or ``value`` unchanged).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``argument`` for a kernel whose Fourier-space equation does not close (its
        scaling state is :func:`maxwell_kinetics.inelastic_boltzmann.scaling_state`).
    """
    kernel = getattr(value, "kernel", value)
    if not isinstance(kernel, _kernels.Kernel):
        return value
    if not kernel.fourier_closed:
        from particles.validation import InvalidArgumentError

        raise InvalidArgumentError(argument, value, "a restitution or a kernel whose "
                                   "Fourier-space equation closes (the scaling state of "
                                   f"{kernel.name!r} is inelastic_boltzmann.scaling_state)")
    return kernel.restitution


@dataclass(frozen=True)
class CollisionModel:
    """A kinetic collision model (kernel): the base of the classes of :data:`KINETIC_MODELS`.

    Every pair of particles collides at rate :meth:`rate` (per unit τ, relative to the Maxwell
    rate 1) and a collision transfers the fraction p = (1 + r)/2 of the relative velocity.

    Attributes
    ----------
    restitution : float
        Restitution coefficient r ∈ [0, 1], checked at construction (r = 1 elastic).
    name : str
        Class attribute: the model's key in :data:`KINETIC_MODELS`.
    fourier_closed : bool
        Class attribute: True when the Fourier-space equation closes (a rate independent of the
        relative velocity, as for Maxwell molecules), False for a velocity-space kernel.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``restitution`` is not a number in [0, 1] (from
        :func:`particles.validation.check_restitution`).
    """

    name: ClassVar[str] = ""
    fourier_closed: ClassVar[bool] = False

    restitution: float

    def __post_init__(self):
        object.__setattr__(self, "restitution", check_restitution(self.restitution))

    @property
    def p(self) -> float:
        """Momentum-transfer fraction p = (1 + r)/2 ∈ [1/2, 1]
        (:func:`particles.collision.transfer_fraction`, the particle engines' rule)."""
        return transfer_fraction(self.restitution)

    def rate(self, v, w, xp=np):
        """The collision rate of a pair with velocities ``v``, ``w`` (arrays of ``xp``, the
        velocity components along the last axis in d ≥ 2), per unit τ.

        Parameters
        ----------
        v, w : array
            Velocities of the two partners (arrays of ``xp``).
        xp : module, default numpy
            Array module (``numpy`` or ``jax.numpy``).

        Returns
        -------
        array
            The rate of each pair.

        Raises
        ------
        NotImplementedError
            In this base class: each kernel defines it.
        """
        raise NotImplementedError(f"{type(self).__name__} defines no collision rate")

    def energy_rate(self) -> float:
        """Λ: the mean energy of the free (undriven) gas decays as e^{−Λτ}.

        Raises
        ------
        NotImplementedError
            In this base class: each kernel defines it.
        """
        raise NotImplementedError(f"{type(self).__name__} defines no energy decay rate")


@dataclass(frozen=True)
class MaxwellModel(CollisionModel):
    """The pseudo-Maxwell (Ulam) kernel with restitution coefficient r, in dimension d.

    A colliding pair exchanges the fraction p = (1 + r)/2 of its velocity difference (of its
    component along the collision direction n in d ≥ 2); every particle collides at rate 1 with
    a random partner, so τ counts collisions per particle (not physical time t).  The derived
    constants are p, β = 1/p and λ = p(1 − p) = (1 − r²)/4, and the rates of the moment
    hierarchy and of the Fourier-space linearisation near q = 0 (Ben-Naim & Krapivsky, Phys.
    Rev. E 2000; Bobylev, Cercignani & Toscani, J. Stat. Phys. 2003; Ernst & Brito, J. Stat.
    Phys. 2002).  The rescaled equation of G(q, τ) reads

        ∂τ G = (Λ/2) q ∂q G − G + ⟨G(b q) G(a q)⟩_η,   b = p √η,  a = √(1 − (1 − (1 − p)²) η),

    η = (k̂·n)² of the law :attr:`law` (η ≡ 1 in d = 1: b = p, a = 1 − p, Λ/2 = λ).

    Attributes
    ----------
    restitution : float
        Restitution coefficient r ∈ [0, 1], checked at construction (r = 1 elastic).
    dimension : int, default 1
        Space dimension d ∈ {1, 2, 3}.
    angular : str, default "uniform"
        Angular model, a key of :data:`maxwell_kinetics.angular.ANGULAR_MODELS` (irrelevant
        in d = 1).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``dimension`` or ``angular`` is invalid (from
        :func:`~maxwell_kinetics.angular.angular_law`), or
        ``restitution`` is not a number in [0, 1] (from
        :func:`particles.validation.check_restitution`).
    """

    name: ClassVar[str] = "maxwell"
    fourier_closed: ClassVar[bool] = True

    dimension: int = 1
    angular: str = "uniform"

    def __post_init__(self):
        law = _angular.angular_law(self.dimension, self.angular)
        object.__setattr__(self, "dimension", law.dimension)
        object.__setattr__(self, "angular", law.angular)
        super().__post_init__()

    # -- the kernel as functions of p (or λ): host floats, NumPy arrays or traced JAX values --

    @staticmethod
    def complement_of(p):
        """1 − p: the fraction of the relative velocity a particle keeps (the gain's second
        argument (1 − p) q in d = 1).

        Parameters
        ----------
        p : float or array
            The transfer fraction p (a float, a NumPy array or a traced JAX array).

        Returns
        -------
        float or array
            ``1.0 - p``, of the type of ``p``.
        """
        return 1.0 - p

    @staticmethod
    def lam_of(p):
        """λ = p(1 − p), computed as ``p * (1.0 - p)``.

        Parameters
        ----------
        p : float or array
            The transfer fraction p (a float, a NumPy array or a traced JAX array).

        Returns
        -------
        float or array
            λ, of the type of ``p``.
        """
        return p * (1.0 - p)

    @staticmethod
    def cross_fraction_of(p):
        """1 − (1 − p)² = p(2 − p): the coefficient c of a² = 1 − c η in the gain factor
        a = √(1 − c η) (d ≥ 2).

        Parameters
        ----------
        p : float or array
            The transfer fraction p (a float, a NumPy array or a traced JAX array).

        Returns
        -------
        float or array
            c, of the type of ``p``.
        """
        return 1.0 - (1.0 - p) ** 2

    @staticmethod
    def rate_of(p, s):
        """1 − p^s − (1 − p)^s: the decay rate of the moment of order s (d = 1), per unit τ,
        computed as −expm1(s ln(1 − q)) − q^s with q = 1 − p, so that 1 − p^s keeps its relative
        precision as r → 1 (q → 0, where 1 − p^s ≈ sq).  Host arithmetic (NumPy).

        Parameters
        ----------
        p : float or array
            The transfer fraction p (a float, a NumPy array or a traced JAX array).
        s : float or array
            Moment order (need not be an integer).

        Returns
        -------
        float or array
            The rate, broadcast over ``p`` and ``s``.
        """
        q = 1.0 - np.asarray(p, dtype=float)
        s = np.asarray(s, dtype=float)
        out = -np.expm1(s * np.log1p(-q)) - q**s
        return float(out) if out.ndim == 0 else out

    @staticmethod
    def power_sum_of(lam, k: int):
        """p^k + (1 − p)^k in terms of λ = p(1 − p), for k = 2 (1 − 2λ) and k = 3 (1 − 3λ).

        Parameters
        ----------
        lam : float or array
            λ (a float, a NumPy array or a traced JAX array).
        k : int
            2 or 3.

        Returns
        -------
        float or array
            ``1.0 - k * lam``, of the type of ``lam``.

        Raises
        ------
        ValueError
            For another ``k``.
        """
        if k == 2:
            return 1.0 - 2.0 * lam
        if k == 3:
            return 1.0 - 3.0 * lam
        raise ValueError(f"power_sum_of: k must be 2 or 3, got {k!r}")

    @staticmethod
    def gain_scales_of(p, eta, xp=np):
        """(b, a) = (p √η, √(1 − (1 − (1 − p)²) η)): the gain is G(b q) G(a q) at the node η.

        Parameters
        ----------
        p : float or array
            The transfer fraction p (a float, a NumPy array or a traced JAX array).
        eta : float or array
            η = (k̂·n)² ∈ [0, 1] (η = 1 gives b = p, a = 1 − p: d = 1).
        xp : module, default numpy
            Array module of ``sqrt`` (``numpy`` or ``jax.numpy``).

        Returns
        -------
        b, a : float or array
            The two factors.
        """
        return p * xp.sqrt(eta), xp.sqrt(1.0 - (1.0 - (1.0 - p) ** 2) * eta)

    # -- the model's own numbers --

    @property
    def law(self) -> _angular.AngularLaw:
        """The :class:`~maxwell_kinetics.angular.AngularLaw` of η = (k̂·n)² (η ≡ 1 in d = 1)."""
        return _angular.angular_law(self.dimension, self.angular)

    def rate(self, v, w, xp=np):
        """1 for every pair (Maxwell molecules).

        Parameters
        ----------
        v, w : array
            Velocities of the two partners (arrays of ``xp``).
        xp : module, default numpy
            Array module (``numpy`` or ``jax.numpy``).

        Returns
        -------
        array
            Ones, of the broadcast shape of ``v`` and ``w`` (less the last axis in d ≥ 2).
        """
        shape = np.broadcast_shapes(xp.shape(v), xp.shape(w))
        return xp.ones(shape if self.dimension == 1 else shape[:-1])

    @property
    def beta(self) -> float:
        """β = 2/(1 + r) = 1/p, as in the paper's velocity-space master equation."""
        return 1.0 / self.p

    @property
    def lam(self) -> float:
        """The rate λ = p(1 − p) = (1 − r²)/4, computed as the latter (accurate as r → 1).

        In d = 1 the energy decays as e^{−2λτ}."""
        return 0.25 * (1.0 - self.restitution**2)

    @property
    def complement(self) -> float:
        """1 − p (:meth:`complement_of`)."""
        return self.complement_of(self.p)

    @property
    def pair_lam(self) -> float:
        """λ computed from p as p(1 − p) (:meth:`lam_of`; equals :attr:`lam` to round-off)."""
        return self.lam_of(self.p)

    def gain_shifts(self, eta: float) -> tuple[float, float]:
        """(ln b, ln a) of the gain factors at the node η (:meth:`gain_scales_of`): ln p and
        ln(1 − p) for η = 1 (d = 1, by log and log1p), else ln p + ½ ln η and
        ½ ln(1 − (1 − (1 − p)²) η) (log1p).  The solver's stencils move by these over h.

        Parameters
        ----------
        eta : float
            η ∈ (0, 1].

        Returns
        -------
        shift_b, shift_a : float
            ln b and ln a.
        """
        p = self.p
        q = 1.0 - p
        if eta == 1.0:
            return math.log(p), math.log1p(-p)
        return math.log(p) + 0.5 * math.log(eta), 0.5 * math.log1p(-(1.0 - q * q) * eta)

    def gain_moment_coefficients(self, nmax: int) -> np.ndarray:
        """c[n, m] = C(n, m) p^m (1 − p)^{n−m} (m ≤ n ≤ ``nmax``): the n-th moment of the gain
        is Σ_m c[n, m] M_m M_{n−m} (d = 1).

        Parameters
        ----------
        nmax : int
            Highest moment order.

        Returns
        -------
        numpy.ndarray
            c, shape (nmax + 1, nmax + 1), zero above the diagonal.
        """
        p = self.p
        coef = np.zeros((nmax + 1, nmax + 1))
        for n in range(nmax + 1):
            for m in range(n + 1):
                coef[n, m] = math.comb(n, m) * p**m * self.complement_of(p) ** (n - m)
        return coef

    def coefficient_rate(self, s):
        """λ(s) = 1 − ⟨(1 − (1 − (1 − p)²)η)^s⟩ − p^{2s}⟨η^s⟩: decay rate of the |k|^{2s}
        coefficient of the characteristic function, per unit τ (array_like s ≥ 0, a NumPy
        array).  d = 1: 1 − p^{2s} − (1 − p)^{2s}, with 1 − p^{2s} free of cancellation as
        r → 1.  λ(1) = Λ, λ(n) the rate of ⟨|v|^{2n}⟩.

        Parameters
        ----------
        s : array_like
            Exponents s ≥ 0.

        Returns
        -------
        numpy.ndarray
            λ(s), of the shape of ``s``.
        """
        law, p = self.law, self.p
        q = 0.5 * (1.0 - self.restitution)  # 1 − p, exact for r ≥ 1/2 (1.0 − p would round)
        if law.degenerate:
            s = np.asarray(s, dtype=float)
            return -np.expm1(2.0 * s * np.log1p(-q)) - q ** (2.0 * s)
        return (1.0 - law.mixed_moment(1.0 - q * q, s)
                - p ** (2.0 * np.asarray(s)) * law.moment(s))

    def transport_speed(self, eta: np.ndarray, weights: np.ndarray) -> float:
        """p (1 − p) Σ ω_i η_i for a quadrature (η_i, ω_i) of the law (= Λ/2 with the
        quadrature's own ⟨η⟩, so that the discrete equation keeps G''(0) = −1 exactly); λ for
        the single node η = 1 (d = 1).

        Parameters
        ----------
        eta, weights : numpy.ndarray
            Nodes η_i and weights ω_i (Σ ω_i = 1) of the quadrature.

        Returns
        -------
        float
            The speed, per unit τ.
        """
        if eta.size == 1 and eta[0] == 1.0:
            return self.lam
        return self.lam * float(weights @ eta)

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
        return self.rate_of(self.p, n)

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

    def energy_rate(self, dimension: int | None = None, angular: str | None = None) -> float:
        """Λ = 2 p (1 − p) ⟨η⟩ of the d-dimensional isotropic model: ⟨|v|²⟩ ∝ e^{−Λτ}.

        η = (k̂·n)² has the law of :func:`~maxwell_kinetics.angular.angular_law` (⟨η⟩ = 1/d
        "uniform", 2/(d + 1) "hard"; η ≡ 1 for d = 1, where Λ = 2λ).  Computed as 2λ⟨η⟩ with
        λ = (1 − r²)/4.

        Parameters
        ----------
        dimension : int, optional
            Space dimension d ∈ {1, 2, 3}; None: the model's own.
        angular : str, optional
            Angular model, "uniform" or "hard"; None: the model's own.

        Returns
        -------
        float
            Λ, per unit τ.

        Raises
        ------
        particles.validation.InvalidArgumentError
            If ``dimension`` or ``angular`` is invalid (from
            :func:`~maxwell_kinetics.angular.angular_law`).
        """
        law = _angular.angular_law(self.dimension if dimension is None else dimension,
                                   self.angular if angular is None else angular)
        return 2.0 * self.lam * law.mean

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


@dataclass(frozen=True)
class DrivenMaxwellModel(MaxwellModel):
    """The 1D Maxwell kernel heated by white noise of strength D between collisions
    (:mod:`maxwell_kinetics.driven`): ∂τ P̂ = −D k² P̂ − P̂ + P̂(pk) P̂((1 − p)k).

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1] (the steady state needs r < 1: :mod:`maxwell_kinetics.driven` checks it).
    dimension, angular
        As for :class:`MaxwellModel`; the driven model is one-dimensional: ``dimension`` must
        be 1.
    driving : float, default 1.0
        Noise strength D ≥ 0, keyword only (checked by :mod:`maxwell_kinetics.driven`).

    Raises
    ------
    particles.validation.InvalidArgumentError
        As :class:`MaxwellModel`, and for ``dimension`` other than 1.
    """

    name: ClassVar[str] = "driven"

    driving: float = field(default=1.0, kw_only=True)

    def __post_init__(self):
        super().__post_init__()
        if self.dimension != 1:
            from particles.validation import InvalidArgumentError

            raise InvalidArgumentError("dimension", self.dimension,
                                       "1 (the driven model is one-dimensional; pass driving= "
                                       "by name)")

    def moment_rates(self, orders) -> np.ndarray:
        """a_j = 1 − p^{2j} − (1 − p)^{2j} of the cumulant/moment hierarchy, for array_like j
        (:meth:`MaxwellModel.rate_of` at s = 2j).

        Parameters
        ----------
        orders : array_like
            The j ≥ 1.

        Returns
        -------
        numpy.ndarray
            a_j, of the shape of ``orders``.
        """
        return self.rate_of(self.p, 2.0 * np.asarray(orders, dtype=float))

    @property
    def steady_energy(self) -> float:
        """⟨v²⟩ = D / (p(1 − p)) of the steady state (zero mean)."""
        return self.driving / self.lam_of(self.p)


#: The exponents γ of the rate n|v − w|^γ that :class:`RelativeVelocityModel` accepts: 0 (the
#: Maxwell model in physical time) to 2, the range of the velocity-space solver (its collision
#: sums are exact in moments for any γ ≥ 0; beyond 2 the tails of f grow too fast for a grid of
#: fixed extent: ``maxwell_kinetics.inelastic_boltzmann``).
RATE_EXPONENTS = (_kernels.EXPONENT.low, _kernels.EXPONENT.high)


@dataclass(frozen=True)
class RelativeVelocityModel(CollisionModel):
    """The 1D inelastic kernel whose pairs collide at rate n|v − w|^γ (a velocity-space kernel).

    The weak form of its homogeneous Boltzmann equation, for any test function φ, at density n
    and physical time t:

        d/dt ∫φ f dv = (n/2) ∫∫ |v − w|^γ f(v) f(w) [φ(v′) + φ(w′) − φ(v) − φ(w)] dv dw,

    v′ = v − p(v − w), w′ = w + p(v − w), p = (1 + r)/2
    (:func:`particles.collision.transfer_fraction`).
    γ = 1 is hard rods (point particles on a line); γ = 0 is the Maxwell model, whose time τ
    (collisions per particle) is n t.  Mass and momentum are conserved and
    d⟨v²⟩/dt = −λ n ⟨|v − w|^{γ+2}⟩, λ = (1 − r²)/4.

    Attributes
    ----------
    restitution : float
        Restitution coefficient r ∈ [0, 1], checked at construction (r = 1 elastic).
    exponent : float, default 1.0
        γ of the rate |v − w|^γ, in :data:`RATE_EXPONENTS` (a closed range).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``restitution`` if it is not a number in [0, 1], ``exponent`` if it is not a
        finite real number in :data:`RATE_EXPONENTS`.
    """

    name: ClassVar[str] = _kernels.RelativeVelocity.name
    fourier_closed: ClassVar[bool] = False

    exponent: float = 1.0

    def __post_init__(self):
        super().__post_init__()
        from particles.validation import InvalidArgumentError

        gamma = check_real(self.exponent, "exponent")
        low, high = RATE_EXPONENTS
        if not low <= gamma <= high:
            raise InvalidArgumentError("exponent", self.exponent,
                                       f"an exponent gamma of the rate |v - w|^gamma in "
                                       f"[{low:g}, {high:g}]")
        object.__setattr__(self, "exponent", gamma)

    @property
    def kernel(self) -> _kernels.RelativeVelocity:
        """The collision kernel of the base layer (:class:`particles.kernels.RelativeVelocity`)
        whose rate and bound the particle engines read: the same formulas."""
        return _kernels.RelativeVelocity(self.restitution, self.exponent)

    @property
    def complement(self) -> float:
        """1 − p: the fraction of its own velocity a colliding particle keeps
        (v′ = (1 − p) v + p w)."""
        return MaxwellModel.complement_of(self.p)

    @property
    def lam(self) -> float:
        """λ = p(1 − p) = (1 − r²)/4 (computed as the latter): a pair with relative velocity g
        loses 2λg² of v² + w²."""
        return 0.25 * (1.0 - self.restitution**2)

    def rate(self, v, w, xp=np):
        """|v − w|^γ: the collision rate of a pair per unit density and time (1 for γ = 0,
        also at v = w).

        Parameters
        ----------
        v, w : array
            Velocities of the two partners (arrays of ``xp``).
        xp : module, default numpy
            Array module (``numpy`` or ``jax.numpy``).

        Returns
        -------
        array
            The rate of each pair, of the broadcast shape of ``v`` and ``w``
            (:meth:`particles.kernels.RelativeVelocity.rate`, the engines' formula).
        """
        return self.kernel.rate(v, w, xp)

    def post_collision(self, v, w):
        """v′ = (1 − p) v + p w: the velocity of the partner that had ``v``, after colliding with
        one that had ``w`` (the other leaves with (1 − p) w + p v).

        Parameters
        ----------
        v, w : array_like
            Pre-collision velocities.

        Returns
        -------
        array_like
            v′, of the broadcast shape.
        """
        return self.complement * v + self.p * w

    def energy_rate(self) -> float:
        """−d ln⟨v²⟩/dt is not a constant for γ > 0 (it is λ n⟨|v − w|^{γ+2}⟩/⟨v²⟩, which
        depends on the law); for γ = 0 it is 2λ n.

        Returns
        -------
        float
            2λ, per unit n t, for γ = 0.

        Raises
        ------
        NotImplementedError
            For γ > 0 (use the solver's ``energy`` instead).
        """
        if self.exponent == 0.0:
            return 2.0 * self.lam
        raise NotImplementedError("the energy of a gas with rate |v - w|^gamma, gamma > 0, does "
                                  "not decay at a constant rate: solve for it")


#: The kinetic models, by name: add a kernel's class here (module docstring).
KINETIC_MODELS: dict[str, type[CollisionModel]] = {
    MaxwellModel.name: MaxwellModel,
    DrivenMaxwellModel.name: DrivenMaxwellModel,
    RelativeVelocityModel.name: RelativeVelocityModel,
}
