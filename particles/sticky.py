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
exact late-time velocity law below (:func:`exact_moments` ``["velocity_variance"]``); comparison
9 of :mod:`maxwell_kinetics.comparisons` shows E t^{2/3} approaching it. Exact as well: the
*displacements* of the particles. A particle's position at t is the slope of the minorant, so
D/t^{2/3} tends in law to a multiple of Chernoff's argmax of W(u) − u² (:func:`displacements`,
:func:`displacement_scale`, :func:`chernoff_density`), with ⟨D²⟩ t^{−4/3} → 0.664129 at unit
variance and density; ⟨U²⟩ = ⟨D²⟩ t^{−4/3} − ⟨(c − x₀)²⟩ t^{−4/3}, c the centre of the initial
positions of the particle's cluster (the cross term sums to zero over each cluster).

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

import functools
import math
from dataclasses import asdict, dataclass

import numpy as np

from .driver import initial_velocities, next_grid_point
from .initial import get_law
from .validation import InvalidArgumentError, check_count, check_nonnegative, check_positive

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
    t = 0 every particle is its own cluster.  Inputs are trusted (checked by the public
    callers).

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
    """
    x0 = np.asarray(x0, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    n = x0.size
    length = float(length)
    t = float(t)
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
    _check_state(state)
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
    _check_state(state)
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
    _check_state(state)
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
    _check_state(state)
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
    _check_state(state)
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
    _check_state(state)
    where = np.roll(np.repeat(state.positions, state.masses), state.starts[0])
    d = where - state.initial_positions
    d[: state.starts[0]] -= state.length
    return d


#: Var Z of Chernoff's law, Z = argmax_t (W(t) − t²) for a two-sided standard Brownian motion W
#: (Groeneboom and Wellner, J. Comput. Graph. Stat. 10, 388 (2001): 0.26355964); the quadrature
#: of :func:`chernoff_density` gives 0.2635596413
#: (``tests/test_particles/test_sticky_displacement.py``).
CHERNOFF_VARIANCE = 0.26355964


def chernoff_density(z, *, cutoff: float = 40.0, nodes: int = 800) -> np.ndarray:
    """Chernoff's density f(z) = g(z) g(−z) / 2 of Z = argmax_t (W(t) − t²) (Groeneboom,
    Probab. Th. Rel. Fields 81, 79 (1989)), where g has the Fourier transform
    ĝ(λ) = ∫ e^{iλz} g(z) dz = 2^{1/3} / Ai(i 2^{−1/3} λ).  ĝ(−λ) is the conjugate of ĝ(λ), so
    g(z) = (1/π) ∫_0^∞ Re[e^{−iλz} ĝ(λ)] dλ, computed by Gauss–Legendre quadrature with
    ``nodes`` nodes on [0, ``cutoff``]: |ĝ(λ)| falls like exp(−(√2/3) (2^{−1/3} λ)^{3/2}), below
    1e-23 at λ = 40, and the integrand's phase λ|z| needs |z| ≲ 10 for 800 nodes.  f is even,
    ∫ f = 1 and Var Z = :data:`CHERNOFF_VARIANCE` (both checked by the tests).

    Parameters
    ----------
    z : array_like of float
        Where to evaluate f.
    cutoff : float
        The upper end of the λ integral.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        f(z).
    """
    from scipy.special import airy

    z = np.asarray(z, dtype=float)
    x, w = _leggauss(int(nodes))
    lam = 0.5 * cutoff * (x + 1.0)
    w = 0.5 * cutoff * w
    ghat = 2.0 ** (1.0 / 3.0) / airy(1j * 2.0 ** (-1.0 / 3.0) * lam)[0]

    def g(values):
        phase = np.exp(-1j * np.multiply.outer(values, lam))
        return (phase * ghat).real @ w / math.pi

    flat = z.ravel()
    return (0.5 * g(flat) * g(-flat)).reshape(z.shape)


def displacement_scale(density: float = 1.0, variance: float = 1.0) -> float:
    """b with displacement / t^{2/3} → b Z in law (Z of :func:`chernoff_density`), for
    independent initial velocities of ``variance`` σ² and number ``density`` n, at t ≫ 1/n:
    b = 2^{2/3} σ^{2/3} n^{−1/3}, so ⟨D²⟩ t^{−4/3} → b² Var Z (= 0.664129 at σ = n = 1).

    Derivation (module docstring, "Energy decay", for the scaling m = a s, a = (σ n t)^{2/3}):
    a particle's position is the slope of the convex minorant of F, and its initial position
    that of m²/(2n), so D = σ^{2/3} n^{−1/3} t^{2/3} (X(s) − s), X(s) the slope at s of the
    convex minorant of W(s) + s²/2.  X(s) − s is stationary in s and, by the switching
    relation X(0) ≤ x ⇔ argmin_u (W(u) + u²/2 − x u) ≥ 0, distributed as
    argmax_u (W(u) − u²/2) = 2^{2/3} Z.

    Parameters
    ----------
    density : float
        n.
    variance : float
        σ², the variance of the initial velocities.

    Returns
    -------
    float
        b.
    """
    n = check_positive(density, "density")
    s2 = check_positive(variance, "variance")
    return 2.0 ** (2.0 / 3.0) * s2 ** (1.0 / 3.0) * n ** (-1.0 / 3.0)


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
        Naming ``v`` (fewer than 10 velocities, or a tail of fewer than 3 distinct points) or
        ``quantiles``.
    """
    v = np.abs(np.asarray(v, dtype=float).ravel())
    if v.size < 10:
        raise InvalidArgumentError("v", f"{v.size} values", "at least 10 velocities")
    e = float(np.mean(v * v)) if energy is None else check_positive(energy, "energy")
    hi, lo = (float(q) for q in quantiles)
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
    if xs.size < 3 or np.ptp(xs) == 0.0:
        raise InvalidArgumentError("v", "a tail with fewer than 3 distinct points", "a tail")
    a = np.vstack([xs, np.ones_like(xs)]).T
    coef, res, *_ = np.linalg.lstsq(a, ys, rcond=None)
    dof = xs.size - 2
    sigma2 = float(res[0]) / dof if res.size and dof > 0 else 0.0
    cov = sigma2 * np.linalg.inv(a.T @ a)
    return float(coef[0]), float(math.sqrt(cov[0, 0])), (float(wq[keep][0]), float(wq[keep][-1]))


