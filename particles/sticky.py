"""The sticky gas on a ring, solved exactly with no events (SPEC §7, issue 15).

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
particles: then p − N and p are its ends).  Cost: one PAVA of 2N numbers per time.  Tested against
an event-driven sticky simulation of the ring, with clusters across the seam
(``tests/test_sticky.py``).

Energy decay
------------
For independent velocities of variance 1 and density n, at t ≫ 1/n the free-streamed partial sums
are F(m) ≈ m²/(2n) + t W(m) (W a Brownian motion in the label m; the position fluctuations are
smaller by a factor t).  With m = (nt)^{2/3} s, a particle's velocity is (nt)^{−1/3} U, U the mean
increment of a two-sided Brownian motion B over the segment covering s = 0 of the convex
minorant of B(s) + s²/2, so E t^{2/3} → n^{−2/3} ⟨U²⟩ for any law of variance 1 (the
white-noise Burgers problem; Frachebourg, Martin, Piasecki).  The constant ⟨U²⟩ is not derived
here; measured with this module (N = 10⁷, 12 seeds): 0.4497, 0.4438, 0.4425, 0.4420, 0.4439
(± 0.0002 … 0.003) at t = 10, 10², 10³, 10⁴, 10⁵.  What is exact: the *displacements* of the
particles.  A particle's position at t is the slope of the minorant, so D/t^{2/3} tends in law
to a multiple of Chernoff's argmax of W(u) − u² (:func:`displacements`,
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
]


@dataclass(frozen=True)
class StickyParams:
    """Parameters of the sticky gas, checked at construction: ``n`` particles (N ≥ 2) of unit
    mass, number ``density`` N/L > 0, and the name of the ``initial`` velocity law
    (:mod:`particles.initial`)."""

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
        return asdict(self)


@dataclass(frozen=True, eq=False)
class StickyState:
    """The sticky gas at ``time`` t.

    ``initial_positions`` (sorted, in [0, L)) and ``initial_velocities`` are the data at t = 0
    (the state at any time is computed from them, exactly); ``starts``, ``positions`` and
    ``cluster_velocities`` describe the clusters at ``time`` (module docstring); ``velocities[j]``
    is the velocity of particle j (its cluster's); ``collisions`` = N − number of clusters.
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
        clusters are recomputed from the initial data on reading, and checked against them)."""
        return {
            "time": np.array(self.time, dtype=float),
            "length": np.array(self.length, dtype=float),
            "initial_positions": np.array(self.initial_positions, dtype=float),
            "initial_velocities": np.array(self.initial_velocities, dtype=float),
            "velocities": np.array(self.velocities, dtype=float),
            "collisions": np.array(self.collisions, dtype=np.int64),
        }


def sticky_state(x0, v0, length: float, t: float) -> StickyState:
    """The exact sticky-gas state at time ``t`` ≥ 0 from initial positions ``x0`` (sorted, in
    [0, ``length``)) and velocities ``v0`` (module docstring: one isotonic regression of the two
    unrolled periods).  Inputs are trusted (checked by the public callers)."""
    x0 = np.asarray(x0, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    n = x0.size
    length = float(length)
    t = float(t)
    g = np.empty(2 * n)
    np.multiply(v0, t, out=g[:n])
    g[:n] += x0
    g[:n] -= length  # a constant: the window's values lie in [-L, L) + v t
    np.add(g[:n], length, out=g[n:])
    from scipy.optimize import isotonic_regression  # ~1 s to import: on first use only

    fit = isotonic_regression(g)
    del g
    blocks = fit.blocks  # window indices of the block starts, with 2n appended
    values = fit.x
    # The first window vertex p >= n is a cut of the ring; so is p - n (module docstring).
    k_hi = int(np.searchsorted(blocks, n, side="left"))
    p = int(blocks[k_hi])
    k_lo = int(np.searchsorted(blocks, p - n, side="left"))
    if int(blocks[k_lo]) != p - n:  # impossible in exact arithmetic; guards the lemma
        raise RuntimeError(f"sticky: no cut at {p - n} although {p} is one (window {blocks})")
    wstarts = blocks[k_lo:k_hi]  # cluster starts in window indices, in [p - n, p)
    wpos = values[wstarts] + length  # undo the constant
    del fit, values, blocks
    masses = np.diff(np.append(wstarts, p))
    q = (p - n) % n  # the label at window index p - n
    vw = np.roll(v0, -q)  # velocities in window order
    vel = np.add.reduceat(vw, wstarts - (p - n)) / masses
    del vw
    # Label order: clusters starting at window index >= n start at label w - n, positions - L.
    labels = wstarts % n
    second = wstarts >= n
    wpos[second] -= length
    order = np.concatenate([np.flatnonzero(second), np.flatnonzero(~second)])
    starts = labels[order]
    positions = wpos[order]
    cvel = vel[order]
    masses = masses[order]
    velocities = np.repeat(cvel, masses)
    velocities = np.roll(velocities, starts[0])  # the wrapping cluster's tail sits at labels < s0
    return StickyState(
        t, length, x0, v0, starts.astype(np.int64), positions, cvel, velocities,
        int(n - starts.size),
    )


# ---------------------------------------------------------------------------------------------
# Observables


def clusters(state: StickyState):
    """``(starts, masses, positions, velocities)`` of the clusters in label order: first labels,
    numbers of particles, positions reduced mod L into [0, L), velocities."""
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
    ``state.length`` for clusters per unit length (the m^{-1/2} law of SPEC §7 is in these)."""
    _check_state(state)
    m, count = np.unique(state.masses, return_counts=True)
    return m, count


