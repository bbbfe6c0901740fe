"""The deviation form of the rescaled equation, written against an array module ``xp`` (NumPy or
``jax.numpy``) and importing no JAX: the reference g(q) = e^{−q²/2}(1 − i m₃ q³/6), the source
S = g(pq) g((1−p)q) − g(q) + λ q g'(q) that the deviation w = G − g feels, and the solver's
time-integration settings.  Used by :mod:`maxwell_kinetics.solver` and by its compiled scheme
:mod:`maxwell_kinetics._kinetic_scheme` (which imports nothing from the solver)."""

from __future__ import annotations

import math

import numpy as np

from .model import MaxwellModel

__all__ = ["reference", "source", "source_parts"]


def reference(q, m3: float, xp=np):
    """The reference g(q) = e^{−q²/2} (1 − i m₃ q³/6) (real when m₃ = 0).

    Its imaginary part is not a phase e^{−i m₃q³/6}: that would oscillate ever faster in
    s = ln q (q³ radians per unit s) and could not be interpolated on the grid.

    Parameters
    ----------
    q : array_like
        Rescaled wave numbers q = k·v0(τ) (array of the module ``xp``).
    m3 : float
        Third moment ⟨x³⟩ of the rescaled velocity (constant in time for zero mean data).
    xp : module, default numpy
        Array module, ``numpy`` or ``jax.numpy``.

    Returns
    -------
    array
        g(q), real if ``m3 == 0`` and complex otherwise.
    """
    if xp is np:  # the public NumPy call; the compiled scheme passes traced jax arrays
        q, m3 = _checked(q, {"m3": m3})
    gauss = xp.exp(-0.5 * q * q)
    if m3 == 0.0:
        return gauss
    return gauss * (1.0 - 1j * (m3 / 6.0) * q**3)


def _checked(q, scalars: dict):
    """q as a float array and the named scalars as floats, checked (NumPy path only)."""
    from particles.validation import check_real, check_real_array

    return (check_real_array(q, "q"), *(check_real(v, k) for k, v in scalars.items()))


def _expm1_minus_x(x, xp):
    """e^x − 1 − x by its Taylor series (Horner, 15 terms; truncation < 1e-17 for x < 0.5)."""
    series = xp.zeros_like(x) + 1.0 / math.factorial(16)
    for n in range(15, 1, -1):
        series = series * x + 1.0 / math.factorial(n)
    return series * x * x


def source(q, lam: float, m3: float, xp=np):
    """S = g(pq) g((1−p)q) − g(q) + λ q g'(q) for the reference g = e^{−q²/2}(1 + i a q³).

    With a = −m₃/6, x = λq², p² + (1−p)² = 1 − 2λ, p³ + (1−p)³ = 1 − 3λ, p(1−p) = λ:

        Re S = e^{−q²/2} (e^x − 1 − x) − a² λ³ q⁶ e^{−(1−2λ)q²/2},
        Im S = a q³ e^{−q²/2} [(1 − 3λ)(e^x − 1 − x) − 3λ² q²].

    Both are O(q⁴) as q → 0 and are evaluated without cancellation (series for e^x − 1 − x);
    e^{−q²/2} e^x = e^{−(1−2λ)q²/2} never overflows.

    Parameters
    ----------
    q : array_like
        Rescaled wave numbers (array of the module ``xp``).
    lam : float
        λ = p(1 − p) = (1 − r²)/4 of the model.
    m3 : float
        Third rescaled moment; the reference is real when it is 0.
    xp : module, default numpy
        Array module, ``numpy`` or ``jax.numpy``.

    Returns
    -------
    array
        S(q), real if ``m3 == 0`` and complex otherwise.
    """
    if xp is np:
        q, lam, m3 = _checked(q, {"lam": lam, "m3": m3})
    re, im = source_parts(q, lam, m3, xp)
    return re if im is None else re + 1j * im


def source_parts(q, lam: float, m3: float, xp=np, gauss=None, gain=None):
    """Real and imaginary parts of :func:`source` (``im`` is None when m₃ = 0).

    ``gauss`` = e^{−q²/2} and ``gain`` = e^{−(1−2λ)q²/2} may be passed in when the caller has
    them (the solver's right-hand side does: exponentials dominate its cost).

    Parameters
    ----------
    q : array_like
        Rescaled wave numbers (array of the module ``xp``).
    lam : float
        λ = p(1 − p) of the model.
    m3 : float
        Third rescaled moment.
    xp : module, default numpy
        Array module, ``numpy`` or ``jax.numpy``.
    gauss, gain : array, optional
        Precomputed e^{−q²/2} and e^{−(1−2λ)q²/2} on ``q``; computed when None.

    Returns
    -------
    re : array
        Re S(q).
    im : array or None
        Im S(q), or None when ``m3 == 0``.
    """
    x = lam * q * q
    gauss = xp.exp(-0.5 * q * q) if gauss is None else gauss
    if gain is None:  # p² + (1 − p)² = 1 − 2λ
        gain = xp.exp(-0.5 * MaxwellModel.power_sum_of(lam, 2) * q * q)
    phi2 = xp.where(x < 0.5, gauss * _expm1_minus_x(x, xp), gain - gauss * (1.0 + x))
    if m3 == 0.0:
        return phi2, None
    a = -m3 / 6.0
    q3 = q * q * q
    re = phi2 - a * a * lam**3 * q3 * q3 * gain
    im = a * q3 * (MaxwellModel.power_sum_of(lam, 3) * phi2 - 3.0 * lam * lam * q * q * gauss)
    return re, im