def _check_state(state) -> None:
    if not isinstance(state, StickyState):
        raise InvalidArgumentError("state", type(state).__name__, "a StickyState")


# ---------------------------------------------------------------------------------------------
# The engine


class StickyGas:
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

    Parameters
    ----------
    params : StickyParams
        The gas.
    stop_step : float, optional
        The driver's stop grid (units of t); None: no intermediate stops.

    Raises
    ------
    InvalidArgumentError
        Naming ``params`` or ``stop_step`` when they are not of their domain.
    """

    name = "sticky"
    time_name = "t"

    def __init__(self, params: StickyParams, *, stop_step: float | None = None):
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

    def next_stop(self, time: float) -> float:
        """The next point of the stop grid after ``time`` (infinity without a grid).

        Parameters
        ----------
        time : float
            The current time t.

        Returns
        -------
        float
        """
        if not math.isfinite(self.stop_step):
            return math.inf
        return next_grid_point(time, self.stop_step)

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
        _check_state(state)
        until = check_nonnegative(until, "until")
        if until < state.time:
            raise InvalidArgumentError("until", until, f"a time >= the state's time {state.time}")
        if state.velocities.size != self.params.n:
            raise InvalidArgumentError("state", f"N={state.velocities.size}", f"N={self.params.n}")
        return sticky_state(state.initial_positions, state.initial_velocities, self.params.length,
                            until)

    def state_from_arrays(self, arrays) -> StickyState:
        """Rebuild a state from :meth:`StickyState.to_arrays`; an inconsistent one raises
        ``InvalidArgumentError`` naming ``checkpoint``.

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
        keys = ("time", "length", "initial_positions", "initial_velocities", "velocities",
                "collisions")
        try:
            missing = [k for k in keys if k not in arrays]
        except TypeError:
            raise InvalidArgumentError("checkpoint", type(arrays).__name__, "a mapping") from None
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "a sticky-gas state")
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
# Exact late-time laws (white-noise Burgers): velocity and cluster-mass distributions
#
# Everything below is a function of the scaled variables w = v (n t / T₀)^{1/3} and
# μ = m / (n² T₀ t²)^{1/3}, where n is the number density and T₀ = ⟨v²⟩ the initial variance of
# the velocities (the engine draws T₀ = 1).  The derivation is in :func:`exact_shock_density`.

_CUBE = 2.0 ** (-1.0 / 3.0)  # 2^{-1/3}: the Airy scale of the parabola s²/2
_N_ZEROS = 400  # zeros of Ai in the residue sums (enough for μ ≥ _K_SPLIT and τ ≤ _PSI_SPLIT)
_K_SPLIT = 0.5  # k(μ): residue sum for μ ≥ this, Hankel contour below
_PSI_SPLIT = -2.0  # ψ(τ): residue sum for τ ≤ this, saddle-point contour above
_PSI_TABLE = (-2.0, 26.0, 2.0, 28)  # ψ's interpolation table: [lo, hi], panel width, degree
_MU_MAX = 40.0  # F(μ) < 1e-1100 beyond: returned as 0
_W_MAX = 30.0  # P(w), P_E(w) < 1e-1900 beyond: returned as 0


@functools.lru_cache(maxsize=32)
def _leggauss(nodes: int):
    """Gauss–Legendre nodes and weights, cached: the exact laws ask for the same few rules many
    times.  From ``scipy.special.roots_legendre`` (Golub–Welsch below 150 nodes, asymptotic
    formulas above: 2 ms at 300 nodes where ``numpy.polynomial.legendre.leggauss`` takes ~1 s;
    the two agree to 1e-13 relative).  The arrays are shared: read-only."""
    from scipy.special import roots_legendre

    x, w = roots_legendre(int(nodes))
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def _check_finite_array(x, name: str) -> np.ndarray:
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, x, "finite real numbers") from None
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)].ravel()[0]
        raise InvalidArgumentError(name, float(bad), "finite real numbers")
    return arr


def _airy_zeros():
    """(a_k, Ai'(a_k)) for the first :data:`_N_ZEROS` zeros of Ai, cached."""
    cache = _airy_zeros.__dict__
    if "value" not in cache:
        from scipy.special import ai_zeros

        a, _, _, aip = ai_zeros(_N_ZEROS)
        cache["value"] = (a, aip)
    return cache["value"]


def _log_airy(z):
    """(log Ai(z), Ai'(z)/Ai(z)) for complex z (principal branches), from the exponentially
    scaled Airy functions, so that neither under- nor overflows for |z| up to ~1e10."""
    from scipy.special import airye

    z = np.asarray(z, dtype=complex)
    e_ai, e_aip, _, _ = airye(z)
    return np.log(e_ai) - (2.0 / 3.0) * z**1.5, e_aip / e_ai