def profile_x(state: StickyState):
    """The profile v(x, t): particle positions (each at its cluster's) reduced mod L into [0, L),
    sorted increasingly, and the particles' velocities (the MD convention of
    :func:`particles.md.profile_x`)."""
    _check_state(state)
    y = np.mod(np.repeat(state.positions, state.masses), state.length)
    v = np.repeat(state.cluster_velocities, state.masses)
    order = np.argsort(y, kind="stable")
    return y[order], v[order]


def profile_i(state: StickyState):
    """The profile v(i, t) against particle label i (as :func:`particles.md.profile_i`)."""
    _check_state(state)
    return np.arange(state.velocities.size), state.velocities.copy()


def total_momentum(state: StickyState) -> float:
    """Σ_j v_j (unit masses): conserved, zero at t = 0 up to round-off."""
    _check_state(state)
    return float(np.sum(state.velocities))


def displacements(state: StickyState) -> np.ndarray:
    """Each particle's displacement since t = 0, unwrapped (not reduced mod L): its cluster's
    position minus its initial position, with the labels j < ``starts[0]`` of a cluster across
    the seam counted at x_j + L (module docstring).  Σ_j of it is t Σ_j v_j(0) (the centre of
    mass flies freely).  At t ≫ 1/n it tends in law to :func:`displacement_scale` · t^{2/3} · Z,
    Z of Chernoff's law (:func:`chernoff_density`)."""
    _check_state(state)
    where = np.roll(np.repeat(state.positions, state.masses), state.starts[0])
    d = where - state.initial_positions
    d[: state.starts[0]] -= state.length
    return d


#: Var Z of Chernoff's law, Z = argmax_t (W(t) − t²) for a two-sided standard Brownian motion W
#: (Groeneboom and Wellner, J. Comput. Graph. Stat. 10, 388 (2001): 0.26355964); the quadrature
#: of :func:`chernoff_density` gives 0.2635596413 (``tests/test_sticky_displacement.py``).
CHERNOFF_VARIANCE = 0.26355964


