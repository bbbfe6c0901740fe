"""Tolerances with a stated coverage: the number of standard errors a check allows under the
law of its own z.

Every statistical check of the verdicts keeps the two-sided coverage of :data:`NOMINAL_SIGMAS`
(3) normal standard errors, 99.73 % (a one-sided bound: 99.865 %, the same quantile).  Its z
is normal when σ is known (a χ² null, binomial counts, a fit with known errors, many runs), a
Student's t with ν degrees of freedom when σ is the scatter of ν + 1 seeds (Welch–Satterthwaite
ν when both sides are measured), and the largest of k such values for a scan: :func:`t_sigmas`
is the quantile of that law at the nominal coverage.  Three seeds allow 19.2σ, four 9.22σ,
eight 4.53σ, sixteen 3.59σ.

Imports nothing from the rest of the package.
"""

from __future__ import annotations

import math

from particles.validation import InvalidArgumentError

__all__ = ["NOMINAL_SIGMAS", "t_sigmas", "student_sigmas"]

#: The normal standard errors whose two-sided coverage every statistical check keeps.
NOMINAL_SIGMAS = 3.0


def t_sigmas(dof: float | None, n_sigma: float = NOMINAL_SIGMAS, trials: int = 1) -> float:
    """The number of standard errors to allow for a z that is Student's t with ``dof`` degrees
    of freedom (normal when None), the largest |z| of ``trials`` independent values: its
    quantile at the two-sided coverage of ``n_sigma`` normal standard errors (for the maximum:
    each value at the Šidák coverage c^(1/trials)).

    Parameters
    ----------
    dof : float or None
        Degrees of freedom (> 0, not necessarily whole: Welch–Satterthwaite); None: infinite.
    n_sigma : float, optional
        The normal standard errors whose coverage is kept (default 3: 99.73 %).
    trials : int, optional
        The number of values the check's z is the largest |z| of (default 1).

    Returns
    -------
    float
        ``n_sigma`` itself for dof None and one trial; larger otherwise.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``dof`` (not None nor a finite number > 0), ``n_sigma`` (not a finite number
        > 0) or ``trials`` (not an integer ≥ 1).
    """
    from scipy import stats

    if dof is not None and (isinstance(dof, bool) or not _finite(dof) or dof <= 0):
        raise InvalidArgumentError("dof", dof, "None (infinite) or a finite number > 0")
    if isinstance(n_sigma, bool) or not _finite(n_sigma) or n_sigma <= 0:
        raise InvalidArgumentError("n_sigma", n_sigma, "a finite number > 0")
    if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
        raise InvalidArgumentError("trials", trials, "an integer >= 1")
    if dof is None and trials == 1:
        return float(n_sigma)
    # the two-sided tail of one value: 1 − (1 − tail)^(1/trials), without cancellation
    tail = float(2.0 * stats.norm.sf(n_sigma))
    if trials > 1:
        tail = -math.expm1(math.log1p(-tail) / trials)
    law = stats.norm if dof is None else stats.t(float(dof))
    return float(law.isf(tail / 2.0))


def student_sigmas(seeds: int, n_sigma: float = NOMINAL_SIGMAS) -> float:
    """The number of standard errors to allow for a mean over ``seeds`` runs whose standard
    error is estimated from those runs: :func:`t_sigmas` with ``seeds − 1`` degrees of
    freedom.  19.2 for 3 seeds, 9.22 for 4, 6.62 for 5; ``n_sigma`` for many seeds.

    Parameters
    ----------
    seeds : int
        The number of runs (at least 2).
    n_sigma : float, optional
        The normal standard errors whose coverage is kept (default 3).

    Returns
    -------
    float

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``seeds`` below 2 or ``n_sigma`` not positive.
    """
    if isinstance(seeds, bool) or not isinstance(seeds, int) or seeds < 2:
        raise InvalidArgumentError("seeds", seeds, "an integer >= 2")
    return t_sigmas(seeds - 1, n_sigma)


def _finite(x) -> bool:
    try:
        return math.isfinite(float(x))
    except (TypeError, ValueError):
        return False