def _saddle(c, p: int) -> np.ndarray:
    """The real saddle x₀ > a₁ of e^{−c z} / Ai(z)^p: the root of p Ai'(x)/Ai(x) = −c (the left
    side decreases from +∞ at a₁ to −∞), by Newton's method kept inside a shrinking bracket."""
    a1 = _airy_zeros()[0][0]
    c = np.asarray(c, dtype=float)
    lo = np.full(c.shape, a1)
    hi = (np.maximum(c, 0.0) / p) ** 2 + 2.0
    x = np.clip((c / p) ** 2 * (c > 0), a1 + 0.3, None)
    x = np.where(x < hi, x, 0.5 * (lo + hi))
    for _ in range(80):
        ratio = _log_airy(x)[1].real
        g = p * ratio + c
        lo = np.where(g > 0, x, lo)
        hi = np.where(g <= 0, x, hi)
        step = g / (p * (x - ratio * ratio))
        new = x - step
        inside = (new > lo) & (new < hi)
        new = np.where(inside, new, 0.5 * (lo + hi))
        done = np.abs(new - x) <= 1e-15 * np.maximum(1.0, np.abs(x))
        x = new
        if np.all(done):
            break
    return x


def _contour_log(tau, p: int, nodes: int = 72) -> np.ndarray:
    """log I_p(τ), I_p(τ) = (1/2πi) ∫ e^{−2^{−1/3} τ z} Ai(z)^{−p} dz upward on a path to the
    right of the zeros of Ai, for p = 1, 2 (I_p > 0 for real τ).

    The path leaves the real saddle x₀ (:func:`_saddle`) vertically and bends to the directions
    ±2π/3, where 1/Ai decays fastest: z = x₀ − (s/√3)(cosh u − 1) + i s sinh u, s the Gaussian
    width at the saddle.  The integrand is real-symmetric, so I_p = (1/π) Im ∫_0^∞ … du, done by
    the trapezoidal rule in u (double-exponential decay) with ``nodes`` steps up to |Im z| =
    max(14 s, 24).  The integrand is scaled by its value at the saddle, so there is no
    cancellation and the relative error is that of the rule (~1e-14, checked against the
    residue sums and at twice the nodes in the tests) for every τ."""
    tau = np.asarray(tau, dtype=float)
    c = _CUBE * tau
    x0 = _saddle(c, p)
    l0, r0 = _log_airy(x0)
    r0 = r0.real
    s = 1.0 / np.sqrt(p * (r0 * r0 - x0))
    e0 = -c * x0 - p * l0.real
    u_max = np.arcsinh(np.maximum(14.0 * s, 24.0) / s)
    t = np.linspace(0.0, 1.0, nodes + 1)
    u = u_max[..., None] * t
    h = u_max / nodes
    ss = s[..., None]
    z = x0[..., None] - (ss / math.sqrt(3.0)) * (np.cosh(u) - 1.0) + 1j * ss * np.sinh(u)
    dz = -(ss / math.sqrt(3.0)) * np.sinh(u) + 1j * ss * np.cosh(u)
    log_f = -c[..., None] * z - p * _log_airy(z)[0] - e0[..., None]
    terms = np.exp(log_f) * dz
    terms[..., 0] *= 0.5
    value = np.imag(terms.sum(axis=-1)) * h / math.pi
    return np.log(value) + e0


def _log_psi_direct(tau) -> np.ndarray:
    """log ψ(τ) without the table: the residue sum for τ ≤ −2, the contour above."""
    tau = np.asarray(tau, dtype=float)
    out = np.empty(tau.shape)
    low = tau <= _PSI_SPLIT
    if np.any(low):
        a, aip = _airy_zeros()
        terms = np.exp(np.multiply.outer(tau[low], -_CUBE * a)) / aip
        out[low] = math.log(2.0 ** (1.0 / 3.0)) + np.log(terms.sum(axis=-1))
    if np.any(~low):
        out[~low] = math.log(2.0 ** (1.0 / 3.0)) + _contour_log(tau[~low], 1)
    return out


def _psi_table():
    """Chebyshev coefficients of log ψ on the panels of :data:`_PSI_TABLE`, cached (built from
    :func:`_log_psi_direct` at the Chebyshev points: ~0.2 s on first use)."""
    cache = _psi_table.__dict__
    if "value" not in cache:
        lo, hi, width, deg = _PSI_TABLE
        panels = int(round((hi - lo) / width))
        k = np.arange(deg + 1)
        x = np.cos(np.pi * (k + 0.5) / (deg + 1))  # Chebyshev points of the first kind
        centres = lo + width * (np.arange(panels) + 0.5)
        values = _log_psi_direct(centres[:, None] + 0.5 * width * x[None, :])
        # coefficients by the discrete cosine transform on the points of the first kind
        basis = np.cos(np.outer(k, np.arccos(x)))  # T_j(x_i), shape (deg+1, deg+1)
        coef = values @ basis.T * (2.0 / (deg + 1))
        coef[:, 0] *= 0.5
        cache["value"] = coef
    return cache["value"]


def _log_psi(tau) -> np.ndarray:
    """log ψ(τ) (see :func:`exact_shock_density`): piecewise Chebyshev interpolation of log ψ on
    [−2, 26] (degree 28 on panels of width 2; interpolation error < 1e-13, checked), the residue
    sum below −2 and the contour above 26."""
    tau = np.asarray(tau, dtype=float)
    lo, hi, width, deg = _PSI_TABLE
    out = np.empty(tau.shape)
    inside = (tau > lo) & (tau < hi)
    if np.any(~inside):
        out[~inside] = _log_psi_direct(tau[~inside])
    if np.any(inside):
        coef = _psi_table()
        t = tau[inside]
        idx = np.minimum(((t - lo) / width).astype(int), coef.shape[0] - 1)
        x = 2.0 * (t - (lo + width * idx)) / width - 1.0
        c = coef[idx]
        b1 = np.zeros_like(t)
        b2 = np.zeros_like(t)
        for j in range(deg, 0, -1):  # Clenshaw
            b1, b2 = 2.0 * x * b1 - b2 + c[:, j], b1
        out[inside] = x * b1 - b2 + c[:, 0]
    return out


