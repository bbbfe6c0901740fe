"""Observables of a sticky-gas state (:class:`particles.sticky.StickyState`): its clusters, the
profiles v(x) and v(i), the momentum, the displacements and the local exponent of the velocity
tail.

Energy decay
------------
For independent velocities of variance 1 and density n, at t ≫ 1/n the free-streamed partial
sums are F(m) ≈ m²/(2n) + t W(m) (W a Brownian motion in the label m; the position fluctuations
are smaller by a factor t). With m = (nt)^{2/3} s, a particle's velocity is (nt)^{−1/3} U, U the
mean increment of a two-sided Brownian motion B over the segment covering s = 0 of the convex
minorant of B(s) + s²/2, so E t^{2/3} → n^{−2/3} ⟨U²⟩ for any law of variance 1 (the white-noise
Burgers problem; Frachebourg, Martin, Piasecki). ⟨U²⟩ = 0.44275 is the second moment of the
exact late-time velocity law (:mod:`particles.sticky_exact`,
:func:`~particles.sticky_exact.exact_moments` ``["velocity_variance"]``); comparison 9 of
:mod:`maxwell_kinetics.app.comparisons` shows E t^{2/3}
approaching it. Exact as well: the *displacements* of the particles. A particle's position at t
is the slope of the minorant, so D/t^{2/3} tends in law to a multiple of Chernoff's argmax of
W(u) − u² (:func:`displacements`, :func:`~particles.sticky_exact.displacement_scale`,
:func:`~particles.sticky_exact.chernoff_density`), with
⟨D²⟩ t^{−4/3} → 0.664129 at unit variance and density; ⟨U²⟩ = ⟨D²⟩ t^{−4/3} − ⟨(c − x₀)²⟩
t^{−4/3}, c the centre of the initial positions of the particle's cluster (the cross term sums
to zero over each cluster).
"""

from __future__ import annotations

import math

import numpy as np

from .sticky import StickyState, check_state
from .validation import InvalidArgumentError, check_positive, check_real, check_real_array

__all__ = [
    "clusters",
    "cluster_mass_distribution",
    "profile_x",
    "profile_i",
    "total_momentum",
    "displacements",
    "velocity_tail_exponent",
]


# ---------------------------------------------------------------------------------------------
# Observables


def clusters(state: StickyState):
    """``(starts, masses, positions, velocities)`` of the clusters in label order: first labels,
    numbers of particles, positions reduced mod L into [0, L), velocities.

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    starts, masses, positions, velocities : numpy.ndarray
    """
    check_state(state)
    return (
        state.starts.copy(),
        state.masses,
        np.mod(state.positions, state.length),
        state.cluster_velocities.copy(),
    )


def cluster_mass_distribution(state: StickyState):
    """``(m, count)``: the cluster masses present, increasing, and how many clusters have each
    (``count.sum()`` is the number of clusters, ``(m * count).sum()`` = N).  Divide by
    ``state.length`` for clusters per unit length (their late-time law is
    :func:`~particles.sticky_exact.exact_mass_density`).

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    m, count : numpy.ndarray
    """
    check_state(state)
    m, count = np.unique(state.masses, return_counts=True)
    return m, count


def profile_x(state: StickyState):
    """The profile v(x, t): particle positions (each at its cluster's) reduced mod L into [0, L),
    sorted increasingly, and the particles' velocities (the MD convention of
    :func:`particles.md.profile_x`).

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    x, v : numpy.ndarray
        Sorted positions and the velocities.
    """
    check_state(state)
    y = np.mod(np.repeat(state.positions, state.masses), state.length)
    v = np.repeat(state.cluster_velocities, state.masses)
    order = np.argsort(y, kind="stable")
    return y[order], v[order]


def profile_i(state: StickyState):
    """The profile v(i, t) against particle label i (as :func:`particles.md.profile_i`).

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    i, v : numpy.ndarray
        Labels and velocities.
    """
    check_state(state)
    return np.arange(state.velocities.size), state.velocities.copy()


def total_momentum(state: StickyState) -> float:
    """Σ_j v_j (unit masses): conserved, zero at t = 0 up to round-off.

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    float
    """
    check_state(state)
    return float(np.sum(state.velocities))


