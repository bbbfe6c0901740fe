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

Modules
-------
This module holds the state and the engine; the observables of a state are in
:mod:`particles.sticky_observables`, the exact late-time laws in :mod:`particles.sticky_exact` and
the comparison of runs with them in :mod:`particles.sticky_comparison`.

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
from .validation import (
    InvalidArgumentError,
    check_count,
    check_nonnegative,
    check_positive,
    check_real_array,
)

__all__ = [
    "StickyParams",
    "StickyState",
    "StickyGas",
    "sticky_state",
    "check_state",
]

#: Names that lived here before and have one home elsewhere now: a deep import of one of them
#: from this module raises an ImportError naming that home.
_MOVED = {
    **{name: "particles.sticky_observables" for name in (
        "clusters", "cluster_mass_distribution", "profile_x", "profile_i", "total_momentum",
        "displacements", "velocity_tail_exponent")},
    **{name: "particles.sticky_exact" for name in (
        "chernoff_density", "displacement_scale", "CHERNOFF_VARIANCE", "exact_shock_density",
        "exact_mass_density", "exact_velocity_density", "exact_eulerian_velocity_density",
        "exact_velocity_survival", "exact_velocity_tail_exponent", "exact_asymptotes",
        "exact_moments")},
    **{name: "particles.sticky_comparison" for name in (
        "EXACT_W_EDGES", "ExactLawComparison", "exact_law_runs")},
}


def __getattr__(name: str):
    if name in _MOVED:
        raise ImportError(f"particles.sticky.{name} moved to {_MOVED[name]}.{name}")
    raise AttributeError(f"module 'particles.sticky' has no attribute {name!r}")


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
    return _exact_state(x0, v0, length, t)


def _exact_state(x0: np.ndarray, v0: np.ndarray, length: float, t: float) -> StickyState:
    """:func:`sticky_state` of data already checked: float arrays ``x0`` sorted in
    [0, ``length``) and ``v0`` of one length, float ``length`` > 0 and ``t`` ≥ 0.  The engine
    calls it with the initial data of a state, checked once when that state was made, so a run
    never validates (or copies) its N-particle arrays at each requested time."""
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
    starts = blocks[j: i + 1].astype(np.int64)  # a copy (the scratch may be int32)
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
    # block starts are labels < N: int32 below 2³¹ (4 bytes a block less at the peak)
    starts = np.empty(n, dtype=np.int32 if n < 2**31 else np.int64)
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
        x = rng.uniform(0.0, p.length, p.n)
        x.sort()  # in place: no second array of N positions
        v = initial_velocities(p.initial, p.n, rng)
        if not x[-1] < p.length:  # uniform(0, L) rounds up to L with probability ~N·2⁻⁵³
            return sticky_state(x, v, p.length, 0.0)  # refused there, naming x0
        return _exact_state(x, v, p.length, 0.0)

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
        # the initial data were checked when the state was made (initial_state, sticky_state
        # or rebuild_state): not again at every requested time
        return _exact_state(state.initial_positions, state.initial_velocities,
                            self.params.length, float(until))

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

    def velocity_classes(self, state: StickyState) -> tuple[np.ndarray, np.ndarray]:
        """The distinct velocities of ``state`` and how many particles hold each: the
        clusters' velocities and masses (the driver computes the kurtosis and histogram from
        them, in a pass over the clusters instead of the particles).

        Parameters
        ----------
        state : StickyState
            The state.

        Returns
        -------
        tuple of numpy.ndarray or None
            ``(state.cluster_velocities, state.masses)``; None while more than N/8 clusters
            remain (a pass over the particles is then as cheap, and needs no masses).
        """
        if 8 * state.starts.size > state.velocities.size:
            return None
        return state.cluster_velocities, state.masses

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
            # the same sum as particles.sticky_observables.total_momentum
            "total_momentum": float(np.sum(state.velocities)),
        }