def _airy_log_derivative_series(terms: int) -> np.ndarray:
    """b_j of the large-z expansion Ai'(z)/Ai(z) ~ Σ_j b_j z^{(1−3j)/2} (|arg z| < π), from
    the Riccati equation L' + L² = z: b₀ = −1, Σ_{i+j=n} b_i b_j + b_{n−1}(4 − 3n)/2 = 0."""
    b = np.zeros(terms)
    b[0] = -1.0
    for n in range(1, terms):
        conv = sum(b[i] * b[n - i] for i in range(1, n))
        b[n] = (conv + b[n - 1] * (4.0 - 3.0 * n) / 2.0) / 2.0
    return b


def _k_contour_parts(nodes: int = 24, series: int = 7):
    """Nodes and weights of the Hankel contour used by :func:`_log_k` at small μ, cached:
    Gauss–Legendre with ``nodes`` nodes on each of the panels [0, 1], [1, 3], … [81, 243] of
    r along the ray x₀ + r e^{3πi/4}, x₀ = 1."""
    cache = _k_contour_parts.__dict__
    key = (nodes, series)
    if key not in cache:
        from scipy.special import gamma

        b = _airy_log_derivative_series(series)
        powers = (1.0 - 3.0 * np.arange(series)) / 2.0
        edges = np.array([0.0, 1.0, 3.0, 9.0, 27.0, 81.0, 243.0])
        x, w = _leggauss(nodes)
        half = 0.5 * np.diff(edges)
        r = (edges[:-1, None] + half[:, None] * (x[None, :] + 1.0)).ravel()
        wr = (half[:, None] * w[None, :]).ravel()
        direction = np.exp(0.75j * math.pi)
        z = 1.0 + r * direction
        remainder = _log_airy(z)[1] - (b[None, :] * z[:, None] ** powers[None, :]).sum(axis=1)
        cache[key] = (z, remainder * direction * wr, b, powers, gamma(-powers))
    return cache[key]


def _log_k(mu, nodes: int = 24) -> np.ndarray:
    """log k(μ), k(μ) = 2 Σ_k exp(2^{−1/3} a_k μ) (a_k the zeros of Ai): twice the density at
    0 of a killed Airy-drift bridge (:func:`exact_shock_density`).

    μ ≥ 0.5: the residue sum over the first 400 zeros (the rest below 1e-17 relative).
    μ < 0.5: the sum is (1/2πi) ∫ e^{cz} Ai'(z)/Ai(z) dz (c = 2^{−1/3} μ) on a contour around
    the negative axis, here the rays x₀ + r e^{±3πi/4} from x₀ = 1.  Subtracting the large-z
    expansion Σ_{j<7} b_j z^{(1−3j)/2} of Ai'/Ai, whose integrals are c^{(3j−3)/2}/Γ((3j−1)/2)
    exactly (Hankel), leaves a remainder O(|z|^{−19/2}), integrated by Gauss–Legendre on
    panels up to r = 243 (:func:`_k_contour_parts`).  The j = 0, 1 terms give
    k(μ) = √(2/π) μ^{−3/2} − 1/2 + O(μ^{3/2})."""
    mu = np.asarray(mu, dtype=float)
    out = np.empty(mu.shape)
    big = mu >= _K_SPLIT
    if np.any(big):
        a = _airy_zeros()[0]
        m = mu[big]
        terms = np.exp(np.multiply.outer(m, _CUBE * (a - a[0])))
        out[big] = math.log(2.0) + _CUBE * a[0] * m + np.log(terms.sum(axis=-1))
    if np.any(~big):
        z, weights, b, powers, gam = _k_contour_parts(nodes)
        c = _CUBE * mu[~big]
        series = (b[None, :] * c[:, None] ** (-powers[None, :] - 1.0) / gam[None, :]).sum(axis=1)
        integral = (np.exp(np.multiply.outer(c, z)) @ weights).imag / math.pi
        out[~big] = np.log(2.0 * (series + integral))
    return out


def _log_psi_convolution(mu) -> np.ndarray:
    """log (ψ∗ψ)(μ), (ψ∗ψ)(μ) = ∫ ψ(a) ψ(μ − a) da = 2 I₂(μ) (:func:`_contour_log`): the
    Fourier transform of ψ is 2^{2/3}/Ai(i 2^{1/3} λ), so that of ψ∗ψ is its square."""
    return math.log(2.0) + _contour_log(mu, 2)