def chernoff_density(z, *, cutoff: float = 40.0, nodes: int = 800) -> np.ndarray:
    """Chernoff's density f(z) = g(z) g(−z) / 2 of Z = argmax_t (W(t) − t²) (Groeneboom,
    Probab. Th. Rel. Fields 81, 79 (1989)), where g has the Fourier transform
    ĝ(λ) = ∫ e^{iλz} g(z) dz = 2^{1/3} / Ai(i 2^{−1/3} λ).  ĝ(−λ) is the conjugate of ĝ(λ), so
    g(z) = (1/π) ∫_0^∞ Re[e^{−iλz} ĝ(λ)] dλ, computed by Gauss–Legendre quadrature with
    ``nodes`` nodes on [0, ``cutoff``]: |ĝ(λ)| falls like exp(−(√2/3) (2^{−1/3} λ)^{3/2}), below
    1e-23 at λ = 40, and the integrand's phase λ|z| needs |z| ≲ 10 for 800 nodes.  f is even,
    ∫ f = 1 and Var Z = :data:`CHERNOFF_VARIANCE` (both checked by the tests)."""
    from scipy.special import airy

    z = np.asarray(z, dtype=float)
    x, w = np.polynomial.legendre.leggauss(int(nodes))
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
    argmax_u (W(u) − u²/2) = 2^{2/3} Z."""
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
    particles share one velocity), so compare seeds for an honest spread."""
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
    """

    name = "sticky"
    time_name = "t"

    def __init__(self, params: StickyParams, *, stop_step: float | None = None):
        if not isinstance(params, StickyParams):
            raise InvalidArgumentError("params", params, "a StickyParams")
        self.p = params
        self.stop_step = math.inf if stop_step is None else check_positive(stop_step, "stop_step")

    def params(self) -> dict:
        out = self.p.to_dict()
        out["model"] = self.name
        out["stop_step"] = self.stop_step if math.isfinite(self.stop_step) else None
        return out

    def next_stop(self, time: float) -> float:
        if not math.isfinite(self.stop_step):
            return math.inf
        return next_grid_point(time, self.stop_step)

    def initial_state(self, rng: np.random.Generator) -> StickyState:
        """Uniform sorted positions on [0, L), then velocities from the law with zero mean and
        ⟨v²⟩ = 1 (:func:`particles.driver.initial_velocities`): the draws of MD."""
        if not isinstance(rng, np.random.Generator):
            raise InvalidArgumentError("rng", rng, "a numpy.random.Generator")
        p = self.p
        x = np.sort(rng.uniform(0.0, p.length, p.n))
        v = initial_velocities(p.initial, p.n, rng)
        return sticky_state(x, v, p.length, 0.0)

    def advance(self, state: StickyState, until: float, rng: np.random.Generator | None = None):
        """The exact state at ``until`` ≥ ``state.time`` (computed from the initial data)."""
        _check_state(state)
        until = check_nonnegative(until, "until")
        if until < state.time:
            raise InvalidArgumentError("until", until, f"a time >= the state's time {state.time}")
        if state.velocities.size != self.p.n:
            raise InvalidArgumentError("state", f"N={state.velocities.size}", f"N={self.p.n}")
        return sticky_state(state.initial_positions, state.initial_velocities, self.p.length,
                            until)

    def state_from_arrays(self, arrays) -> StickyState:
        """Rebuild a state from :meth:`StickyState.to_arrays`; an inconsistent one raises
        ``InvalidArgumentError`` naming ``checkpoint``."""
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
        n = self.p.n
        if x0.shape != (n,) or v0.shape != (n,) or v.shape != (n,):
            shapes = (x0.shape, v0.shape, v.shape)
            raise InvalidArgumentError("checkpoint", f"shapes {shapes}", f"arrays of length {n}")
        ok = (math.isfinite(t) and t >= 0.0 and length == self.p.length
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
        k = state.starts.size
        return {
            "clusters": float(k),
            "mean_cluster_mass": state.velocities.size / k,
            "total_momentum": total_momentum(state),
        }
