"""Initial velocity laws shared by the kinetic solver and the particle models (NumPy only).

Every law has zero mean and unit variance.  A law carries

* its characteristic function ``phi(k) = E[exp(i k v)]`` (the sign convention of this project:
  ``P̂(k) = ∫ e^{ikv} P(v) dv``), evaluated by NumPy on any array of real ``k``.  The built-in
  laws write it against an array module ``xp`` (``characteristic(k, xp)``) so that the kinetic
  solver can also evaluate it inside JAX with ``xp = jax.numpy``;
* a sampler ``sample(rng, n)`` drawing ``n`` independent velocities from a
  ``numpy.random.Generator``;
* its standardised third moment ``skewness = E[v^3]`` (zero for symmetric laws), which fixes the
  imaginary part ``-skewness q^3 / 6`` of the rescaled characteristic function near ``q = 0``
  for all times (M3 / M2^{3/2} is conserved).

Laws, by command-line name:

``gaussian``    N(0, 1)
``uniform``     U(-√3, √3)
``laplace``     Laplace with scale 1/√2
``bimodal``     equal mixture of N(+0.9, 0.19) and N(-0.9, 0.19) (0.19 is the variance)
``asymmetric``  shifted exponential v = X - 1 with X ~ Exp(1): mean 0, variance 1, E[v^3] = 2

A user law is built by :func:`law_from_characteristic` from a characteristic function and its
variance; it is rescaled to unit variance.  Such a law has no sampler.

This module must not import JAX: ``particles`` imports it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .validation import InvalidArgumentError, check_positive

__all__ = [
    "InitialLaw", "LAWS", "PROBE_K_MAX", "get_law", "law_from_characteristic", "law_names",
    "first_non_finite",
]

CharacteristicFunction = Callable[..., np.ndarray]  # characteristic(k, xp) -> phi(k)
Sampler = Callable[[np.random.Generator, int], np.ndarray]


@dataclass(frozen=True)
class InitialLaw:
    """A zero-mean, unit-variance initial velocity law.

    A law is known by its characteristic function φ(k) = E[e^{ikv}] (the sign convention of this
    project), and, for the built-in laws, by a sampler and a cumulative distribution function.
    The built-in laws are in ``LAWS`` (:func:`get_law` by name); a user law comes from
    :func:`law_from_characteristic`.  The fields below are also its attributes.

    Parameters
    ----------
    name : str
        The law's name (``"gaussian"``, ... or the user's name).
    characteristic : callable
        ``characteristic(k, xp)``, φ at an array ``k`` of real wave numbers computed with the
        array module ``xp`` (``numpy``, or ``jax.numpy`` when ``traceable``).
    sampler : callable or None
        ``sampler(rng, n)`` draws ``n`` independent velocities with a ``numpy.random.Generator``;
        None for a user law.
    skewness : float
        The standardised third moment E[v³] (zero for a symmetric law), conserved by the
        dynamics; it fixes the imaginary part −skewness q³/6 of the rescaled characteristic
        function near q = 0.
    description : str
        The law in words, for listings.
    traceable : bool
        True when ``characteristic`` works with ``xp = jax.numpy`` (the built-in laws).
    distribution : callable or None
        The cumulative distribution function F(v) = P(V ≤ v) on a float array; None for a user
        law.
    """

    name: str
    characteristic: CharacteristicFunction = field(repr=False)
    sampler: Sampler | None = field(repr=False, default=None)
    skewness: float = 0.0
    description: str = ""
    #: True when ``characteristic(k, xp)`` works for ``xp = jax.numpy`` (built-in laws).
    traceable: bool = True
    #: The cumulative distribution function F(v) = P(V ≤ v) (None for user laws).
    distribution: Callable[[np.ndarray], np.ndarray] | None = field(repr=False, default=None)

    def cdf(self, v) -> np.ndarray:
        """The cumulative distribution function P(V ≤ v) (built-in laws).

        Parameters
        ----------
        v : array_like
            Velocities.

        Returns
        -------
        numpy.ndarray
            F(v), a float array of the shape of ``v``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``initial``, for a law without a known CDF (a user law).
        """
        if self.distribution is None:
            raise InvalidArgumentError("initial", self.name, "a law with a known CDF")
        return np.asarray(self.distribution(np.asarray(v, dtype=float)), dtype=float)

    def phi(self, k) -> np.ndarray:
        """The characteristic function φ(k) = E[e^{ikv}] evaluated with NumPy.

        Parameters
        ----------
        k : array_like
            Real wave numbers.

        Returns
        -------
        numpy.ndarray
            φ(k), a complex array of the shape of ``k``.
        """
        k = np.asarray(k, dtype=float)
        return np.asarray(self.characteristic(k, np), dtype=complex)

    def sample(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """Draw ``n`` independent velocities from the law.

        Parameters
        ----------
        rng : numpy.random.Generator
            The random generator.
        n : int
            The number of velocities.

        Returns
        -------
        numpy.ndarray
            Float array of shape ``(n,)``; its empirical mean and variance fluctuate around 0 and 1.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``initial``, for a law without a sampler (a user law).
        """
        if self.sampler is None:
            raise InvalidArgumentError(
                "initial", self.name, "a law with a sampler (user laws have none)"
            )
        return np.asarray(self.sampler(rng, int(n)), dtype=float)

    @property
    def symmetric(self) -> bool:
        """True when the characteristic function is real (checked, not assumed)."""
        k = np.linspace(0.01, 20.0, 257)
        return bool(np.max(np.abs(self.phi(k).imag)) < 1e-14)


_S3 = np.sqrt(3.0)
_B_LAPLACE = 1.0 / np.sqrt(2.0)
_MU_BIMODAL, _VAR_BIMODAL = 0.9, 0.19


def _uniform_phi(k, xp):
    # sin(√3 k)/(√3 k) written with sinc(x) = sin(πx)/(πx) so that k = 0 is exact.
    return xp.sinc(_S3 * k / np.pi)


def _ndtr(v):
    from scipy.special import ndtr

    return ndtr(v)


def _laplace_cdf(v):
    return np.where(v < 0, 0.5 * np.exp(np.minimum(v, 0.0) / _B_LAPLACE),
                    1.0 - 0.5 * np.exp(-np.maximum(v, 0.0) / _B_LAPLACE))


def _bimodal_cdf(v):
    sd = np.sqrt(_VAR_BIMODAL)
    return 0.5 * (_ndtr((v - _MU_BIMODAL) / sd) + _ndtr((v + _MU_BIMODAL) / sd))


def _bimodal_sample(rng, n):
    signs = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    return signs * _MU_BIMODAL + np.sqrt(_VAR_BIMODAL) * rng.standard_normal(n)


LAWS: dict[str, InitialLaw] = {
    law.name: law
    for law in (
        InitialLaw(
            "gaussian",
            lambda k, xp: xp.exp(-0.5 * k**2),
            lambda rng, n: rng.standard_normal(n),
            0.0,
            "N(0, 1)",
            distribution=_ndtr,
        ),
        InitialLaw(
            "uniform",
            _uniform_phi,
            lambda rng, n: rng.uniform(-_S3, _S3, n),
            0.0,
            "U(-sqrt(3), sqrt(3))",
            distribution=lambda v: np.clip((v + _S3) / (2.0 * _S3), 0.0, 1.0),
        ),
        InitialLaw(
            "laplace",
            lambda k, xp: 1.0 / (1.0 + (_B_LAPLACE * k) ** 2),
            lambda rng, n: rng.laplace(0.0, _B_LAPLACE, n),
            0.0,
            "Laplace, scale 1/sqrt(2)",
            distribution=_laplace_cdf,
        ),
        InitialLaw(
            "bimodal",
            lambda k, xp: xp.cos(_MU_BIMODAL * k) * xp.exp(-0.5 * _VAR_BIMODAL * k**2),
            _bimodal_sample,
            0.0,
            "equal mixture of N(+0.9, 0.19) and N(-0.9, 0.19)",
            distribution=_bimodal_cdf,
        ),
        InitialLaw(
            "asymmetric",
            lambda k, xp: xp.exp(-1j * k) / (1.0 - 1j * k),
            lambda rng, n: rng.exponential(1.0, n) - 1.0,
            2.0,
            "shifted exponential X - 1, X ~ Exp(1): E[v^3] = 2",
            distribution=lambda v: np.where(v < -1.0, 0.0, 1.0 - np.exp(-(np.maximum(v, -1.0)
                                                                          + 1.0))),
        ),
    )
}


def law_names() -> list[str]:
    """The names of the built-in laws, as the command line accepts them.

    Returns
    -------
    list of str
        The names in ``LAWS``, sorted.
    """
    return sorted(LAWS)


def get_law(name) -> InitialLaw:
    """Return the law registered under ``name``; an ``InitialLaw`` passes through.

    Parameters
    ----------
    name : str or particles.initial.InitialLaw
        ``gaussian``, ``uniform``, ``laplace``, ``bimodal`` or ``asymmetric`` (all with zero
        mean and unit variance).

    Returns
    -------
    particles.initial.InitialLaw
        With its characteristic function E[e^{ikv}], sampler and CDF.

    Raises
    ------
    particles.InvalidArgumentError
        For an unknown name.
    """
    if isinstance(name, InitialLaw):
        return name
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise InvalidArgumentError(
            "initial", name, "one of " + ", ".join(law_names())
        ) from None


#: Largest |k| at which :func:`law_from_characteristic` checks a user φ.  The solver evaluates φ
#: on its q grid, q ≤ q_max e^{cells h} ≈ 59 for the offered resolutions; a characteristic
#: function is bounded by 1 for every real k, so a non-finite value anywhere is an error.
PROBE_K_MAX = 1e6


def _probe_points() -> np.ndarray:
    """Increasing k ∈ [−1e6, 1e6]: dense and uniform on |k| ≤ 64 (step 1/32, beyond every q
    the solver's grids reach), log-spaced from 1e-8 to ``PROBE_K_MAX`` (20 points a decade)."""
    positive = np.unique(np.concatenate([
        np.linspace(0.0, 64.0, 2049), np.geomspace(1e-8, PROBE_K_MAX, 281)
    ]))
    return np.concatenate([-positive[:0:-1], positive])


def first_non_finite(k: np.ndarray, values: np.ndarray) -> tuple[float, complex] | None:
    """Find the non-finite value at the smallest |k|.

    Parameters
    ----------
    k : numpy.ndarray
        Real wave numbers.
    values : numpy.ndarray
        The values φ(k), of the shape of ``k``.

    Returns
    -------
    tuple of (float, complex) or None
        ``(k, value)`` at the k of smallest |k| (the positive one on a tie) where ``values`` is
        not finite, or None when all are finite.
    """
    values = np.asarray(values)
    bad = np.flatnonzero(~np.isfinite(values))
    if not bad.size:
        return None
    kb = np.asarray(k, dtype=float)[bad]
    j = bad[np.lexsort((-kb, np.abs(kb)))[0]]
    return float(np.asarray(k, dtype=float)[j]), complex(values[j])


#: Tolerances of the checks of a user characteristic function (see :func:`_check_characteristic`).
MODULUS_TOLERANCE = 1e-9
MOMENT_STEP = 1e-4
MOMENT_TOLERANCE = 1e-3


def _check_characteristic(phi, probe, k, variance, sigma) -> None:
    """A characteristic function of a zero-mean law of the declared variance: |φ| ≤ 1 on the
    probe points (to ``MODULUS_TOLERANCE``); zero mean, Im φ(h)/h → E[v] (h = ``MOMENT_STEP``);
    the declared variance, −φ''(0) ≈ 2(1 − Re φ(h))/h² = 1 after the rescaling.  Both moments are
    checked to ``MOMENT_TOLERANCE`` = 1e-3 in units of the standard deviation: the difference
    quotients converge at O(h) for a law with a |k|³ term (f̂ = (1+|k|)e^{−|k|}: 6.7e-5 at
    h = 1e-4) and carry a round-off of ~1e-16/h² = 1e-8.  The check that failed is named."""
    modulus = np.abs(probe)
    worst = int(np.argmax(modulus))
    if modulus[worst] > 1.0 + MODULUS_TOLERANCE:
        raise InvalidArgumentError(
            "characteristic", f"|phi({k[worst] / sigma:.6g})| = {modulus[worst]:.6g}",
            "|phi(k)| <= 1 for all real k (a characteristic function)",
        )
    h = MOMENT_STEP
    value = complex(np.ravel(phi(np.array([h])))[0])
    mean = value.imag / h
    if abs(mean) > MOMENT_TOLERANCE:
        raise InvalidArgumentError(
            "characteristic", f"mean {mean * sigma:.6g} (from Im phi(h)/h, h = {h * sigma:g})",
            "a law with zero mean",
        )
    second = 2.0 * (1.0 - value.real) / h**2
    if abs(second - 1.0) > MOMENT_TOLERANCE:
        raise InvalidArgumentError(
            "variance", variance,
            f"the variance of the law, -phi''(0) = {second * variance:.6g} (to a relative "
            f"{MOMENT_TOLERANCE:g})",
        )


def law_from_characteristic(
    characteristic: CharacteristicFunction, variance: float, name: str = "user"
) -> InitialLaw:
    """Wrap a user characteristic function of a zero-mean law with the given variance.

    The law is rescaled to unit variance: the returned law's characteristic function is
    ``characteristic(k / sqrt(variance))``.  Before it is accepted, the function is checked: it
    must be callable and finite, with φ(0) = 1, |φ| ≤ 1, zero mean (Im φ(h)/h at h = 10⁻⁴) and the
    declared variance (from 2(1 − Re φ(h))/h²), both moments to a relative 10⁻³.  The rescaled
    function is probed on |k| ≤ 64 (step 1/32, covering every q the solver's grids reach) and on
    log-spaced |k| up to ``PROBE_K_MAX`` = 10⁶; an error names the smallest offending k in the
    caller's units (k / sqrt(variance)).  The skewness is read from the imaginary part at
    k = 10⁻² (Im φ ≈ −E[v³] k³/6).

    Parameters
    ----------
    characteristic : callable
        ``characteristic(k)``: φ(k) = E[e^{ikv}] on a float array of real ``k``, returning an
        array of the same shape (or one that broadcasts to it).
    variance : float
        The variance of the law, > 0.
    name : str, optional
        The name of the law (default ``"user"``).

    Returns
    -------
    InitialLaw
        A unit-variance law with no sampler and no CDF, ``traceable`` False.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``characteristic`` if it is not callable, raises, returns a non-finite value,
        has φ(0) ≠ 1, |φ| > 1 or a non-zero mean; naming ``variance`` if it is not a finite
        number > 0 or differs from the variance of φ.
    """
    if not callable(characteristic):
        raise InvalidArgumentError("characteristic", characteristic, "a callable phi(k)")
    sigma = np.sqrt(check_positive(variance, "variance"))

    def phi(k, xp=np):
        return np.asarray(characteristic(np.asarray(k, dtype=float) / sigma), dtype=complex)

    k = _probe_points()  # in the solver's unit-variance units; phi(k) calls characteristic(k/σ)
    try:
        at_zero = complex(np.ravel(phi(np.zeros(1)))[0])
        probe = np.broadcast_to(phi(k), k.shape)
    except Exception as exc:  # a user function may fail in any way; report it as bad input
        raise InvalidArgumentError(
            "characteristic", characteristic, f"a callable phi(k) ({exc})"
        ) from exc
    bad = first_non_finite(k, probe)
    if bad is not None:  # reported at the user's own argument k / σ
        bad_k, value = bad
        raise InvalidArgumentError(
            "characteristic", f"phi({bad_k / sigma:.6g}) = {value}",
            "finite values phi(k) for all real k (checked up to |k| = "
            f"{PROBE_K_MAX / sigma:.3g})",
        )
    if not np.isfinite(at_zero) or abs(at_zero - 1.0) > 1e-12:
        raise InvalidArgumentError("characteristic", f"phi(0)={at_zero}", "phi(0) = 1")
    _check_characteristic(phi, probe, k, variance, sigma)
    kk = 1e-2
    skew = float(-6.0 * phi(np.array([kk])).imag[0] / kk**3)
    return InitialLaw(
        name, phi, None, skew, f"user characteristic function, variance {variance}", traceable=False
    )