def exact_shock_density(a, b) -> np.ndarray:
    """J(a, b): the late-time density, per unit of scaled mass, of clusters whose particles
    came from the scaled labels [ξ − a, ξ + b] and which sit at the scaled position ξ.
    J(a, b) = ¼ (a + b) k(a + b) ψ(a) ψ(b) for a + b > 0, else 0; the cluster's scaled mass is
    μ = a + b and its scaled velocity w = (a − b)/2.

    Scaling.  Label the particles by their mass coordinate m and let Σ_{j<m} v_j = σ B(m)
    (σ² = T₀, B a Brownian motion for any law of finite variance).  The free-streamed partial
    sums are F(m) = m²/(2n) + t σ B(m) + (terms smaller by 1/(n σ t)), and the clusters at time t
    are the segments of the convex minorant of F (module docstring).  With m = ℓ s,
    ℓ = (σ n t)^{2/3} = (n² T₀ t²)^{1/3}, F = σ^{4/3} n^{1/3} t^{4/3} (W(s) + s²/2), W a
    standard two-sided Brownian motion: a cluster is a segment [s₁, s₂] of the convex minorant of
    W(s) + s²/2, its mass is m = ℓ (s₂ − s₁) = ℓ μ, its velocity σ ΔB/Δm = σ^{2/3} (n t)^{−1/3}
    ΔW/Δs, i.e. w = ΔW/Δs, and its position is ℓ/n times the slope ξ of the segment.  So the
    scaled laws below hold for every n, T₀ and initial law of finite variance, at n t ≫ 1.  In
    Burgers' terms: each particle carries its velocity over a spacing 1/n, so the initial
    velocity potential ∫₀^x u₀ = (1/n) Σ_{x_j < x} v_j = (σ/n) B(n x) is a Brownian motion of
    variance T₀/n per unit length (white-noise velocity of strength T₀/n).

    The segment of slope ξ.  H_ξ(s) = W(s) + (s − ξ)²/2 takes its minimum at s₁ = ξ − a and
    s₂ = ξ + b; then W(s₂) − W(s₁) = (a² − b²)/2, so w = (a − b)/2: the cluster's velocity is
    its position minus the centre of its initial labels, over t.  Shifting s and ξ together
    leaves the law of W's increments unchanged, so the clusters form a stationary process in ξ
    and J is a rate per unit ξ, i.e. per unit scaled mass (the slopes advance by as much as the
    labels on average).  Particles: a fraction μ J of the mass sits in such clusters, whence
    ∫∫ (a + b) J(a, b) da db = 1.

    Computing J.  Fix ξ = 0 and follow Z(s) = H₀(s) − h (h the minimum) to the right of a point
    τ where Z = x > 0: dZ = s ds + dW, a Brownian path with the drift s.  Girsanov's theorem
    turns this drift into the potential ∫ X ds of a driftless path X, so the density of Z killed
    at 0 is q(s₀, x; s₁, y) = e^{s₁ y − s₀ x − (s₁³ − s₀³)/6} K(s₁ − s₀; x, y), K the kernel of
    exp(−t(−½ ∂² + x)) on x > 0 with a Dirichlet wall.  Its eigenfunctions are Ai(2^{1/3} x +
    a_k) with eigenvalues −2^{−1/3} a_k, and ∂_x ∂_y K(t; 0, 0) = k(t) = 2 Σ_k e^{2^{−1/3} a_k
    t} (:func:`_log_k`).  The probability that Z, started at x at the point τ, never returns to
    0 is S(τ, x) ≈ φ(τ) x for small x, and ψ(τ) = e^{−τ³/6} φ(τ) has the Fourier transform
    ∫ e^{iλτ} ψ(τ) dτ = 2^{2/3}/Ai(i 2^{1/3} λ) (Laplace transform of the backward equation in
    τ: the solution vanishing at x = 0 whose growth in x is that of e^{τx − τ³/6}).  Hence
    ψ(τ) = 2^{1/3} (1/2πi) ∫ e^{−2^{−1/3} τ z}/Ai(z) dz (:func:`_contour_log`), also
    ψ(τ) = 2^{1/3} Σ_k e^{−2^{−1/3} a_k τ}/Ai'(a_k) for τ < 0, and ψ(τ) ≈ 2τ e^{−τ³/6} as
    τ → ∞.  This is Groeneboom's function (1989): his g(t) is 2^{1/3} ψ(2^{2/3} t), and the
    density of argmin H₀ is ½ ψ(s) ψ(−s), Chernoff's law rescaled.

    Now count jumps of the argmin s*(ξ) between ξ = 0 and δ.  Let W start from Lebesgue
    measure (each level h then counts once, and the count is that of W(0) = 0).  The minimum of
    H₀ sits at s₁ = −a (left part: a path from the left that stays above h, entrance factor
    φ(a) after the reflection s → −s), a second dip to within δμ of h sits at s₂ = b (right
    part: φ(b)), and between them runs a bridge of Z killed at 0.  Each touching point
    contributes the flux ½ ∂ of a killed density (as in the joint law of the place and value
    of a Brownian minimum), the bridge contributes ∂_x∂_y q = e^{−(s₂³ − s₁³)/6} k(μ), and the
    dip may lie anywhere in a window of width δμ.  Altogether
    J = ¼ μ k(μ) φ(a) e^{−a³/6} φ(b) e^{−b³/6} = ¼ μ k(μ) ψ(a) ψ(b).
    Checks (tests): ∫∫ μ J = 1, and the jump rate across s = 0, ∫∫_{a,b>0} J = ½ ψ(0)², equals
    the density of argmin H₀ at 0; the engine reproduces the laws.

    ``a`` and ``b`` broadcast; not finite → ``InvalidArgumentError``.  Computed as above: ψ from
    its table (:func:`_log_psi`), k from :func:`_log_k`, in logarithms (no underflow before the
    final exponential).

    Parameters
    ----------
    a, b : array_like of float
        Scaled label distances (broadcast together).

    Returns
    -------
    numpy.ndarray
        J(a, b).

    Raises
    ------
    InvalidArgumentError
        Naming ``a`` or ``b`` when a value is not finite.
    """
    a = _check_finite_array(a, "a")
    b = _check_finite_array(b, "b")
    a, b = np.broadcast_arrays(a, b)
    mu = a + b
    out = np.zeros(mu.shape)
    ok = (mu > 0) & (mu < _MU_MAX + 2.0 * _W_MAX)
    if np.any(ok):
        m = mu[ok]
        out[ok] = 0.25 * m * np.exp(_log_k(m) + _log_psi(a[ok]) + _log_psi(b[ok]))
    return out


