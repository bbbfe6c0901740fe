"""The sticky gas on a ring, solved exactly with no events.

Model
-----
N unit-mass point particles on a ring of length L = N / n (n the number density) fly freely;
particles that meet stick (restitution r = 0): a cluster moves with the mean velocity of its
particles.  This is the inviscid Burgers limit and the late stage of the inelastic hard-rod gas
(Ben-Naim, Chen, Doolen, Redner 1999).  Time is t (the MD time, :mod:`particles.md`).

The exact solution on the line
------------------------------
E, Rykov and Sinai (1996); Brenier and Grenier (1998).  With labels in order and the free-streamed
positions g_j(t) = x_j + v_j t, the clusters at time t are the segments of the convex minorant of
the points (i, F_i), F_i = Σ_{j<i} g_j; a segment [i_a, i_b) is one cluster, its slope (the mean
of g over it) is the cluster's position and the mean of v over it its velocity.  The slopes of a
convex minorant of partial sums are the *isotonic regression* of g (least-squares nondecreasing
fit, pool-adjacent-violators algorithm), so this module calls
``scipy.optimize.isotonic_regression`` (PAVA, O(N), compiled in SciPy): block means of g are
computed directly, never as differences of the quadratically growing F_i, so the round-off of a
position is that of an average of numbers of size L (about 1e-16 L), not of F ~ N L.  A constant
is subtracted from g (it adds a linear term to F and changes nothing).

The ring, exactly
-----------------
Unroll the ring: particle j + kN (k ∈ ℤ) sits at x_j + kL with velocity v_j.  The periodic
infinite system is the ring's dynamics, and its partial sums satisfy F_{i+N} = F_i + C + L i, so
its convex minorant over ℤ is periodic the same way, and every minorant segment has fewer than
N + 1 steps (a segment holding steps j and j + N would have both slopes g and g + L).  Hence every
window of N + 1 consecutive points contains a vertex of the minorant over ℤ (a *cut*: no cluster
crosses it).

Lemma: if p < q are vertices of the minorant over ℤ and W ⊇ [p, q] is a finite window, then the
minorant of the points in W equals the minorant over ℤ on [p, q].  (The global minorant is convex
and below F on W, so it is below the window's; the window's, continued by the global minorant
outside [p, q], is convex because at p and q its one-sided slopes bound the global ones, and it
is below F, so it is below the global one.)

Take the window of two periods, points 0 … 2N (labels 0 … N − 1, then the same labels with
positions + L).  Let p* ≤ N be the first vertex over ℤ in it and q* ≥ N the last; by the lemma the
window's vertices in [p*, q*] are exactly the vertices over ℤ.  So the first vertex p ≥ N of the
window's minorant is a cut over ℤ, so is p − N ≥ p*, and the window's segments in [p − N, p) are
the clusters of the ring, with no assumption on their size (one cluster may hold all N
particles: then p − N and p are its ends).  The second period is the first shifted by L, and
both are monotone after their own regression, so the regression of the window is that of one
period except for one block pooled across the junction (:func:`pool_junction`); one period is
itself regressed in chunks joined the same way (:func:`period_regression`).  Cost: one PAVA of
N numbers per time, with scratch memory of about 32 bytes per cluster.  Tested against an
event-driven sticky simulation of the ring, with clusters across the seam, and against one PAVA
of the 2N numbers of the window (``tests/test_particles/test_sticky.py``).

Energy decay
------------
For independent velocities of variance 1 and density n, at t ≫ 1/n the free-streamed partial
sums are F(m) ≈ m²/(2n) + t W(m) (W a Brownian motion in the label m; the position fluctuations
are smaller by a factor t). With m = (nt)^{2/3} s, a particle's velocity is (nt)^{−1/3} U, U the
mean increment of a two-sided Brownian motion B over the segment covering s = 0 of the convex
minorant of B(s) + s²/2, so E t^{2/3} → n^{−2/3} ⟨U²⟩ for any law of variance 1 (the white-noise
Burgers problem; Frachebourg, Martin, Piasecki). ⟨U²⟩ = 0.44275 is the second moment of the
exact late-time velocity law (:mod:`particles.sticky_exact`, :func:`exact_moments`
``["velocity_variance"]``); comparison 9 of :mod:`maxwell_kinetics.app.comparisons` shows E t^{2/3}
approaching it. Exact as well: the *displacements* of the particles. A particle's position at t
is the slope of the minorant, so D/t^{2/3} tends in law to a multiple of Chernoff's argmax of
W(u) − u² (:func:`displacements`, :func:`displacement_scale`, :func:`chernoff_density`), with
⟨D²⟩ t^{−4/3} → 0.664129 at unit variance and density; ⟨U²⟩ = ⟨D²⟩ t^{−4/3} − ⟨(c − x₀)²⟩
t^{−4/3}, c the centre of the initial positions of the particle's cluster (the cross term sums
to zero over each cluster).

Conventions
-----------
The clusters of a state are listed in label order by their first labels ``starts`` (increasing);
the last cluster wraps across the seam when ``starts[0] > 0`` (it holds labels
``starts[-1] … N − 1`` and ``0 … starts[0] − 1``).  Positions are *unwrapped*: a cluster's
position is the mean of x_j + v_j t over its particles, where the labels j < starts[0] (those of
the wrapping cluster past the seam) count with x_j + L, so that
``positions[0] ≤ positions[1] ≤ … ≤ positions[-1] ≤ positions[0] + L``.  Every particle carries its
cluster's velocity (``state.velocities``), so the energy ⟨v²⟩, histograms and S(k) of
:mod:`particles.observables` and the driver apply unchanged.  ``collisions`` counts merges:
N − (number of clusters).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from .driver import EngineBase, initial_velocities
from .initial import get_law
from .sticky_exact import (
    CHERNOFF_VARIANCE,
    chernoff_density,
    displacement_scale,
    exact_asymptotes,
    exact_eulerian_velocity_density,
    exact_mass_density,
    exact_moments,
    exact_shock_density,
    exact_velocity_density,
    exact_velocity_survival,
    exact_velocity_tail_exponent,
)
from .validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_positive,
    check_real,
    check_real_array,
)

__all__ = [
    "StickyParams",
    "StickyState",
    "StickyGas",
    "sticky_state",
    "clusters",
    "cluster_mass_distribution",
    "profile_x",
    "profile_i",
    "total_momentum",
    "displacements",
    "chernoff_density",
    "displacement_scale",
    "CHERNOFF_VARIANCE",
    "velocity_tail_exponent",
    "check_state",
    "exact_shock_density",
    "exact_mass_density",
    "exact_velocity_density",
    "exact_eulerian_velocity_density",
    "exact_velocity_survival",
    "exact_velocity_tail_exponent",
    "exact_asymptotes",
    "exact_moments",
    "EXACT_W_EDGES",
    "ExactLawComparison",
    "exact_law_runs",
]


@dataclass(frozen=True)
class StickyParams:
    """Parameters of the sticky gas, checked at construction: ``n`` particles (N ≥ 2) of unit
    mass, number ``density`` N/L > 0, and the name of the ``initial`` velocity law
    (:mod:`particles.initial`).

    Attributes
    ----------
    n : int
        N ≥ 2.
    density : float
        n = N/L > 0.
    initial : str
        The initial law, a name of :mod:`particles.initial` with a sampler.

    Raises
    ------
    InvalidArgumentError
        Naming the parameter that is out of its domain (also a density so small that L = N/n
        overflows).
    """

    n: int
    density: float
    initial: str = "gaussian"

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        object.__setattr__(self, "density", check_positive(self.density, "density"))
        if not math.isfinite(self.length):  # n/density overflows: density underflows
            raise InvalidArgumentError(
                "density", self.density,
                f"a density whose ring length n/density is finite (n = {self.n})",
            )
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", self.initial, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)

    @property
    def length(self) -> float:
        """Ring length L = N / n (computed as in :class:`particles.md.MDParams`)."""
        return self.n / self.density

    def to_dict(self) -> dict:
        """The parameters, JSON-able.

        Returns
        -------
        dict
        """
        return asdict(self)


@dataclass(frozen=True, eq=False)
class StickyState:
    """The sticky gas at ``time`` t.

    ``initial_positions`` (sorted, in [0, L)) and ``initial_velocities`` are the data at t = 0
    (the state at any time is computed from them, exactly); ``starts``, ``positions`` and
    ``cluster_velocities`` describe the clusters at ``time`` (module docstring); ``velocities[j]``
    is the velocity of particle j (its cluster's); ``collisions`` = N − number of clusters.

    Attributes
    ----------
    time : float
        t.
    length : float
        L.
    initial_positions, initial_velocities : numpy.ndarray
        The data at t = 0.
    starts, positions, cluster_velocities : numpy.ndarray
        The clusters at ``time``: first labels, positions (unwrapped), velocities.
    velocities : numpy.ndarray
        Each particle's velocity (its cluster's).
    collisions : int
        N − number of clusters.
    """

    time: float
    length: float
    initial_positions: np.ndarray
    initial_velocities: np.ndarray
    starts: np.ndarray
    positions: np.ndarray
    cluster_velocities: np.ndarray
    velocities: np.ndarray
    collisions: int

    @property
    def masses(self) -> np.ndarray:
        """Number of particles in each cluster (sums to N)."""
        n = self.velocities.size
        return np.diff(np.append(self.starts, self.starts[0] + n))

    def to_arrays(self) -> dict[str, np.ndarray]:
        """What a checkpoint stores: the time, the initial data and the current velocities (the
        clusters are recomputed from the initial data on reading, and checked against them).

        Returns
        -------
        dict of numpy.ndarray
        """
        return {
            "time": np.array(self.time, dtype=float),
            "length": np.array(self.length, dtype=float),
            "initial_positions": np.array(self.initial_positions, dtype=float),
            "initial_velocities": np.array(self.initial_velocities, dtype=float),
            "velocities": np.array(self.velocities, dtype=float),
            "collisions": np.array(self.collisions, dtype=np.int64),
        }


#: Particles per isotonic regression: one period is regressed in chunks of this size, and the
#: chunks are joined by pooling across each junction (:func:`period_regression`); it bounds the
#: regression's scratch memory (about 32 bytes a particle of a chunk).
CHUNK = 1 << 22


def sticky_state(x0, v0, length: float, t: float) -> StickyState:
    """The exact sticky-gas state at time ``t`` ≥ 0 from initial positions ``x0`` (sorted, in
    [0, ``length``)) and velocities ``v0`` (module docstring: the isotonic regression of two
    unrolled periods, computed as one period's and the pooling across the junction).  At
    t = 0 every particle is its own cluster.  The inputs are checked (a few passes over
    the arrays, small beside the regression).

    Parameters
    ----------
    x0 : numpy.ndarray
        Initial positions, sorted, in [0, ``length``).
    v0 : numpy.ndarray
        Initial velocities.
    length : float
        L.
    t : float
        The time, ≥ 0.

    Returns
    -------
    StickyState

    Raises
    ------
    InvalidArgumentError
        Naming ``x0`` or ``v0`` (not one-dimensional finite reals of one non-zero length, or
        positions not sorted in [0, ``length``)), ``length`` (not a finite number > 0) or ``t``
        (not a finite number >= 0).
    """
    x0 = check_real_array(x0, "x0", ndim=1, min_size=1)
    v0 = check_real_array(v0, "v0", ndim=1)
    length = check_positive(length, "length")
    t = check_nonnegative(t, "t")
    if v0.size != x0.size:
        raise InvalidArgumentError("v0", f"{v0.size} values", f"one per position ({x0.size})")
    if x0[0] < 0.0 or not x0[-1] < length or np.any(np.diff(x0) < 0):
        raise InvalidArgumentError("x0", f"positions in [{x0.min():g}, {x0.max():g}]",
                                   f"positions sorted in [0, length = {length:g})")
    n = x0.size
    if t == 0.0:
        frozen = [a.view() for a in (x0, v0)]
        for a in frozen:
            a.flags.writeable = False  # shared with the initial data: read-only
        return StickyState(0.0, length, x0, v0, np.arange(n, dtype=np.int64), frozen[0],
                           frozen[1], frozen[1], 0)
    blocks, means, weights = period_regression(x0, v0, length, t)
    i, j, junction = pool_junction(means, weights, length)
    # Clusters in label order: the blocks j .. i − 1 of one period, then the junction block
    # (labels blocks[i] … N − 1 and, when j > 0, 0 … blocks[j] − 1: it wraps across the seam).
    starts = blocks[j: i + 1].copy()
    positions = np.empty(starts.size)
    np.add(means[j:i], length, out=positions[:-1])  # undo the constant
    positions[-1] = junction + length
    tail = int(blocks[j])  # labels < tail belong to the junction block (none when j = 0)
    del blocks, means, weights
    cvel = np.add.reduceat(v0, starts)
    if j > 0:  # the wrapping cluster: its tail past the seam, summed in label order after it
        cvel[-1] = np.add.reduce(np.concatenate([v0[starts[-1]:], v0[:tail]]))
    k = starts.size
    velocities = np.empty(n)
    # masses and per-particle velocities by groups of clusters, so that the scratch stays
    # about CHUNK particles (a state is computed while the previous one is still held)
    step = max(1, int(k * min(1.0, CHUNK / n)))
    for a in range(0, k, step):
        b = min(k, a + step)
        ends = starts[a + 1: b + 1] if b < k else np.append(starts[a + 1:], starts[0] + n)
        masses = ends - starts[a:b]
        cvel[a:b] /= masses
        if b == k:
            masses[-1] -= starts[0]  # the wrapping cluster's labels < starts[0] are set above
        velocities[starts[a]: starts[a] + int(masses.sum())] = np.repeat(cvel[a:b], masses)
    velocities[: starts[0]] = cvel[-1]
    return StickyState(
        t, length, x0, v0, starts, positions, cvel, velocities, int(n - starts.size),
    )


def period_regression(x0, v0, length, t):
    """``(blocks, means, weights)``: the isotonic regression of g_j = x_j + v_j t − L over one
    period, j = 0 … N − 1, as block starts (labels), block means of g and block sizes.

    Each chunk of :data:`CHUNK` labels is regressed by SciPy's PAVA; two monotone sequences
    regress to themselves except for one block pooled across their junction, so each chunk
    joins the blocks so far by pooling adjacent violators across it (a block of the result is
    a union of whole blocks of the chunks: a vertex of the convex minorant of the whole is one
    of every contiguous part containing it).  The result is kept on a stack of preallocated
    arrays, of which only the blocks found are ever written (the views returned keep them, and
    their resident memory is that of the blocks)."""
    from scipy.optimize import isotonic_regression  # ~1 s to import: on first use only

    n = x0.size
    starts = np.empty(n, dtype=np.int64)
    means = np.empty(n)
    weights = np.empty(n)
    top = 0
    for a in range(0, n, CHUNK):
        b = min(n, a + CHUNK)
        g = np.multiply(v0[a:b], t)
        g += x0[a:b]
        g -= length  # a constant: the values lie in [-L, 0) + v t
        fit = isotonic_regression(g)
        del g
        cb = fit.blocks[:-1]
        cm = fit.x[cb]
        cw = np.diff(fit.blocks).astype(float)
        del fit
        j = 0
        if top > 0 and means[top - 1] >= cm[0]:  # pool across the junction (PAVA pools ties)
            i = top - 1
            total = means[i] * weights[i] + cm[0] * cw[0]
            mass = weights[i] + cw[0]
            j = 1
            while True:
                m = total / mass
                if i > 0 and means[i - 1] >= m:
                    i -= 1
                    total += means[i] * weights[i]
                    mass += weights[i]
                elif j < cm.size and cm[j] <= m:
                    total += cm[j] * cw[j]
                    mass += cw[j]
                    j += 1
                else:
                    break
            means[i], weights[i] = m, mass  # starts[i] stays the pooled block's first label
            top = i + 1
        k = cm.size - j
        starts[top: top + k] = cb[j:] + a
        means[top: top + k] = cm[j:]
        weights[top: top + k] = cw[j:]
        top += k
    return starts[:top], means[:top], weights[:top]  # views: only written pages are resident


def pool_junction(means, weights, length):
    """The isotonic regression of two unrolled periods from that of one period.

    ``means`` (nondecreasing) and ``weights`` are one period's blocks; the second period's are
    the same with means + L.  Both halves are already monotone, so the regression of the two
    periods differs from them in one block only, pooled across the junction by adjacent
    violators.  Returns ``(i, j, m)``: that block is the first period's blocks i … end with the
    second period's blocks 0 … j − 1 (labels ``blocks[i]`` … N − 1 and 0 … ``blocks[j]`` − 1),
    of mean m; ``(last, 0, its mean)`` when the periods join without a violation (the junction
    is then a cut and every block is a cluster).  A block never takes a label twice (i ≥ j): at
    i = j it holds the whole ring.
    """
    b = means.size
    last = b - 1
    if not means[last] > means[0] + length:
        return last, 0, float(means[last])
    total = means[last] * weights[last] + (means[0] + length) * weights[0]
    mass = weights[last] + weights[0]
    i, j = last, 1
    while True:
        m = total / mass
        if i > j and means[i - 1] > m:
            i -= 1
            total += means[i] * weights[i]
            mass += weights[i]
        elif j < i and means[j] + length < m:
            total += (means[j] + length) * weights[j]
            mass += weights[j]
            j += 1
        else:
            return i, j, float(m)


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
    :func:`exact_mass_density`).

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
    mass flies freely).  At t ≫ 1/n it tends in law to :func:`displacement_scale` · t^{2/3} · Z,
    Z of Chernoff's law (:func:`chernoff_density`).

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


def check_state(state) -> None:
    """Refuse anything but a :class:`StickyState`.

    Parameters
    ----------
    state : object
        The value to check.

    Raises
    ------
    InvalidArgumentError
        Naming ``state`` when it is not a StickyState.
    """
    if not isinstance(state, StickyState):
        raise InvalidArgumentError("state", type(state).__name__, "a StickyState")


# ---------------------------------------------------------------------------------------------
# The engine


class StickyGas(EngineBase):
    """The exact sticky gas: an engine of :func:`particles.driver.simulate`.

    Driver protocol: ``name = "sticky"``, ``time_name = "t"``; ``initial_state(rng)`` draws
    exactly as :class:`particles.md.MDEngine` with rod length 0 (same seed, N, density and law:
    same positions and velocities); ``advance(state, until, rng)`` computes the state at
    ``until`` directly from the initial data (the rng is unused), so stopping points change
    nothing; ``next_stop`` is the grid ``stop_step · m`` (default ``stop_step=None``: no
    intermediate stops, each requested time is one O(N) computation); ``state_from_arrays``
    recomputes the state from the stored initial data and checks the stored velocities against
    it; ``observe`` records
    the number of ``clusters``, the ``mean_cluster_mass`` N/clusters and the
    ``total_momentum``.

    Built like every engine from its parameters by keyword, ``StickyGas(n=1000,
    density=1.0)``, or, as before, from a :class:`StickyParams`:
    ``StickyGas(StickyParams(1000, 1.0))`` (not both).

    Parameters
    ----------
    params : StickyParams or None, optional
        The gas (None: from the keywords ``n``, ``density``, ``initial``).
    stop_step : float, optional
        The driver's stop grid (units of t); None: no intermediate stops.
    n, density, initial : optional
        The fields of :class:`StickyParams`, when ``params`` is None (``n`` and ``density``
        required then; default law ``"gaussian"``).

    Raises
    ------
    InvalidArgumentError
        Naming ``params`` (not a StickyParams, or given together with the keywords),
        ``stop_step`` or the field of :class:`StickyParams` that is not of its domain.
    """

    name = "sticky"
    time_name = "t"
    state_keys = ("time", "length", "initial_positions", "initial_velocities", "velocities",
                  "collisions")

    def __init__(self, params: StickyParams | None = None, *, stop_step: float | None = None,
                 n: int | None = None, density: float | None = None,
                 initial: str | None = None):
        given = {k: v for k, v in (("n", n), ("density", density), ("initial", initial))
                 if v is not None}
        if params is None:
            params = StickyParams(n, density, "gaussian" if initial is None else initial)
        elif given:
            raise InvalidArgumentError(
                "params", params, f"a StickyParams or the keywords {sorted(given)}, not both"
            )
        if not isinstance(params, StickyParams):
            raise InvalidArgumentError("params", params, "a StickyParams")
        self.params = params
        self.stop_step = math.inf if stop_step is None else check_positive(stop_step, "stop_step")

    def to_dict(self) -> dict:
        """The engine's parameters, JSON-able (they name the run in its files).

        Returns
        -------
        dict
        """
        out = self.params.to_dict()
        out["model"] = self.name
        out["stop_step"] = self.stop_step if math.isfinite(self.stop_step) else None
        return out

    def initial_state(self, rng: np.random.Generator) -> StickyState:
        """Uniform sorted positions on [0, L), then velocities from the law with zero mean and
        ⟨v²⟩ = 1 (:func:`particles.driver.initial_velocities`): the draws of MD.

        Parameters
        ----------
        rng : numpy.random.Generator
            The run's generator.

        Returns
        -------
        StickyState
            The state at t = 0.

        Raises
        ------
        InvalidArgumentError
            Naming ``rng`` when it is not a ``numpy.random.Generator``.
        """
        if not isinstance(rng, np.random.Generator):
            raise InvalidArgumentError("rng", rng, "a numpy.random.Generator")
        p = self.params
        x = np.sort(rng.uniform(0.0, p.length, p.n))
        v = initial_velocities(p.initial, p.n, rng)
        return sticky_state(x, v, p.length, 0.0)

    def advance(self, state: StickyState, until: float, rng: np.random.Generator | None = None):
        """The exact state at ``until`` ≥ ``state.time`` (computed from the initial data).

        Parameters
        ----------
        state : StickyState
            The state (only its initial data are used).
        until : float
            t ≥ ``state.time``.
        rng : numpy.random.Generator, optional
            Unused.

        Returns
        -------
        StickyState

        Raises
        ------
        InvalidArgumentError
            Naming ``state`` or ``until`` when they do not fit.
        """
        check_state(state)
        until = check_nonnegative(until, "until")
        if until < state.time:
            raise InvalidArgumentError("until", until, f"a time >= the state's time {state.time}")
        if state.velocities.size != self.params.n:
            raise InvalidArgumentError("state", f"N={state.velocities.size}", f"N={self.params.n}")
        return sticky_state(state.initial_positions, state.initial_velocities, self.params.length,
                            until)

    def rebuild_state(self, arrays) -> StickyState:
        """Rebuild a state from :meth:`StickyState.to_arrays` (its keys present: checked by
        :meth:`state_from_arrays`, of :class:`particles.driver.EngineBase`); the state is
        recomputed from the stored initial data and checked against the stored velocities.

        Parameters
        ----------
        arrays : dict of numpy.ndarray
            :meth:`StickyState.to_arrays` of a state.

        Returns
        -------
        StickyState

        Raises
        ------
        InvalidArgumentError
            Naming ``checkpoint`` for an inconsistent state.
        """
        try:
            t = float(np.asarray(arrays["time"]))
            length = float(np.asarray(arrays["length"]))
            x0 = np.array(arrays["initial_positions"], dtype=float)
            v0 = np.array(arrays["initial_velocities"], dtype=float)
            v = np.array(arrays["velocities"], dtype=float)
            count = int(np.asarray(arrays["collisions"]))
        except (TypeError, ValueError) as exc:
            raise InvalidArgumentError("checkpoint", str(exc), "a sticky-gas state") from None
        n = self.params.n
        if x0.shape != (n,) or v0.shape != (n,) or v.shape != (n,):
            shapes = (x0.shape, v0.shape, v.shape)
            raise InvalidArgumentError("checkpoint", f"shapes {shapes}", f"arrays of length {n}")
        ok = (math.isfinite(t) and t >= 0.0 and length == self.params.length
              and np.all(np.isfinite(x0)) and np.all(np.isfinite(v0))
              and np.all(np.diff(x0) >= 0.0) and x0[0] >= 0.0 and x0[-1] < length)
        if not ok:
            raise InvalidArgumentError(
                "checkpoint", "bad time, length or initial data", "a sticky-gas state"
            )
        state = sticky_state(x0, v0, length, t)
        if state.collisions != count or not np.array_equal(state.velocities, v):
            raise InvalidArgumentError(
                "checkpoint", "velocities or collisions differ from the exact state",
                "a sticky-gas state"
            )
        return state

    def memory_per_particle(self) -> float:
        """Working bytes per particle: 96 (69 measured at N = 3·10⁷ with 20 output times,
        rounded up).

        Returns
        -------
        float
            96 bytes.
        """
        return 96.0

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Hull steps: N log₂N per requested time (each time is one computation from the
        initial data).

        Parameters
        ----------
        t_max : float
            The last requested t (unused).
        n_times : int
            The number of requested times.

        Returns
        -------
        tuple of (float, str)
            ``(N max(1, log₂N) n_times, "hull steps")``.
        """
        n = float(self.params.n)
        return n * max(1.0, math.log2(max(n, 2.0))) * n_times, "hull steps"

    def observe(self, state: StickyState) -> dict[str, float]:
        """The engine's scalars at this state, recorded per time by the driver.

        Parameters
        ----------
        state : StickyState
            The state.

        Returns
        -------
        dict
            ``clusters``, ``mean_cluster_mass`` and ``total_momentum``.
        """
        k = state.starts.size
        return {
            "clusters": float(k),
            "mean_cluster_mass": state.velocities.size / k,
            "total_momentum": total_momentum(state),
        }


# ---------------------------------------------------------------------------------------------
# The engine against the exact laws

#: The scaled-velocity bins of :class:`ExactLawComparison`: 24 bins of width 0.25 on w ∈ [−3, 3]
#: (the two open bins beyond ±3 are added to the outermost ones).
EXACT_W_EDGES = np.linspace(-3.0, 3.0, 25)

_EXACT_CACHE: dict = {}  # exact bin integrals and survivals on fixed grids, computed once


def _bin_integrals(density, edges, nodes: int = 12) -> np.ndarray:
    """∫ ``density`` over each [edges[i], edges[i + 1]] by Gauss–Legendre with ``nodes`` nodes."""
    from scipy.special import roots_legendre

    edges = np.asarray(edges, dtype=float)
    x, weight = roots_legendre(int(nodes))
    lo, hi = edges[:-1, None], edges[1:, None]
    pts = 0.5 * (hi - lo) * (x[None, :] + 1.0) + lo
    return (density(pts) * weight[None, :]).sum(axis=1) * 0.5 * (hi - lo)[:, 0]


def _cached(key, compute):
    if key not in _EXACT_CACHE:
        _EXACT_CACHE[key] = compute()
    return _EXACT_CACHE[key]


def _two_sided_survival(w) -> np.ndarray:
    """2 :func:`exact_velocity_survival` at the positive ``w``, each value computed once."""
    w = np.atleast_1d(np.asarray(w, dtype=float))
    new = [x for x in np.unique(w).tolist() if ("S", x) not in _EXACT_CACHE]
    if new:
        for x, value in zip(new, 2.0 * exact_velocity_survival(np.array(new)), strict=True):
            _EXACT_CACHE[("S", x)] = float(value)
    return np.array([_EXACT_CACHE[("S", x)] for x in w.tolist()])


def _merge_outer(clusters_per_bin, minimum: float) -> np.ndarray:
    """Start indices of groups of adjacent bins: the outer bins are merged inwards (from each
    end) until each end group holds at least ``minimum`` clusters."""
    k = clusters_per_bin.size
    lo, acc = 0, 0.0
    while lo < k // 2 and acc + clusters_per_bin[lo] < minimum:
        acc += clusters_per_bin[lo]
        lo += 1
    hi, acc = k, 0.0
    while hi > k // 2 and acc + clusters_per_bin[hi - 1] < minimum:
        acc += clusters_per_bin[hi - 1]
        hi -= 1
    return np.concatenate([[0], np.arange(lo + 1, min(hi, k))]) if hi > lo + 1 else np.array([0])


class ExactLawComparison:
    """Sticky-gas states at one time t, pooled over runs (:meth:`add`), against the exact
    late-time laws: the mass-weighted velocity histogram in w = v (n t/T₀)^{1/3}
    (:meth:`velocity`), the cluster-mass histogram in μ = m/(n² T₀ t²)^{1/3} (:meth:`mass`) and
    the two-sided survival P(|w| > w_k) with its local exponent β on the grid ``tail_w``
    (:meth:`tail`).  ``variance`` is T₀, the variance of the initial velocities (the engine
    draws 1); the density n is read from each state (N/L).  Only histograms are kept, so states
    of any size can be added one at a time.

    Variance models (χ² = Σ (observed − expected)²/variance over the bins):

    * velocity: a cluster's particles share one velocity, so a bin's particle count is a sum of
      cluster masses; clusters are taken as independent, and the variance of the count is
      Σ m² over the clusters in the bin.  Bins of width 0.25 on [−3, 3], the open bins beyond
      added to the outermost ones, and the outer bins merged inwards until each end holds at
      least ``min_clusters`` clusters.  Expected: N ∫ P(w) dw over the bin
      (:func:`exact_velocity_density`, Gauss–Legendre with 8 nodes; beyond ±3
      :func:`exact_velocity_survival`).  dof = number of bins (nothing is fitted).
    * mass: integer masses grouped in bins [m_a, m_b] (half-integer edges, about 12 per decade
      from m = 1 to 8 M, M = (n² T₀ t²)^{1/3}; masses beyond go to the last bin), cluster counts
      taken as independent Poisson numbers (variance = expected count, checked against the
      scatter of independent runs in the comparison's tests); expected N/M ∫ F(μ) dμ over
      [m_a − ½, m_b + ½]/M (:func:`exact_mass_density`, 8 nodes); bins with fewer than
      ``min_clusters`` expected clusters are merged with their neighbours.  dof = bins.
    * tail: S_k = (mass of the clusters with |w| > w_k)/N, variance Σ m²/N² over those
      clusters; the chord exponent between neighbours β_k = Δ ln(−ln S)/Δ ln w, its error by the
      delta method with the clusters above w_{k+1} and those between w_k and w_{k+1} as two
      independent sums; only grid points with at least ``min_clusters`` clusters beyond count
      as resolved.  The exact β_k is the same chord on 2 :func:`exact_velocity_survival`.

    The finite-t corrections to scaling are the only systematic difference (finite N enters
    through the ring's length only), so χ²/dof → 1 as t grows at fixed N per bin.

    Parameters
    ----------
    t : float
        The time of the states, > 0.
    variance : float
        T₀.
    w_edges : array_like
        The velocity histogram's edges in w.
    tail_w : array_like, optional
        The tail grid (default 10 geometric points from 0.5 to 4).
    min_clusters : int
        Clusters needed per outer bin and beyond a resolved tail point.

    Raises
    ------
    InvalidArgumentError
        Naming the argument that is out of its domain.
    """

    def __init__(self, t: float, *, variance: float = 1.0, w_edges=EXACT_W_EDGES,
                 tail_w=None, min_clusters: int = 25):
        self.t = check_positive(t, "t")
        self.variance = check_positive(variance, "variance")
        self.w_edges = np.asarray(w_edges, dtype=float)
        if self.w_edges.ndim != 1 or self.w_edges.size < 2 or np.any(np.diff(self.w_edges) <= 0):
            raise InvalidArgumentError("w_edges", w_edges, "increasing bin edges")
        grid = np.geomspace(0.5, 4.0, 10) if tail_w is None else np.asarray(tail_w, float)
        if grid.ndim != 1 or grid.size < 2 or grid[0] <= 0 or np.any(np.diff(grid) <= 0):
            raise InvalidArgumentError("tail_w", tail_w, "increasing positive velocities")
        self.tail_w = grid
        self.min_clusters = check_count(min_clusters, "min_clusters", 1)
        nb = self.w_edges.size + 1  # with the open bins below and above
        self.particles = 0
        self.runs = 0
        self.energy = []  # E (n t)^{2/3} T₀^{−2/3} per run
        self.cluster_count = []  # clusters × M / N per run
        self._v = np.zeros((3, nb))  # Σ m, Σ m², clusters per velocity bin
        self._m = np.zeros(0)  # clusters per integer mass
        self._s = np.zeros((3, grid.size + 1))  # the same per tail interval
        self._top = (np.zeros(0), np.zeros(0))  # the fastest clusters' |w| and masses
        self._scales = None

    def _scale(self, state):
        n = state.velocities.size / state.length
        wscale = (n * self.t / self.variance) ** (1.0 / 3.0)
        mscale = (n * n * self.variance * self.t * self.t) ** (1.0 / 3.0)
        if self._scales is None:
            self._scales = (n, wscale, mscale)
        elif not math.isclose(n, self._scales[0], rel_tol=1e-12):
            raise InvalidArgumentError("state", f"density {n}", f"density {self._scales[0]}")
        return wscale, mscale

    def add(self, state: StickyState) -> None:
        """Add one run's state at time t to the histograms.

        Parameters
        ----------
        state : StickyState
            A state at time t.

        Raises
        ------
        InvalidArgumentError
            Naming ``state`` when it is at another time or of another density.
        """
        check_state(state)
        if not math.isclose(state.time, self.t, rel_tol=1e-12):
            raise InvalidArgumentError("state", f"time {state.time}", f"time {self.t}")
        wscale, mscale = self._scale(state)
        m = state.masses
        mf = m.astype(float)
        w = state.cluster_velocities * wscale
        n = int(m.sum())
        idx = np.searchsorted(self.w_edges, w, side="right")  # 0: below, size: above
        for row, weight in enumerate((mf, mf * mf, None)):
            self._v[row] += np.bincount(idx, weights=weight, minlength=self._v.shape[1])
        counts = np.bincount(m)
        if counts.size > self._m.size:
            self._m = np.pad(self._m, (0, counts.size - self._m.size))
        self._m[:counts.size] += counts
        aw = np.abs(w)
        k = np.searchsorted(self.tail_w, aw, side="left")  # grid points below |w|
        for row, weight in enumerate((mf, mf * mf, None)):
            self._s[row] += np.bincount(k, weights=weight, minlength=self._s.shape[1])
        keep = 4 * self.min_clusters
        top_w = np.concatenate([self._top[0], aw])
        top_m = np.concatenate([self._top[1], mf])
        if top_w.size > keep:
            sel = np.argpartition(top_w, top_w.size - keep)[-keep:]
            top_w, top_m = top_w[sel], top_m[sel]
        self._top = (top_w, top_m)
        self.particles += n
        self.runs += 1
        self.energy.append(float(np.sum(mf * w * w)) / n)
        self.cluster_count.append(m.size * mscale / n)

    def _need(self):
        if self.runs == 0:
            raise InvalidArgumentError("states", 0, "at least one added state")

    def velocity(self) -> dict:
        """χ² of the velocity histogram (class docstring): ``chi2``, ``dof``, the bins
        ``edges`` (±inf at the open ends), ``observed``, ``expected``, ``sigma`` (particles per
        merged bin) and, on the unmerged bins of ``w_edges``, ``density`` (observed particles /
        (N × width)) and ``density_error``.

        Returns
        -------
        dict
        """
        self._need()
        e = self.w_edges
        inner = _cached(("velocity", tuple(e.tolist())),
                        lambda: _bin_integrals(exact_velocity_density, e, 8))
        below, above = 0.5 * _two_sided_survival(np.abs(e[[0, -1]]))
        below = 1.0 - below if e[0] > 0 else below
        above = 1.0 - above if e[-1] < 0 else above
        expected = self.particles * np.concatenate([[below], inner, [above]])
        counts, var, ncl = self._v
        groups = _merge_outer(ncl, self.min_clusters)
        obs, var_g, exp_g = (np.add.reduceat(a, groups) for a in (counts, var, expected))
        ok = var_g > 0
        chi2 = float(np.sum((obs[ok] - exp_g[ok]) ** 2 / var_g[ok]))
        full = np.concatenate([[-np.inf], e, [np.inf]])
        width = np.diff(e) * self.particles
        return {"t": self.t, "chi2": chi2, "dof": int(ok.sum()),
                "edges": np.append(full[groups], np.inf), "observed": obs, "expected": exp_g,
                "sigma": np.sqrt(var_g), "density": counts[1:-1] / width,
                "density_error": np.sqrt(var[1:-1]) / width}

    def mass(self) -> dict:
        """χ² of the cluster-mass histogram (class docstring): ``chi2``, ``dof``, the integer
        bins ``lo``, ``hi`` (inclusive; the last open), ``observed``, ``expected``, and
        ``mu`` (bin centres (lo + hi)/2M), ``density`` (observed F: clusters / (N/M × bin width
        in μ)), ``density_error`` (Poisson), ``exact`` (the expected F on the same bins).

        Returns
        -------
        dict
        """
        self._need()
        mscale = self._scales[2]
        upper = max(2, int(8.0 * mscale + 1e-9))
        per_decade = 12
        cuts = np.unique(np.round(np.geomspace(
            1, upper + 1, max(per_decade, int(per_decade * math.log10(upper + 1))) + 1)))
        edges = cuts - 0.5
        fine = self.particles / mscale * _bin_integrals(exact_mass_density, edges / mscale, 8)
        starts = [0]
        acc = 0.0
        for i, x in enumerate(fine):  # merge bins with fewer than min_clusters expected
            acc += x
            if acc >= self.min_clusters and i < fine.size - 1:
                starts.append(i + 1)
                acc = 0.0
        if acc < self.min_clusters and len(starts) > 1:
            starts.pop()  # the last group is short: merge it with the one before
        starts = np.array(starts)
        expected = np.add.reduceat(fine, starts)
        lo = cuts[starts].astype(int)
        hi = np.append(cuts[starts[1:]] - 1, upper).astype(int)
        per_mass = self._m
        csum = np.concatenate([[0.0], np.cumsum(per_mass)])
        top = min(per_mass.size, upper + 1)
        observed = (csum[np.minimum(hi + 1, top)] - csum[np.minimum(lo, top)])
        observed[-1] += csum[-1] - csum[top]  # masses beyond the last edge
        chi2 = float(np.sum((observed - expected) ** 2 / expected))
        width = (hi - lo + 1) / mscale
        norm = self.particles / mscale * width
        return {"t": self.t, "chi2": chi2, "dof": int(expected.size), "lo": lo, "hi": hi,
                "observed": observed, "expected": expected, "mu": 0.5 * (lo + hi) / mscale,
                "density": observed / norm, "density_error": np.sqrt(expected) / norm,
                "exact": expected / norm}

    def tail(self, exact: bool = True) -> dict:
        """The two-sided survival S(w) = P(|w| > w_k) on ``tail_w`` and its chord exponents
        (class docstring): ``w``, ``survival``, ``survival_error``, ``clusters_beyond``,
        ``resolved`` (bool per point), ``exact_survival`` (resolved points only, NaN
        elsewhere), ``beta`` / ``beta_error`` / ``beta_exact`` per chord between consecutive
        resolved points (at ``beta_w``, the geometric middles), and ``deepest``: the
        ``min_clusters``-th fastest cluster's |w|, the engine's S there (clusters at or beyond
        it) with its error, and the exact S.  ``exact=False`` leaves the exact values NaN (they
        cost ~0.16 s per point; each point is computed once per process).

        Parameters
        ----------
        exact : bool
            Compute the exact values too.

        Returns
        -------
        dict
        """
        self._need()
        grid = self.tail_w
        mass, mass2, ncl = (np.cumsum(row[::-1])[::-1][1:] for row in self._s)
        total = float(self.particles)
        s = mass / total
        ds = np.sqrt(mass2) / total
        resolved = ncl >= self.min_clusters
        res = np.flatnonzero(resolved)
        exact_s = np.full(grid.size, np.nan)
        if res.size and exact:
            exact_s[res] = _two_sided_survival(grid[res])
        k0, k1 = res[:-1], res[1:]
        dlw = np.log(grid[k1]) - np.log(grid[k0])
        with np.errstate(divide="ignore", invalid="ignore"):
            beta = (np.log(-np.log(s[k1])) - np.log(-np.log(s[k0]))) / dlw
            beta_exact = (np.log(-np.log(exact_s[k1])) - np.log(-np.log(exact_s[k0]))) / dlw
            g0 = 1.0 / (s[k0] * np.log(s[k0]))
            g1 = 1.0 / (s[k1] * np.log(s[k1]))
        var_b = mass2[k1] / total**2
        var_d = (mass2[k0] - mass2[k1]) / total**2
        beta_error = np.sqrt((g1 - g0) ** 2 * var_b + g0**2 * var_d) / dlw
        tw, tm = self._top
        order = np.argsort(tw)[::-1]
        j = min(self.min_clusters, order.size) - 1
        w_deep = float(tw[order[j]])
        m_deep = tm[order[: j + 1]]
        deep = {"w": w_deep, "clusters": j + 1, "survival": float(m_deep.sum()) / total,
                "survival_error": float(np.sqrt(np.sum(m_deep**2))) / total,
                "exact_survival": float(_two_sided_survival(w_deep)[0]) if exact else math.nan}
        return {"t": self.t, "w": grid, "survival": s, "survival_error": ds,
                "clusters_beyond": ncl, "resolved": resolved, "exact_survival": exact_s,
                "beta_w": np.sqrt(grid[k0] * grid[k1]), "beta": beta, "beta_error": beta_error,
                "beta_exact": beta_exact, "deepest": deep}

    def corrections(self) -> dict:
        """The scale-free corrections to scaling: E (n t)^{2/3} T₀^{−2/3} and the number of
        clusters × M/N, mean ± standard error over the runs, against their exact limits
        (:func:`exact_moments` ``velocity_variance`` and ``clusters``).

        Returns
        -------
        dict
            ``energy`` and ``clusters``: ``value`` (mean, standard error), ``exact`` and
            ``relative``.
        """
        self._need()
        mom = exact_moments()
        out = {}
        for key, values, limit in (("energy", self.energy, mom["velocity_variance"]),
                                   ("clusters", self.cluster_count, mom["clusters"])):
            x = np.asarray(values)
            se = float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else None
            out[key] = {"value": [float(x.mean()), se], "exact": limit,
                        "relative": float(x.mean() / limit - 1.0)}
        return out

    def sums(self) -> dict:
        """The pooled histograms this comparison has accumulated (copies): what
        :meth:`merge` adds.

        Returns
        -------
        dict
            ``scales`` (the density n and the scales of w and μ; None before the first
            state), ``velocity_bins``
            (Σ m, Σ m², clusters per velocity bin, 3 rows), ``tail_bins`` (the same per tail
            interval), ``masses`` (clusters per integer mass), ``fastest`` (|w| and masses
            of the fastest clusters kept for the deepest point), ``particles``, ``runs``,
            ``energy`` and ``cluster_count`` (per run).
        """
        return {"scales": self._scales, "velocity_bins": self._v.copy(),
                "tail_bins": self._s.copy(), "masses": self._m.copy(),
                "fastest": (self._top[0].copy(), self._top[1].copy()),
                "particles": self.particles, "runs": self.runs,
                "energy": list(self.energy), "cluster_count": list(self.cluster_count)}

    def merge(self, other: ExactLawComparison) -> None:
        """Add the runs of ``other`` (another comparison at the same time, on the same bins
        and grid, of a gas of the same density) to this one, as if they had been added here.

        Parameters
        ----------
        other : ExactLawComparison
            The comparison whose runs are added; it is not changed.

        Raises
        ------
        InvalidArgumentError
            Naming ``other`` when its time, variance, bins, grid, ``min_clusters`` or density
            differ from this one's.
        """
        theirs = other.sums() if isinstance(other, ExactLawComparison) else None
        same = (theirs is not None and other.t == self.t
                and other.variance == self.variance and other.min_clusters == self.min_clusters
                and np.array_equal(other.w_edges, self.w_edges)
                and np.array_equal(other.tail_w, self.tail_w)
                and (self._scales is None or theirs["scales"] is None
                     or math.isclose(theirs["scales"][0], self._scales[0], rel_tol=1e-12)))
        if not same:
            raise InvalidArgumentError("other", other, "a comparison at the same time, bins, "
                                       "grid, min_clusters and density")
        if theirs["runs"] == 0:
            return
        self._scales = self._scales or theirs["scales"]
        self._v += theirs["velocity_bins"]
        self._s += theirs["tail_bins"]
        masses = theirs["masses"]
        size = max(self._m.size, masses.size)
        self._m = np.pad(self._m, (0, size - self._m.size))
        self._m[:masses.size] += masses
        keep = 4 * self.min_clusters
        top_w = np.concatenate([self._top[0], theirs["fastest"][0]])
        top_m = np.concatenate([self._top[1], theirs["fastest"][1]])
        if top_w.size > keep:
            sel = np.argpartition(top_w, top_w.size - keep)[-keep:]
            top_w, top_m = top_w[sel], top_m[sel]
        self._top = (top_w, top_m)
        self.particles += theirs["particles"]
        self.runs += theirs["runs"]
        self.energy += theirs["energy"]
        self.cluster_count += theirs["cluster_count"]


def exact_law_runs(n: int, seeds, times, *, density: float = 1.0, tail_w=None,
                   min_clusters: int = 25) -> list[ExactLawComparison]:
    """Runs of the sticky gas (Gaussian initial velocities of unit variance) added to one
    :class:`ExactLawComparison` per time: the unit of work of a large ensemble, whose pieces
    are joined by :meth:`ExactLawComparison.merge`.

    Each seed is one gas of ``n`` particles drawn by :meth:`StickyGas.initial_state` from
    ``numpy.random.default_rng(seed)`` and advanced exactly to every time of ``times``.

    Parameters
    ----------
    n : int
        Particles per gas.
    seeds : iterable of int
        One gas per seed, in this order.
    times : sequence of float
        The times t (physical time) at which each gas is compared.
    density : float
        Number density N/L.
    tail_w, min_clusters
        As for :class:`ExactLawComparison`.

    Returns
    -------
    list of ExactLawComparison
        One per time, in the order of ``times``.
    """
    engine = StickyGas(StickyParams(n, density, "gaussian"))
    out = [ExactLawComparison(float(t), tail_w=tail_w, min_clusters=min_clusters) for t in times]
    for seed in seeds:
        s0 = engine.initial_state(np.random.default_rng(int(seed)))
        for cmp in out:
            cmp.add(engine.advance(s0, cmp.t))
        del s0
    return out