def displacements(state: StickyState) -> np.ndarray:
    """Each particle's displacement since t = 0, unwrapped (not reduced mod L): its cluster's
    position minus its initial position, with the labels j < ``starts[0]`` of a cluster across
    the seam counted at x_j + L (module docstring).  Σ_j of it is t Σ_j v_j(0) (the centre of
    mass flies freely).  At t ≫ 1/n it tends in law to
    :func:`~particles.sticky_exact.displacement_scale` · t^{2/3} · Z, Z of Chernoff's law
    (:func:`~particles.sticky_exact.chernoff_density`).

    Parameters
    ----------
    state : StickyState
        The state.

    Returns
    -------
    numpy.ndarray
        One displacement per particle, in label order.
    """
    check_state(state)
    where = np.roll(np.repeat(state.positions, state.masses), state.starts[0])
    d = where - state.initial_positions
    d[: state.starts[0]] -= state.length
    return d



def velocity_tail_exponent(v, energy: float | None = None, *, quantiles=(1e-2, 1e-5)):
    """Local exponent of the velocity tail: the slope β of ln(−ln P(|v| > w)) against ln w
    between the upper ``quantiles`` of |v|/√E, with its standard error from the least-squares
    fit on those points.  P(|v| > w) ~ exp(−c w^β) gives β; the sticky gas predicts β = 3
    (Frachebourg 1999), a Gaussian 2.  Returns ``(beta, error, w_range)``.

    ``v`` are per-particle velocities (mass-weighted, as ``state.velocities``); ``energy``
    defaults to ⟨v²⟩.  The error is the fit's; points of one run are correlated (a cluster's
    particles share one velocity), so compare seeds for an honest spread.

    Parameters
    ----------
    v : array_like
        Per-particle velocities.
    energy : float, optional
        E (default ⟨v²⟩).
    quantiles : tuple of float
        The upper quantiles of |v|/√E between which the slope is fitted.

    Returns
    -------
    beta, error : float
        The slope and its least-squares standard error.
    w_range : tuple of float
        The fitted range of |v|/√E.

    Raises
    ------
    InvalidArgumentError
        Naming ``v`` (not finite reals, fewer than 10 velocities, all zero, or a tail of fewer
        than 3 distinct points: the fit and its error need three), ``energy`` (not a finite
        number > 0) or ``quantiles`` (not two real tail fractions 1 > q1 > q2 >= 1/N).
    """
    v = np.abs(check_real_array(v, "v").ravel())
    if v.size < 10:
        raise InvalidArgumentError("v", f"{v.size} values", "at least 10 velocities")
    if energy is None:
        with np.errstate(over="ignore"):
            e = float(np.mean(v * v))
        if not 0.0 < e < math.inf:
            raise InvalidArgumentError("v", f"energy {e}", "velocities of finite, non-zero "
                                       "energy (or pass energy)")
    else:
        e = check_positive(energy, "energy")
    try:
        hi, lo = (check_real(q, "quantiles") for q in quantiles)
    except (TypeError, ValueError):  # not two values (InvalidArgumentError is a ValueError)
        raise InvalidArgumentError("quantiles", quantiles, "two tail fractions 1 > q1 > q2 > 0"
                                   ) from None
    if not (0.0 < lo < hi < 1.0) or lo * v.size < 1.0:
        raise InvalidArgumentError(
            "quantiles", quantiles, f"upper tail fractions 1 > q1 > q2 >= 1/N = {1 / v.size:g}"
        )
    w = np.sort(v) / math.sqrt(e)
    frac = np.geomspace(hi, lo, 25)
    idx = np.clip(np.round((1.0 - frac) * v.size).astype(int), 0, v.size - 1)
    wq = w[idx]
    tail = np.array([np.count_nonzero(w > a) for a in wq]) / v.size
    keep = (tail > 0) & (wq > 0)
    xs, ys = np.log(wq[keep]), np.log(-np.log(tail[keep]))
    if np.unique(xs).size < 3:  # repeated points (ties in |v|) do not determine the error
        raise InvalidArgumentError("v", f"a tail with {np.unique(xs).size} distinct points",
                                   "a tail of at least 3 distinct points")
    a = np.vstack([xs, np.ones_like(xs)]).T
    coef, res, *_ = np.linalg.lstsq(a, ys, rcond=None)
    dof = xs.size - 2
    sigma2 = float(res[0]) / dof if res.size and dof > 0 else 0.0
    cov = sigma2 * np.linalg.inv(a.T @ a)
    return float(coef[0]), float(math.sqrt(cov[0, 0])), (float(wq[keep][0]), float(wq[keep][-1]))