def exact_mass_density(mu) -> np.ndarray:
    """F(μ), the late-time cluster-mass law: the number of clusters of mass m per particle is
    n(m, t) ≈ (n² T₀ t²)^{−2/3} F(μ) at μ = m/(n² T₀ t²)^{1/3}, so ∫ μ F(μ) dμ = 1 (the mass
    fraction in clusters of scaled mass μ is μ F(μ)) and ∫ F dμ = :func:`exact_moments`
    ``["clusters"]``.

    F(μ) = ∫ J(a, μ − a) da = ¼ μ k(μ) (ψ∗ψ)(μ) (:func:`exact_shock_density`), with
    (ψ∗ψ)(μ) = 2 (1/2πi) ∫ e^{−2^{−1/3} μ z}/Ai(z)² dz computed on the steepest-descent path
    through the real saddle (:func:`_contour_log`; (ψ∗ψ)(0) = 2 ∫ Chernoff = 2) and k(μ) from
    :func:`_log_k`.  Asymptotes (:func:`exact_asymptotes`): F ≈ μ^{−1/2}/√(2π) as μ → 0 (the
    free Brownian bridge, k ≈ √(2/π) μ^{−3/2}); F ≈ √(π/2) μ^{5/2} exp(−μ³/24 − λ₁ μ) as
    μ → ∞, λ₁ = −2^{−1/3} a₁ = 1.8557… (ψ∗ψ ≈ √(2π) μ^{3/2} e^{−μ³/24} by the saddle at
    a = b = μ/2, and k ≈ 2 e^{−λ₁ μ}).

    Vectorised; F = 0 for μ < 0, +∞ at μ = 0, and 0 (below 1e-1100) for μ > 40.  Relative
    accuracy better than 1e-10 (tests: two node counts of the contour, the residue sum against
    the Hankel contour for k, ψ∗ψ against the convolution of ψ, ∫ μ F = 1 to 1e-11).
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    mu : array_like of float
        Scaled masses μ.

    Returns
    -------
    numpy.ndarray
        F(μ) (0 for μ ≤ 0).

    Raises
    ------
    InvalidArgumentError
        Naming ``mu`` when a value is not finite.
    """
    mu = _check_finite_array(mu, "mu")
    out = np.zeros(mu.shape)
    out[mu == 0.0] = math.inf
    ok = (mu > 0.0) & (mu <= _MU_MAX)
    if np.any(ok):
        m = mu[ok]
        out[ok] = 0.25 * m * np.exp(_log_k(m) + _log_psi_convolution(m))
    return out


def _log_velocity_density(w, nodes: int = 80) -> np.ndarray:
    """log P(w) for w ≥ 0 (:func:`exact_velocity_density`)."""
    w = np.asarray(w, dtype=float)
    # Where the integrand matters: a scan of its logarithm on a geometric grid of u = √μ.
    scan = np.geomspace(1e-3, 8.0, 96)

    def log_integrand(u, ww):
        m = u * u
        return (math.log(2.0) + np.log(u) + 2.0 * np.log(m) + _log_k(m)
                + _log_psi(0.5 * m + ww) + _log_psi(0.5 * m - ww))

    grid = log_integrand(scan[None, :], w[:, None])
    top = grid.max(axis=1)
    last = np.array([np.flatnonzero(row > t - 50.0)[-1] for row, t in zip(grid, top,
                                                                          strict=True)])
    u_hi = scan[np.minimum(last + 1, scan.size - 1)]
    x, weight = _leggauss(nodes)
    u = 0.5 * u_hi[:, None] * (x[None, :] + 1.0)
    values = log_integrand(u, w[:, None]) - top[:, None]
    total = (np.exp(values) * weight[None, :]).sum(axis=1) * 0.5 * u_hi
    return np.log(0.25 * total) + top


def exact_velocity_density(w, *, nodes: int = 80) -> np.ndarray:
    """P(w), the late-time law of a particle's scaled velocity w = v (n t/T₀)^{1/3} (a particle
    chosen at random, i.e. clusters weighted by their mass, as the engine's per-particle
    velocities count them): P(w) = ∫ μ J(μ/2 + w, μ/2 − w) dμ
    = ¼ ∫₀^∞ μ² k(μ) ψ(μ/2 + w) ψ(μ/2 − w) dμ (:func:`exact_shock_density`).  Even, ∫ P = 1,
    ∫ w² P dw = :func:`exact_moments` ``["velocity_variance"]`` = lim E (n t)^{2/3} T₀^{−2/3}.

    Computed with μ = u² (the integrand is smooth in u: μ² k ~ μ^{1/2} at 0), Gauss–Legendre
    with ``nodes`` nodes on [0, u_max], u_max where the integrand has fallen by e^{−50} from its
    maximum (found on a scan); ψ from its table, k from :func:`_log_k`, all in logarithms.
    Relative accuracy ~1e-11 (tests: 80 against 160 nodes, ∫ P = 1).

    Tail: P(w) ≈ 2^{11/6}/Ai'(a₁) · |w|^{−2} exp(−|w|³/6 − λ₁ |w|) (:func:`exact_asymptotes`):
    the fast particles sit in small clusters (μ ~ 4/w²) far from their labels' centre, so the
    cubic rate 1/6 is that of the Eulerian field (:func:`exact_eulerian_velocity_density`), and
    P(v) ∝ exp(−n t |v|³/(6 T₀)) in the engine's units.  Zero (below 1e-1900) for |w| > 30.
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        P(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite.
    """
    w = np.abs(_check_finite_array(w, "w"))
    out = np.zeros(w.shape)
    ok = w <= _W_MAX
    if np.any(ok):
        out[ok] = np.exp(_log_velocity_density(w[ok], int(nodes)))
    return out


def exact_eulerian_velocity_density(w) -> np.ndarray:
    """P_E(w) = ½ ψ(w) ψ(−w): the late-time law of the Burgers velocity field u(x, t) at a
    fixed point x (not mass-weighted), in w = u (n t/T₀)^{1/3}.

    The field at x is (x − q(x))/t with q(x) the label that the minimising parabola picks,
    so w = ξ − argmin_s (W(s) + (s − ξ)²/2), of density ½ ψ(w) ψ(−w) (the argmin density of
    :func:`exact_shock_density`).  This is also the law of the particles' scaled
    displacements (:func:`displacements` / (ℓ/n)): w ≡ 2^{2/3} Z, Z of Chernoff's law
    (:func:`chernoff_density`), variance 2^{4/3} · 0.2635596 = 0.664129.  Tail
    P_E ≈ 2^{1/3}/Ai'(a₁) · |w| exp(−|w|³/6 − λ₁|w|).  ψ from its table; zero for |w| > 30.
    Not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.

    Returns
    -------
    numpy.ndarray
        P_E(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite.
    """
    w = np.abs(_check_finite_array(w, "w"))
    out = np.zeros(w.shape)
    ok = w <= _W_MAX
    if np.any(ok):
        out[ok] = 0.5 * np.exp(_log_psi(w[ok]) + _log_psi(-w[ok]))
    return out


def _log_velocity_survival(w, nodes: int = 60) -> np.ndarray:
    """log P_>(w) for w ≥ 0 (:func:`exact_velocity_survival`), −inf beyond w = 30."""
    out = np.full(w.shape, -math.inf)
    x, weight = _leggauss(int(nodes))
    core = w <= 1.0
    if np.any(core):
        lim = w[core]
        pts = 0.5 * lim[:, None] * (x[None, :] + 1.0)
        dens = exact_velocity_density(pts, nodes=80)
        out[core] = np.log(0.5 - 0.5 * lim * (dens * weight[None, :]).sum(axis=1))
    tail = (w > 1.0) & (w <= _W_MAX)
    if np.any(tail):
        v = w[tail]
        length = np.array([np.roots([1.0 / 6.0, 0.5 * a, 0.5 * a * a, -65.0]) for a in v])
        length = np.max(np.where(np.abs(length.imag) < 1e-9, length.real, 0.0), axis=1)
        pts = v[:, None] + 0.5 * length[:, None] * (x[None, :] + 1.0)
        log_dens = _log_velocity_density(pts.ravel(), 80).reshape(pts.shape)
        top = log_dens[:, 0]
        total = (np.exp(log_dens - top[:, None]) * weight[None, :]).sum(axis=1)
        out[tail] = top + np.log(0.5 * length * total)
    return out


def exact_velocity_survival(w, *, nodes: int = 60) -> np.ndarray:
    """``P_>(w) = ∫_w^∞ P(w') dw'``: the probability that a particle's scaled velocity exceeds w
    (:func:`exact_velocity_density`; P(|w'| > w) = 2 P_>(w) for w ≥ 0, P_>(−w) = 1 − P_>(w)).

    For |w| ≤ 1: ½ ∓ ∫_0^{|w|} P by Gauss–Legendre with ``nodes`` nodes.  For |w| > 1 the tail
    integral ∫_w^{w+L} P with the same rule, L the root of x³/6 + w x²/2 + w² x/2 = 65 (the
    cubic part of −ln P(w + x)/P(w), which bounds it: the rest of the decay only adds), so the
    neglected part is below e^{−65} of the kept one.  Relative accuracy ~1e-10 (tests: 60
    against 120 nodes; the two formulas against each other at w = 1; dP_>/dw = −P).  Not finite →
    ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities.
    nodes : int
        Gauss–Legendre nodes.

    Returns
    -------
    numpy.ndarray
        P_>(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite.
    """
    w = _check_finite_array(w, "w")
    flat = np.abs(w.ravel())
    out = np.exp(_log_velocity_survival(flat, int(nodes))).reshape(w.shape)
    return np.where(w < 0, 1.0 - out, out)


def exact_velocity_tail_exponent(w) -> np.ndarray:
    """β(w) = d ln(−ln P(|v| > w)) / d ln w from the exact law: the local exponent that
    :func:`velocity_tail_exponent` estimates from a sample (a scale change of w leaves it
    unchanged, so normalising by √E or not does not matter).  With S = 2 P_>(w) (two-sided
    survival, :func:`exact_velocity_survival`) and dS/dw = −2 P(w): β = 2 w P(w)/(S (−ln S)).

    β → 3 only as −ln S ≈ w³/6 + λ₁ w + 4 ln w + const, i.e.
    β ≈ (w³/2 + λ₁ w + 4)/(w³/6 + λ₁ w + 4 ln w − ln(2^{17/6}/Ai'(a₁))): the linear Airy
    term λ₁ w and the power prefactor w^{−4} hold β well below 3 over every range a simulation
    can sample (values in the tests and ``benchmarks/sticky_exact.py``).  For w > 0;
    w ≤ 0 or not finite → ``InvalidArgumentError``.

    Parameters
    ----------
    w : array_like of float
        Scaled velocities, > 0 and not beyond the range where the survival is representable.

    Returns
    -------
    numpy.ndarray
        β(w).

    Raises
    ------
    InvalidArgumentError
        Naming ``w`` when a value is not finite, not positive or too large.
    """
    w = _check_finite_array(w, "w")
    if np.any(w <= 0):
        raise InvalidArgumentError("w", float(w[w <= 0].ravel()[0]), "positive velocities")
    if np.any(w > _W_MAX):
        raise InvalidArgumentError("w", float(w[w > _W_MAX].ravel()[0]),
                                   f"w <= {_W_MAX} (the survival underflows beyond)")
    flat = w.ravel()
    log_s = math.log(2.0) + _log_velocity_survival(flat)
    log_p = _log_velocity_density(flat)
    return (2.0 * flat * np.exp(log_p - log_s) / -log_s).reshape(w.shape)


def exact_asymptotes() -> dict[str, float]:
    """The constants of the asymptotic forms of the exact laws (derived in the docstrings of
    :func:`exact_mass_density`, :func:`exact_velocity_density` and
    :func:`exact_eulerian_velocity_density`; a₁ = −2.33811 the first zero of Ai):

    * ``airy_rate`` λ₁ = −2^{−1/3} a₁: k(μ) ≈ 2 e^{−λ₁ μ}, ψ(τ) ≈ (2^{1/3}/Ai'(a₁)) e^{λ₁ τ};
    * ``mass_small`` 1/√(2π): F(μ) ≈ μ^{−1/2}/√(2π) as μ → 0;
    * ``mass_large`` √(π/2) and ``mass_cubic`` 1/24: F ≈ √(π/2) μ^{5/2} e^{−μ³/24 − λ₁ μ};
    * ``velocity_tail`` 2^{11/6}/Ai'(a₁) and ``velocity_cubic`` 1/6:
      P(w) ≈ 2^{11/6}/Ai'(a₁) |w|^{−2} e^{−|w|³/6 − λ₁ |w|} (c = 1/6 in P ∝ e^{−c|w|³});
    * ``eulerian_tail`` 2^{1/3}/Ai'(a₁): P_E(w) ≈ 2^{1/3}/Ai'(a₁) |w| e^{−|w|³/6 − λ₁ |w|}.

    Returns
    -------
    dict of float
    """
    a, aip = _airy_zeros()
    return {
        "airy_rate": float(-_CUBE * a[0]),
        "mass_small": 1.0 / math.sqrt(2.0 * math.pi),
        "mass_large": math.sqrt(0.5 * math.pi),
        "mass_cubic": 1.0 / 24.0,
        "velocity_tail": float(2.0 ** (11.0 / 6.0) / aip[0]),
        "velocity_cubic": 1.0 / 6.0,
        "eulerian_tail": float(2.0 ** (1.0 / 3.0) / aip[0]),
    }


def exact_moments() -> dict[str, float]:
    """Moments of the exact late-time laws, by Gauss–Legendre quadrature of the densities
    (300 nodes on w ∈ [0, 15], and on u = √μ ∈ [0, 6] for the mass law: beyond, the densities
    are below 1e-160), cached:

    * ``velocity_variance`` ∫ w² P(w) dw = lim_{t→∞} E (n t)^{2/3} T₀^{−2/3} (E the energy per
      particle, ⟨v²⟩): 0.44275…;
    * ``eulerian_variance`` ∫ w² P_E(w) dw = 2^{4/3} Var Z (Chernoff) = 0.664129, the limit of
      ⟨D²⟩ (n/T₀)^{2/3} t^{−4/3} for the displacements D;
    * ``clusters`` ∫ F dμ: the number of clusters is ≈ N (n² T₀ t²)^{−1/3} × this (1.32826…);
    * ``mean_mass`` ∫ μ² F dμ: the mean scaled mass of the cluster of a random particle.

    Returns
    -------
    dict of float
    """
    cache = exact_moments.__dict__
    if "value" not in cache:
        x, weight = _leggauss(300)
        w = 7.5 * (x + 1.0)
        p = exact_velocity_density(w) * 7.5 * weight
        pe = exact_eulerian_velocity_density(w) * 7.5 * weight
        u = 3.0 * (x + 1.0)
        f = exact_mass_density(u * u) * 2.0 * u * 3.0 * weight
        cache["value"] = {
            "velocity_variance": float(2.0 * np.sum(w * w * p)),
            "eulerian_variance": float(2.0 * np.sum(w * w * pe)),
            "clusters": float(np.sum(f)),
            "mean_mass": float(np.sum(u**4 * f)),
        }
    return dict(cache["value"])


# ---------------------------------------------------------------------------------------------
# The engine against the exact laws

#: The scaled-velocity bins of :class:`ExactLawComparison`: 24 bins of width 0.25 on w ∈ [−3, 3]
#: (the two open bins beyond ±3 are added to the outermost ones).
EXACT_W_EDGES = np.linspace(-3.0, 3.0, 25)

_EXACT_CACHE: dict = {}  # exact bin integrals and survivals on fixed grids, computed once


def _bin_integrals(density, edges, nodes: int = 12) -> np.ndarray:
    """∫ ``density`` over each [edges[i], edges[i + 1]] by Gauss–Legendre with ``nodes`` nodes."""
    edges = np.asarray(edges, dtype=float)
    x, weight = _leggauss(nodes)
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
        _check_state(state)
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
            ``density`` (n of the gas, None before the first state), ``scales`` (n and the
            scales of w and μ, or None), ``velocity_bins``
            (Σ m, Σ m², clusters per velocity bin, 3 rows), ``tail_bins`` (the same per tail
            interval), ``masses`` (clusters per integer mass), ``fastest`` (|w| and masses
            of the fastest clusters kept for the deepest point), ``particles``, ``runs``,
            ``energy`` and ``cluster_count`` (per run).
        """
        return {"density": None if self._scales is None else self._scales[0],
                "scales": self._scales, "velocity_bins": self._v.copy(),
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
                and (self._scales is None or theirs["density"] is None
                     or math.isclose(theirs["density"], self._scales[0], rel_tol=1e-12)))
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
