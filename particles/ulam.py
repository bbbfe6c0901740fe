"""The Ulam (mean-field pseudo-Maxwell) model: exact continuous-time dynamics, vectorized.

Model.  N particles; pair collisions form a Poisson process of rate N/2 in τ, each
collision picks a uniformly random pair i ≠ j and applies the rule of :mod:`particles.collision`.
Each particle thus collides at rate 1 and τ counts collisions per particle.  This is *not* a
synchronous sweep over all pairs.

Exact vectorized scheme.  τ is cut into windows on a fixed grid of step ``window``
(a power of two, so grid points are exact floats) and at the requested times.  For a window of
length Δτ we draw the number of events K ~ Poisson(N Δτ / 2) and the K pairs; event times inside
a window are never needed, only their order.  The events are then fired in rounds: in each round
every remaining event that is the earliest remaining event of *both* its particles fires (all
such events touch disjoint particles, and no earlier event can touch them), and is removed.  This
applies exactly the updates of a sequential loop over the same events, in an order that differs
only by swapping events on disjoint particles, so the velocities agree bit for bit
(:func:`collide_in_order` against :func:`collide_sequential`).

"Earliest remaining event of each particle" is a scatter-max of the occurrence index: the events
are stored in *reverse* time order as an interleaved int32 array ``[a_0, b_0, a_1, b_1, ...]``
and a single fancy assignment ``first[pairs] = arange(2K)`` leaves, for each particle, the
largest occurrence index written to it.  NumPy applies repeated indices in order in practice, but
does not promise it, so the result is checked (every occurrence must see an index ≥ its own) and
recomputed with ``np.maximum.at`` if the check ever fails.

Momentum round-off.  Collisions conserve the total momentum only up to round-off, and that
residue does not decay while the velocities decay like e^{−λτ}: for λτ ≳ 30 every velocity would
approach the round-off mean (measured before this correction: r = 0.9, N = 2·10⁴, τ = 1200, all
velocities of a run equal).  The collision rule is Galilean invariant (it depends only on the
difference of the two velocities), so subtracting the mean velocity from every particle commutes
with the dynamics and is exact up to round-off.  Both engines do it (:func:`recentre`) at the
same deterministic points: the multiples of ``stop_step`` in τ, after every event before that
point and before every event after it.  They are window boundaries of the fast path (``stop_step``
is a multiple of ``window``), so the fast path and the sequential loop still agree bit for bit on
the same events (:func:`collide_sequential` followed by :func:`recentre`).  The momentum recorded
at a grid point is therefore ~0 by construction and says nothing about conservation; the
collisions' own drift shows at times between grid points, and the tests bound it there.

d dimensions, ``dimension`` = 2 or 3.  Velocities have shape (N, d).  A collision of
(a, b) with g = v_a − v_b and a unit vector n applies v_a' = v_a − p (g·n) n, v_b' = v_b + p (g·n) n
(:func:`collide_vectors`; operations in a fixed order, dot products summed column by column, so
the fast path and :func:`collide_sequential_vectors` agree bit for bit).  The same window scheme
is used; each event's angular variables are drawn with the window, in advance
(:func:`draw_angles`).

d = 2 runs in complex numbers: inside ``advance`` the (N, 2) array is viewed as N complex
velocities v = v_x + i v_y (one 16-byte element per particle, so each round is one 1-D gather
and one scatter).  Write n = ĝ e^{iφ}, φ the angle from ĝ to n; then (g·n) n = g cos φ e^{iφ}
(= (g + ḡ n²)/2), and since n and −n are the same collision, φ ∈ [−π/2, π/2] with
c = cos φ = √(1 − s²), s = sin φ.  So δ = g t with t = p (c² + i s c) (:func:`plane_transfer`,
:func:`collide_complex`): no |g|, no normalisation, one drawn number s per event.  Its law:

* ``"uniform"``: n uniform and independent of g, so φ is uniform and independent of g, and s =
  sin φ has the arcsine law, drawn as s = cos(πu), u uniform;
* ``"hard"``: density ∝ |cos φ| dφ = |ds|, so s is uniform on [−1, 1], drawn as 2u − 1.

Then η = c² = 1 − s² is Beta(1/2, 1/2), resp. Beta(1, 1/2) (at d = 2).  The product g t is
written out in real operations (:func:`collide_complex`).  In d = 3 each event's variables are
turned into n when the event fires (:func:`collision_directions`):

* ``"uniform"``: n = z/|z|, z a standard normal vector (n uniform on the sphere, independent
  of g);
* ``"hard"``: n has density ∝ |ĝ·n| on the sphere.  Exact construction: the component
  x = ĝ·n of a uniform direction has density ∝ (1 − x²)^{(d−3)/2}; weighted by |x|, η = x² is
  Beta(1, (d − 1)/2), whose CDF is 1 − (1 − η)^{(d−1)/2}, so η = 1 − u^{2/(d−1)} with u uniform
  (drawn in advance); the direction perpendicular to ĝ is uniform on the sphere of ĝ⊥, obtained
  at firing time by projecting a pre-drawn normal vector z on ĝ⊥ and normalising.  Then
  n = √η ĝ + √(1 − η) e⊥ (the sign of n does not matter: n enters twice).  If g = 0 the
  collision changes nothing, whatever n.

Throughput: ``benchmarks/ulam_dimensions.py`` (N = 10⁶, 10⁶ collisions, configurations
interleaved; the table is in benchmarks/README.md).  With complex arithmetic, 2D uniform runs
about 2 times slower than 1D and 2D hard about 1.6 (before it: 2.8 and 3.2); the 2D cost is the
random-access gather and scatter, the round schedule (as in 1D) and, for "uniform", the cosine
of the draws.  3D (not changed) is about 4-5 times slower than 1D.

Initial velocities in d dimensions: each Cartesian component is an independent draw of the
initial law, centred and scaled to unit variance (so ⟨|v|²⟩ = d at τ = 0).  Recentring subtracts
the mean velocity vector.  Expected energy: ⟨|v|²⟩(τ) = ⟨|v|²⟩(0) e^{−Λτ N/(N−1)} with
Λ = 2pq⟨η⟩, ⟨η⟩ = 1/d (uniform) or 2/(d + 1) (hard) (derivation in :class:`Ulam`).  The run
driver (:func:`particles.driver.simulate`) records per-particle observables of 1D arrays; for
d ≥ 2 call ``initial_state`` / ``advance`` directly.

Driven 1D model (``driving`` = D > 0).  Between its collision events every particle feels white
noise of strength D (Fokker–Planck term D ∂²_v P), i.e. a Gaussian kick of variance 2DΔτ over a
time Δτ.  Exact scheme: the events of a window get explicit times (K sorted uniform times in the
window, which is the law of the event times of a Poisson process given K) and two standard
normals each, drawn in advance; when an event fires, each of its two particles first receives
the kick for the time since its previous kick (``last``), then the collision is applied.  At the
end of ``advance`` and at each recentring point every particle is kicked up to that time (N more
normals).  Since the noise is additive and independent of the velocities, recentring still
commutes with the dynamics; it
removes the random walk of the centre of mass (variance 2Dτ/N), and with zero total momentum the
steady energy is ⟨v²⟩ = (D/pq)(1 − 1/N)² (derivation in :class:`Ulam`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .collision import collide_arrays, collide_scalar, transfer_fraction
from .driver import EngineBase, initial_velocities, next_grid_point
from .initial import get_law
from .validation import (
    InvalidArgumentError,
    check_choice,
    check_count,
    check_dimension,
    check_nonnegative,
    check_restitution,
)

__all__ = [
    "Ulam",
    "UlamReference",
    "UlamState",
    "AngularDraws",
    "ANGULAR_MODELS",
    "draw_pairs",
    "draw_angles",
    "collision_directions",
    "collide_vectors",
    "collide_complex",
    "plane_transfer",
    "collide_in_order",
    "collide_sequential",
    "collide_in_order_vectors",
    "collide_sequential_vectors",
    "recentre",
]

#: Angular models of the d-dimensional collisions (module docstring).
ANGULAR_MODELS = ("uniform", "hard")

#: Events per window aimed at: large enough to amortise NumPy call overhead, small enough that
#: a particle has few events per window (few rounds).  Measured best near 2.5e4 at N = 1e6
#: (2.3e7 events/s, against 1.9e7 with 1e5 and 1.1e7 with 2e5).
TARGET_EVENTS = 25_000


def _window_for(n: int) -> float:
    """Window length in τ: the power of two nearest to 2·TARGET_EVENTS/N, clipped to [2⁻¹², 2]."""
    exponent = int(np.clip(np.round(np.log2(2.0 * TARGET_EVENTS / n)), -12, 1))
    return 2.0**exponent


@dataclass(frozen=True)
class UlamState:
    """Ulam state at time ``time`` (τ): velocities and the total number of pair collisions.

    Attributes
    ----------
    time : float
        τ, collisions per particle (N/2 pair collisions per unit on average).
    velocities : numpy.ndarray
        Shape ``(N,)`` in 1D, ``(N, d)`` otherwise.
    collisions : int
        Total number of pair collisions so far.
    """

    time: float
    velocities: np.ndarray = field(repr=False)
    collisions: int = 0

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The state as a dict of NumPy arrays (what the driver's checkpoints store).

        Returns
        -------
        dict of str to numpy.ndarray
            ``time``, ``velocities`` and ``collisions``.
        """
        return {
            "time": np.array(self.time, dtype=float),
            "velocities": self.velocities,
            "collisions": np.array(self.collisions, dtype=np.int64),
        }

    @classmethod
    def from_arrays(cls, arrays, n: int, dimension: int = 1) -> UlamState:
        """Rebuild a state from :meth:`to_arrays`'s dict.

        Parameters
        ----------
        arrays : mapping
            The arrays, as :meth:`to_arrays` writes them.
        n : int
            The number of particles N.
        dimension : int, optional
            The dimension d (default 1).

        Returns
        -------
        particles.UlamState
            The state (with a copy of the velocities).

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint`` (a ``ValueError``, which the driver turns into its
            ``CheckpointError`` naming the file): a missing entry, or velocities not of shape
            ``(n,)`` (1D) or ``(n, dimension)``.
        """
        missing = [k for k in ("time", "velocities", "collisions") if k not in arrays]
        if missing:
            raise InvalidArgumentError("checkpoint", f"missing {missing}", "an Ulam state")
        v = np.asarray(arrays["velocities"], dtype=float)
        shape = (n,) if dimension == 1 else (n, dimension)
        if v.shape != shape:
            raise InvalidArgumentError(
                "checkpoint", f"velocities of shape {v.shape}", f"an Ulam state, expected {shape}"
            )
        return cls(float(arrays["time"]), v.copy(), int(arrays["collisions"]))


def draw_pairs(rng: np.random.Generator, n: int, k: int) -> np.ndarray:
    """``k`` independent uniformly random ordered pairs (i, j), i ≠ j, of ``n`` particles, as an
    int32 array of shape (k, 2).

    Parameters
    ----------
    rng : numpy.random.Generator
        The random generator.
    n : int
        The number of particles N ≥ 2.
    k : int
        The number of pairs.

    Returns
    -------
    numpy.ndarray
        int32 array of shape ``(k, 2)``.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``rng``) if it is not a ``numpy.random.Generator``; (``n``) if it is not an
        integer in [2, 2³¹ − 1]; (``k``) if it is not an integer >= 0.
    """
    if not isinstance(rng, np.random.Generator):
        raise InvalidArgumentError("rng", type(rng).__name__, "a numpy.random.Generator")
    n = check_count(n, "n", 2)
    if n > 2**31 - 1:
        raise InvalidArgumentError("n", n, "an integer <= 2**31 - 1 (int32 particle ids)")
    return _draw_pairs(rng, n, check_count(k, "k", 0))


def _draw_pairs(rng: np.random.Generator, n: int, k: int) -> np.ndarray:
    """:func:`draw_pairs` without the checks (the engine's own arguments)."""
    pairs = np.empty((k, 2), dtype=np.int32)
    pairs[:, 0] = rng.integers(0, n, k, dtype=np.int32)
    second = rng.integers(0, n - 1, k, dtype=np.int32)
    second += second >= pairs[:, 0]
    pairs[:, 1] = second
    return pairs


def _largest_occurrence(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """For each entry of ``flat`` (particle ids), the largest ``occ`` among the entries with the
    same particle.  One fancy assignment (the last write wins), verified; exact fallback."""
    first[flat] = occ
    own = first[flat]
    if not np.all(own >= occ):  # pragma: no cover - NumPy did not write in order
        own = _largest_occurrence_ufunc(first, flat, occ)
    return own


def _largest_occurrence_ufunc(first: np.ndarray, flat: np.ndarray, occ: np.ndarray) -> np.ndarray:
    """The same with ``np.maximum.at`` (order-independent, ~10x slower)."""
    first[flat] = -1
    np.maximum.at(first, flat, occ)
    return first[flat]


def _rounds(reversed_pairs: np.ndarray, first: np.ndarray, occurrence: np.ndarray):
    """The round schedule of the events of ``reversed_pairs`` ((K, 2) int32, C-contiguous,
    **last event first**): yields, round by round, ``(fired, fire)`` where ``fire`` masks the
    events still pending that fire now (each is the earliest pending event of both its
    particles) and ``fired`` = [a_0, b_0, a_1, …] their particles, all distinct.  ``first`` is
    int32 scratch of size N, ``occurrence`` is ``arange(≥ 2K, dtype=int32)``.  The caller
    applies the round before asking for the next (``fire`` is reused afterwards)."""
    packed = reversed_pairs.view(np.int64).reshape(-1)  # one int64 per event: cheap compaction
    while packed.size:
        m = packed.size
        # a_0, b_0, a_1, b_1, ... (reverse time order); intp indices index ~2x faster than int32
        flat = packed.view(np.int32).astype(np.intp)
        occ = occurrence[: 2 * m]
        own = _largest_occurrence(first, flat, occ)
        # Event r (occurrences 2r, 2r+1) fires iff it is the earliest of both its particles.
        own_is_first = own == occ
        fire = own_is_first[0::2]
        fire &= own_is_first[1::2]
        # np.compress, not packed[fire]: boolean indexing is ~5x slower on random masks.
        fired = np.compress(fire, packed).view(np.int32).astype(np.intp)
        yield fired, fire
        np.logical_not(fire, out=fire)
        packed = np.compress(fire, packed)


def _fire_rounds(
    v: np.ndarray, reversed_pairs: np.ndarray, p: float, first: np.ndarray, occurrence: np.ndarray
) -> int:
    """Apply the events of ``reversed_pairs`` to ``v`` in place, round by round (:func:`_rounds`).
    Returns the number of rounds."""
    rounds = 0
    for fired, _ in _rounds(reversed_pairs, first, occurrence):
        vv = v[fired]
        vv2 = vv.reshape(-1, 2)
        collide_arrays(vv2[:, 0], vv2[:, 1], p)
        v[fired] = vv
        rounds += 1
    return rounds


def recentre(v: np.ndarray) -> None:
    """Subtract the mean velocity from ``v`` in place (exact by Galilean invariance of the
    collision rule; removes the non-decaying round-off of the total momentum).  ``v`` of shape
    (N,) or (N, d).

    Parameters
    ----------
    v : numpy.ndarray
        Velocities, modified in place.
    """
    if v.ndim == 1:
        v -= v.mean()
    else:
        v -= v.mean(axis=0)


# --------------------------------------------------------------------------- d dimensions


@dataclass(frozen=True)
class AngularDraws:
    """Angular variables of K events drawn in advance.  d = 3: ``z`` standard normal vectors
    (K, 3), for the "hard" model also ``eta`` = (ĝ·n)² ~ Beta(1, 1) (K,), else ``None``.
    d = 2: ``sine`` = sin φ (K,), φ the angle from ĝ to n (``z`` and ``eta`` are ``None``).

    Attributes
    ----------
    z : numpy.ndarray or None
        d = 3: standard normal vectors, shape ``(K, 3)``; None in d = 2.
    eta : numpy.ndarray or None
        d = 3, "hard" model: η = (ĝ·n)², shape ``(K,)``; else None.
    sine : numpy.ndarray or None
        d = 2: sin φ, shape ``(K,)``; else None.
    """

    z: np.ndarray | None
    eta: np.ndarray | None = None
    sine: np.ndarray | None = None


def draw_angles(rng: np.random.Generator, k: int, dimension: int, angular: str) -> AngularDraws:
    """The angular variables of ``k`` events (module docstring).  d = 2: one uniform u per
    event, sin φ = cos(πu) ("uniform") or 2u − 1 ("hard").  d = 3: normals first, then η.

    Parameters
    ----------
    rng : numpy.random.Generator
        The random generator.
    k : int
        The number of events.
    dimension : int
        The dimension d (2 or 3).
    angular : str
        ``"uniform"`` or ``"hard"``.

    Returns
    -------
    AngularDraws
        The draws of the ``k`` events.
    """
    if dimension == 2:
        u = rng.random(k)
        if angular == "uniform":
            return AngularDraws(None, sine=np.cos(np.pi * u))
        u *= 2.0
        u -= 1.0  # exact: u is a multiple of 2⁻⁵³ in [0, 1)
        return AngularDraws(None, sine=u)
    z = rng.standard_normal((k, dimension))
    if angular == "uniform":
        return AngularDraws(z)
    u = rng.random(k)
    # η = 1 − u^{2/(d−1)} inverts the CDF 1 − (1 − η)^{(d−1)/2}; 1 − u (not u) keeps η < 1
    eta = 1.0 - (1.0 - u) ** (2.0 / (dimension - 1))
    return AngularDraws(z, eta)


def plane_transfer(sine: np.ndarray, p: float) -> np.ndarray:
    """d = 2: the complex factor t = p (g·n) n / g = p cos φ e^{iφ} = p (c² + i s c) of events
    with sin φ = ``sine`` = s, c = cos φ = √((1 − s)(1 + s)) ≥ 0 (n and −n are the same
    collision, so φ ∈ [−π/2, π/2]).  Element by element with correctly rounded operations, so
    the same bits whether computed for one event or for a window.

    Parameters
    ----------
    sine : array_like
        sin φ of the events.
    p : float
        The transfer fraction (1 + r)/2.

    Returns
    -------
    numpy.ndarray
        Complex array of the shape of ``sine``.
    """
    s = np.asarray(sine, dtype=float)
    c2 = 1.0 - s  # (1 − s)(1 + s), not 1 − s²: c is accurate to round-off even near s = ±1
    c2 *= 1.0 + s
    t = np.empty(s.shape, dtype=np.complex128)
    np.multiply(c2, p, out=t.real)
    c = np.sqrt(c2, out=c2)
    c *= s
    np.multiply(c, p, out=t.imag)
    return t


def collide_complex(va: np.ndarray, vb: np.ndarray, transfer: np.ndarray) -> None:
    """The 2D rule in place on complex velocities v = v_x + i v_y.

    With g = v_a − v_b and δ = g · ``transfer`` (= p (g·n) n, :func:`plane_transfer`),
    v_a −= δ and v_b += δ.  The product g · t is written out in real operations, each correctly
    rounded, so that it gives the same bits for one event as for a window: NumPy's own complex
    multiply may fuse multiply-adds in its SIMD loop but not in its scalar fallback.

    Parameters
    ----------
    va, vb : numpy.ndarray
        Complex velocities of the first and second particle of each event, same shape;
        modified in place.
    transfer : numpy.ndarray
        The complex factors of :func:`plane_transfer`, one per event.
    """
    g = va - vb
    delta = np.empty_like(g)
    re, im = delta.real, delta.imag
    np.multiply(g.real, transfer.real, out=re)
    tmp = g.imag * transfer.imag
    re -= tmp
    np.multiply(g.real, transfer.imag, out=im)
    np.multiply(g.imag, transfer.real, out=tmp)
    im += tmp
    va -= delta
    vb += delta


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a·b of (m, d) arrays, summed column by column (a fixed order of operations)."""
    out = a[:, 0] * b[:, 0]
    for c in range(1, a.shape[1]):
        out += a[:, c] * b[:, c]
    return out


def collision_directions(g: np.ndarray, draws: AngularDraws, angular: str) -> np.ndarray:
    """Unit vectors n (m, d) for relative velocities ``g`` (m, d) and the events' ``draws``.
    d = 2: n = ĝ e^{iφ} (as a vector), the direction :func:`plane_transfer` collides along
    (ĝ = x̂ where g = 0: the collision changes nothing).

    Parameters
    ----------
    g : numpy.ndarray
        Relative velocities v_a − v_b, shape ``(m, d)``.
    draws : AngularDraws
        The angular variables of the m events.
    angular : str
        ``"uniform"`` or ``"hard"``.

    Returns
    -------
    numpy.ndarray
        Unit vectors n, shape ``(m, d)``.
    """
    if g.shape[1] == 2:
        gc = np.ascontiguousarray(g, dtype=float).view(np.complex128).reshape(-1)
        g_norm = np.abs(gc)
        g_hat = np.where(g_norm > 0.0, gc / np.where(g_norm > 0.0, g_norm, 1.0), 1.0)
        s = draws.sine
        n = g_hat * (np.sqrt((1.0 - s) * (1.0 + s)) + 1j * s)
        return np.stack([n.real, n.imag], axis=1)
    z = draws.z
    if angular == "uniform":
        return z / np.sqrt(_dot(z, z))[:, None]
    g_norm = np.sqrt(_dot(g, g))
    g_hat = g / np.where(g_norm > 0.0, g_norm, 1.0)[:, None]  # 0 where g = 0 (no collision)
    perp = z - _dot(z, g_hat)[:, None] * g_hat
    e = perp / np.sqrt(_dot(perp, perp))[:, None]
    eta = draws.eta
    return np.sqrt(eta)[:, None] * g_hat + np.sqrt(1.0 - eta)[:, None] * e


def collide_vectors(va: np.ndarray, vb: np.ndarray, n: np.ndarray, p: float) -> None:
    """The d-dimensional rule in place on (m, d) arrays: with g = v_a − v_b and
    δ = p (g·n) n, v_a −= δ and v_b += δ (the same δ: momentum is conserved up to the two final
    roundings).

    Parameters
    ----------
    va, vb : numpy.ndarray
        Velocities of the first and second particle of each event, shape ``(m, d)``;
        modified in place.
    n : numpy.ndarray
        Unit collision directions, shape ``(m, d)``.
    p : float
        The transfer fraction (1 + r)/2.
    """
    g = va - vb
    delta = (_dot(g, n) * p)[:, None] * n
    va -= delta
    vb += delta


def _scatter_rows(v: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """``v[rows] = values`` for a C-contiguous (N, d) ``v`` and distinct ``rows``, through 1-D
    views: NumPy's row-wise fancy assignment on (N, d) arrays is ~50x slower (measured,
    N = 1e6, 2e4 rows).  d = 2 moves each row as one 16-byte complex; otherwise per component."""
    d = v.shape[1]
    if d == 2:
        v.view(np.complex128).reshape(-1)[rows] = values.view(np.complex128).reshape(-1)
        return
    flat = v.reshape(-1)
    base = rows * d
    for c in range(d):
        flat[base + c] = values[:, c]


def _collide_events_vectors(v, fired, draws: AngularDraws, angular: str, p: float) -> None:
    """Collide the pairs ``fired`` = [a_0, b_0, a_1, b_1, …] (all distinct) with the events'
    ``draws``: one ``np.take`` gather and one scatter (row-wise fancy indexing of (N, d) arrays
    is slow, see :func:`_scatter_rows`)."""
    vv = np.take(v, fired, axis=0)
    va, vb = vv[0::2], vv[1::2]
    n = collision_directions(va - vb, draws, angular)
    collide_vectors(va, vb, n, p)
    _scatter_rows(v, fired, vv)


def _fire_rounds_with_rows(v, reversed_pairs, first, occurrence, collide) -> int:
    """:func:`_fire_rounds` for events that carry data: ``collide(v, fired, rows)`` applies the
    events of rows ``rows`` of ``reversed_pairs`` (particles ``fired`` = [a_0, b_0, a_1, …], all
    distinct)."""
    rows = np.arange(len(reversed_pairs), dtype=np.intp)
    rounds = 0
    for fired, fire in _rounds(reversed_pairs, first, occurrence):
        collide(v, fired, np.compress(fire, rows))
        rows = np.compress(~fire, rows)
        rounds += 1
    return rounds


def _fire_rounds_plane(w, reversed_pairs, transfer, first, occurrence) -> int:
    """d = 2: :func:`_fire_rounds` on complex velocities ``w`` (N,) with one complex factor
    per event (``transfer``, rows as ``reversed_pairs``; :func:`plane_transfer`).  A gather, the
    rule and a scatter of 16-byte elements per round; the factors of the pending events are
    compacted alongside the pairs."""
    rounds = 0
    for fired, fire in _rounds(reversed_pairs, first, occurrence):
        vv = np.take(w, fired)
        collide_complex(vv[0::2], vv[1::2], np.compress(fire, transfer))
        w[fired] = vv
        transfer = np.compress(~fire, transfer)
        rounds += 1
    return rounds


def _subset(draws: AngularDraws, rows) -> AngularDraws:
    def take(a, axis=None):
        return None if a is None else np.take(a, rows, axis=axis)

    return AngularDraws(take(draws.z, 0), take(draws.eta), take(draws.sine))


def _check_vector_events(v, pairs, restitution, draws, angular):
    p = transfer_fraction(restitution)
    v = np.array(v, dtype=float, order="C")  # a C-contiguous copy (_scatter_rows needs it)
    if v.ndim != 2 or v.shape[1] < 2:
        raise InvalidArgumentError("v", f"array of shape {v.shape}", "shape (N, d), d >= 2")
    angular = _check_angular(angular)
    pairs = np.asarray(pairs)
    _check_events(np.zeros(v.shape[0]), pairs, restitution)
    k = (len(pairs),)
    if v.shape[1] == 2:
        bad = draws.sine is None or np.shape(draws.sine) != k
    else:
        bad = (draws.z is None or draws.z.shape != (len(pairs), v.shape[1])) or (
            angular == "hard" and (draws.eta is None or draws.eta.shape != k)
        )
    if bad:
        raise InvalidArgumentError("draws", "arrays of other shapes", "one draw per event")
    return v, pairs, p, angular


def collide_in_order_vectors(v, pairs, restitution, draws: AngularDraws, angular="uniform"):
    """Fast path in d dimensions: apply the events ``pairs[k]`` with angular ``draws`` row k, in
    time order k = 0, 1, …, to a copy of ``v`` (N, d); returns the new velocities.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``, d ≥ 2; not modified (a copy is used).
    pairs : array_like of int
        The events in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].
    draws : AngularDraws
        The angular variables of the K events (:func:`draw_angles`), row k for event k.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``, the law of the collision direction.

    Returns
    -------
    numpy.ndarray
        The velocities after the K events, shape ``(N, d)``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``v``, ``pairs``, ``restitution``, ``angular`` or ``draws`` when out of domain
        or of the wrong shape.
    """
    v, pairs, p, angular = _check_vector_events(v, pairs, restitution, draws, angular)
    k = len(pairs)
    reversed_pairs = np.ascontiguousarray(pairs[::-1], dtype=np.int32)
    reversed_draws = _subset(draws, np.arange(k - 1, -1, -1))
    first = np.empty(v.shape[0], dtype=np.int32)
    occurrence = np.arange(2 * k, dtype=np.int32)
    if v.shape[1] == 2:
        transfer = plane_transfer(reversed_draws.sine, p)
        _fire_rounds_plane(_as_complex(v), reversed_pairs, transfer, first, occurrence)
        return v

    def collide(w, fired, rows):
        _collide_events_vectors(w, fired, _subset(reversed_draws, rows), angular, p)

    _fire_rounds_with_rows(v, reversed_pairs, first, occurrence, collide)
    return v


def collide_sequential_vectors(v, pairs, restitution, draws: AngularDraws, angular="uniform"):
    """Reference: a Python loop over the events in time order, one event at a time.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N, d)``, d ≥ 2; not modified (a copy is used).
    pairs : array_like of int
        The events in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].
    draws : AngularDraws
        The angular variables of the K events (:func:`draw_angles`), row k for event k.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``, the law of the collision direction.

    Returns
    -------
    numpy.ndarray
        The velocities after the K events, shape ``(N, d)``.

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`collide_in_order_vectors`.
    """
    v, pairs, p, angular = _check_vector_events(v, pairs, restitution, draws, angular)
    if v.shape[1] == 2:
        w = _as_complex(v)
        for k, (a, b) in enumerate(pairs.astype(np.intp)):
            pair = w[[a, b]]
            collide_complex(pair[0:1], pair[1:2], plane_transfer(draws.sine[k : k + 1], p))
            w[[a, b]] = pair
        return v
    for k, (a, b) in enumerate(pairs.astype(np.intp)):
        row = np.array([k], dtype=np.intp)
        _collide_events_vectors(v, np.array([a, b]), _subset(draws, row), angular, p)
    return v


def _as_complex(v: np.ndarray) -> np.ndarray:
    """The (N,) complex128 view v_x + i v_y of a C-contiguous (N, 2) float array."""
    return v.view(np.complex128).reshape(-1)


def _check_angular(angular) -> str:
    return check_choice(angular, "angular", ANGULAR_MODELS)


def _is_grid_point(t: float, step: float) -> bool:
    return t > 0.0 and t % step == 0.0


def _check_events(v, pairs, restitution):
    p = transfer_fraction(restitution)
    v = np.array(v, dtype=float)  # a copy
    pairs = np.asarray(pairs)
    if pairs.ndim != 2 or pairs.shape[1] != 2:
        raise InvalidArgumentError("pairs", f"array of shape {pairs.shape}", "shape (K, 2)")
    if pairs.size and (
        pairs.min() < 0 or pairs.max() >= v.size or np.any(pairs[:, 0] == pairs[:, 1])
    ):
        raise InvalidArgumentError(
            "pairs", "out-of-range or i == j entries", f"pairs of 0..{v.size - 1}, i != j"
        )
    return v, pairs, p


def collide_in_order(v, pairs, restitution) -> np.ndarray:
    """Fast path: apply the collisions ``pairs[0], pairs[1], …`` (time order) to a copy of ``v``
    with the round-parallel scheme; returns the new velocities.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)``; not modified (a copy is used).
    pairs : array_like of int
        The collisions in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        The velocities after the K collisions, shape ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``pairs`` (wrong shape, out-of-range or i = j entries) or ``restitution``.
    """
    v, pairs, p = _check_events(v, pairs, restitution)
    reversed_pairs = np.ascontiguousarray(pairs[::-1], dtype=np.int32)
    first = np.empty(v.size, dtype=np.int32)
    occurrence = np.arange(2 * len(pairs), dtype=np.int32)
    _fire_rounds(v, reversed_pairs, p, first, occurrence)
    return v


def collide_sequential(v, pairs, restitution) -> np.ndarray:
    """Reference: a plain Python loop over ``pairs`` in time order, on a copy of ``v``.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)``; not modified (a copy is used).
    pairs : array_like of int
        The collisions in time order, shape ``(K, 2)``: particle indices (i, j), i ≠ j.
    restitution : float
        The restitution coefficient r ∈ [0, 1].

    Returns
    -------
    numpy.ndarray
        The velocities after the K collisions, shape ``(N,)``.

    Raises
    ------
    particles.InvalidArgumentError
        As :func:`collide_in_order`.
    """
    v, pairs, p = _check_events(v, pairs, restitution)
    out = v.tolist()
    for a, b in pairs.tolist():
        out[a], out[b] = collide_scalar(out[a], out[b], p)
    return np.array(out, dtype=float)


@dataclass(frozen=True)
class Ulam(EngineBase):
    """Exact vectorized Ulam engine with ``n`` ≥ 2 particles, restitution ``restitution`` ∈ [0, 1],
    initial law ``initial`` (a name of :mod:`particles.initial`).  Time is τ.

    ``dimension`` ∈ {1, 2, 3} (velocities (N,) in 1D, (N, d) otherwise), ``angular`` ∈
    {"uniform", "hard"} (the law of the collision direction n; irrelevant in 1D), ``driving``
    = D ≥ 0 (white-noise heating, 1D only).  With the defaults this is the 1D Ulam engine,
    unchanged.

    Finite-N identities (expectations, zero total momentum, which recentring keeps).  With
    Σ_i v_i = 0, the mean of |v_i − v_j|² over the N(N − 1) ordered pairs i ≠ j is
    2N/(N − 1) · E, E = (1/N)Σ|v_i|².  A collision changes Σ|v|² by
    −2δ·g + 2|δ|² = −2p(g·n)² + 2p²(g·n)² = −2pq (g·n)² (δ = p(g·n)n), and
    ⟨(g·n)²⟩ = ⟨η⟩|g|² for both angular models (η = (ĝ·n)²).  At N/2 collisions per unit τ:
    dE/dτ = −(N/2)(1/N) 2pq⟨η⟩ · 2N/(N − 1) · E = −Λ N/(N − 1) E, Λ = 2pq⟨η⟩.
    Driven 1D: the noise adds 2D(1 − 1/N) per unit τ to the centred energy, so the steady
    centred energy is D (N − 1)²/(pq N²).

    Parameters
    ----------
    n : int
        Number of particles N, 2 ≤ N ≤ 2³¹ − 1.
    restitution : float
        Restitution coefficient r ∈ [0, 1].
    initial : str, optional
        Name of the initial velocity law (default ``"gaussian"``; one with a sampler).
    dimension : int, optional
        1 (default), 2 or 3.
    angular : str, optional
        ``"uniform"`` (default) or ``"hard"``.
    driving : float, optional
        White-noise heating D ≥ 0 (default 0; 1D only).

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``n``, ``restitution``, ``initial`` (unknown, or without a sampler),
        ``dimension``, ``angular`` or ``driving`` (negative, or non-zero with dimension > 1).
    """

    n: int
    restitution: float
    initial: str = "gaussian"
    dimension: int = 1
    angular: str = "uniform"
    driving: float = 0.0
    name: ClassVar[str] = "ulam"
    #: The model's time: τ (N/2 collisions per unit on average).
    time_name: ClassVar[str] = "tau"

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        if self.n > 2**31 - 1:  # particle ids are int32 in the event arrays
            raise InvalidArgumentError("n", self.n, "an integer <= 2**31 - 1")
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", law.name, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        object.__setattr__(self, "dimension", check_dimension(self.dimension))
        _check_angular(self.angular)
        driving = check_nonnegative(self.driving, "driving")
        if driving > 0.0 and self.dimension != 1:
            raise InvalidArgumentError("driving", self.driving, "0 when dimension > 1")
        object.__setattr__(self, "driving", driving)

    @property
    def p(self) -> float:
        return transfer_fraction(self.restitution)

    @property
    def window(self) -> float:
        """τ-length of an event window (a power of two): about 2.5e4 events per window."""
        return _window_for(self.n)

    @property
    def stop_step(self) -> float:
        """Driver stops (progress, checkpoints) every max(4, window) in τ (a power of two).  Each
        ``advance`` copies the velocities (the previous state must survive Ctrl-C); stops 4 apart
        keep that copy below ~3% of the run time at N = 1e6."""
        return max(4.0, self.window)

    def to_dict(self) -> dict:
        """JSON-able parameters, recorded with every result.

        ``dimension``/``angular`` and ``driving`` appear only where they differ from the 1D
        defaults,
        so that the checkpoints of 1D runs keep their identity.

        Returns
        -------
        dict
            ``n``, ``restitution``, ``initial``, ``window`` and those optional keys.
        """
        out = {
            "n": self.n,
            "restitution": self.restitution,
            "initial": self.initial,
            "window": self.window,
        }
        # Only where they differ from the 1D defaults, so checkpoints of 0.1 runs still match.
        if self.dimension != 1:
            out.update(dimension=self.dimension, angular=self.angular)
        if self.driving != 0.0:
            out["driving"] = self.driving
        return out

    def initial_state(self, rng: np.random.Generator) -> UlamState:
        """The state at τ = 0: velocities from the law, each component drawn by
        :func:`particles.driver.initial_velocities`.

        Parameters
        ----------
        rng : numpy.random.Generator
            The random generator.

        Returns
        -------
        particles.UlamState
            The initial state, with no collisions.
        """
        if self.dimension == 1:
            return UlamState(0.0, initial_velocities(self.initial, self.n, rng), 0)
        columns = [initial_velocities(self.initial, self.n, rng) for _ in range(self.dimension)]
        return UlamState(0.0, np.stack(columns, axis=1), 0)

    def rebuild_state(self, arrays) -> UlamState:
        """Rebuild a checkpointed state (:meth:`UlamState.from_arrays` with this engine's N and d);
        :meth:`state_from_arrays` (of :class:`particles.driver.EngineBase`) calls it.

        Parameters
        ----------
        arrays : mapping
            The arrays of :meth:`UlamState.to_arrays`.

        Returns
        -------
        particles.UlamState
            The state.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, from :meth:`UlamState.from_arrays`.
        """
        return UlamState.from_arrays(arrays, self.n, self.dimension)

    def memory_per_particle(self) -> float:
        """Working bytes per particle: 64 per velocity component (31 measured at N = 10⁶ in 1D,
        doubled).

        Returns
        -------
        float
            64 · d bytes.
        """
        return 64.0 * self.dimension

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """Pair collisions to τ = ``t_max``: N/2 per unit τ.

        Parameters
        ----------
        t_max : float
            The last requested τ.
        n_times : int
            The number of requested times (unused).

        Returns
        -------
        tuple of (float, str)
            ``(N t_max / 2, "collisions")``.
        """
        return float(self.n) * t_max / 2.0, "collisions"

    def windows(self, start: float, until: float) -> list[tuple[float, float]]:
        """The event windows covering (start, until]: cut at multiples of ``window``.

        Parameters
        ----------
        start, until : float
            The τ interval.

        Returns
        -------
        list of tuple of float
            The consecutive windows ``(a, b)``, from ``start`` to ``until``.
        """
        cuts = [start]
        t = start
        while True:
            t = next_grid_point(t, self.window)
            if t >= until:
                break
            cuts.append(t)
        cuts.append(until)
        return list(zip(cuts[:-1], cuts[1:], strict=True))

    def advance(self, state: UlamState, until: float, rng: np.random.Generator) -> UlamState:
        """Exact dynamics from ``state.time`` to ``until`` (window by window).

        Parameters
        ----------
        state : particles.UlamState
            The state to advance (not modified).
        until : float
            The τ to reach, ≥ ``state.time``.
        rng : numpy.random.Generator
            Source of the event counts, pairs and angles.

        Returns
        -------
        particles.UlamState
            The state at ``until``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``until`` if it is before the state's time.
        """
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
        if self.dimension != 1:
            return self._advance_vectors(state, until, rng)
        if self.driving != 0.0:
            return self._advance_driven(state, until, rng)
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p = self.p
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                if occurrence.size < 2 * k:
                    occurrence = np.arange(
                        max(2 * k, int(1.25 * self.n * self.window) + 16), dtype=np.int32
                    )
                # The drawn pairs, read from last to first, are the window's events in order.
                _fire_rounds(v, _draw_pairs(rng, self.n, k), p, first, occurrence)
                collisions += k
            if _is_grid_point(b, self.stop_step):
                recentre(v)
        return UlamState(float(until), v, collisions)

    def _occurrences(self, occurrence: np.ndarray, k: int) -> np.ndarray:
        if occurrence.size < 2 * k:
            occurrence = np.arange(
                max(2 * k, int(1.25 * self.n * self.window) + 16), dtype=np.int32
            )
        return occurrence

    def _advance_vectors(self, state: UlamState, until: float, rng) -> UlamState:
        """d ≥ 2: per window the Poisson count, the pairs, then the angular draws."""
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p, angular = self.p, self.angular
        plane = _as_complex(v) if self.dimension == 2 else None  # a view: v changes with it
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                occurrence = self._occurrences(occurrence, k)
                pairs = _draw_pairs(rng, self.n, k)  # row 0 is the window's last event
                draws = draw_angles(rng, k, self.dimension, angular)
                if plane is not None:
                    transfer = plane_transfer(draws.sine, p)
                    _fire_rounds_plane(plane, pairs, transfer, first, occurrence)
                else:

                    def collide(w, fired, rows, draws=draws):
                        _collide_events_vectors(w, fired, _subset(draws, rows), angular, p)

                    _fire_rounds_with_rows(v, pairs, first, occurrence, collide)
                collisions += k
            if _is_grid_point(b, self.stop_step):
                recentre(v)
        return UlamState(float(until), v, collisions)

    def _advance_driven(self, state: UlamState, until: float, rng) -> UlamState:
        """Driven 1D: per window the Poisson count, the pairs, the sorted event times, two
        normals per event; kicks of variance 2DΔτ since each particle's previous kick."""
        v = state.velocities.copy()
        collisions = int(state.collisions)
        p = self.p
        two_d = 2.0 * self.driving
        last = np.full(self.n, float(state.time))
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.empty(0, dtype=np.int32)
        for a, b in self.windows(state.time, until):
            k = int(rng.poisson(0.5 * self.n * (b - a)))
            if k:
                occurrence = self._occurrences(occurrence, k)
                pairs = _draw_pairs(rng, self.n, k)  # row 0 is the window's last event
                times = np.sort(rng.uniform(a, b, k))[::-1]  # row order: latest first
                kicks = rng.standard_normal((k, 2))

                def collide(w, fired, rows, times=times, kicks=kicks):
                    ia, ib = fired[0::2], fired[1::2]
                    t = times[rows]
                    va = w[ia] + np.sqrt(two_d * (t - last[ia])) * kicks[rows, 0]
                    vb = w[ib] + np.sqrt(two_d * (t - last[ib])) * kicks[rows, 1]
                    last[ia] = t
                    last[ib] = t
                    collide_arrays(va, vb, p)
                    w[ia] = va
                    w[ib] = vb

                _fire_rounds_with_rows(v, pairs, first, occurrence, collide)
                collisions += k
            if _is_grid_point(b, self.stop_step):  # bring every particle to b, then recentre
                v += np.sqrt(two_d * (b - last)) * rng.standard_normal(self.n)
                last[:] = b
                recentre(v)
        if np.any(last < until):
            v += np.sqrt(two_d * (float(until) - last)) * rng.standard_normal(self.n)
        return UlamState(float(until), v, collisions)


@dataclass(frozen=True)
class UlamReference(Ulam):
    """Sequential reference of the same model (for tests): a Python loop drawing exponential
    waiting times of rate N/2 and one random pair per collision.  Memorylessness makes stopping
    at ``until`` and redrawing the next waiting time exact.

    Parameters
    ----------
    n, restitution, initial, dimension, angular, driving
        As for :class:`Ulam`.
    """

    name: ClassVar[str] = "ulam-reference"

    def advance(self, state: UlamState, until: float, rng: np.random.Generator) -> UlamState:
        """One collision at a time, at exponential waiting times of rate N/2 (τ units).

        Parameters
        ----------
        state : particles.UlamState
            The state to advance (not modified).
        until : float
            The τ to reach.
        rng : numpy.random.Generator
            Source of the waiting times and pairs.

        Returns
        -------
        particles.UlamState
            The state at ``until``.
        """
        if self.dimension != 1 or self.driving != 0.0:
            return self._advance_general(state, until, rng)
        v = state.velocities.tolist()
        n, p = self.n, self.p
        t = state.time
        collisions = int(state.collisions)
        mean_wait = 2.0 / n
        step = self.stop_step
        grid = next_grid_point(t, step)  # the next recentring point after the start

        def recentre_list(values):
            arr = np.array(values)
            recentre(arr)
            return arr.tolist()

        while True:
            t += rng.exponential(mean_wait)
            while grid <= until and grid <= t:  # recentre before the events after a grid point
                v = recentre_list(v)
                grid = next_grid_point(grid, step)
            if t >= until:
                break
            i = int(rng.integers(n))
            j = int(rng.integers(n - 1))
            j += j >= i
            v[i], v[j] = collide_scalar(v[i], v[j], p)
            collisions += 1
        return UlamState(float(until), np.array(v), collisions)

    def _advance_general(self, state: UlamState, until: float, rng) -> UlamState:
        """Independent reference for d ≥ 2 and for driving: one event at a time; "hard"
        directions by rejection (n uniform, accepted with probability |ĝ·n|); the noise is
        applied to every particle over each waiting time (kicks of variance 2DΔτ)."""
        n, p = self.n, self.p
        v = np.array(state.velocities, dtype=float, copy=True)
        vector = v.ndim == 2
        t = float(state.time)
        collisions = int(state.collisions)
        step = self.stop_step
        grid = next_grid_point(t, step)
        sigma2 = 2.0 * self.driving

        def heat(dt):
            if sigma2 > 0.0 and dt > 0.0:
                v[:] += math.sqrt(sigma2 * dt) * rng.standard_normal(v.shape)

        while True:
            event = t + rng.exponential(2.0 / n)
            target = min(event, until)
            while grid <= target:
                heat(grid - t)
                t = grid
                recentre(v)
                grid = next_grid_point(grid, step)
            heat(target - t)
            t = target
            if t >= until:
                break
            i = int(rng.integers(n))
            j = int(rng.integers(n - 1))
            j += j >= i
            if not vector:
                v[i], v[j] = collide_scalar(float(v[i]), float(v[j]), p)
            else:
                g = v[i] - v[j]
                while True:
                    direction = rng.standard_normal(self.dimension)
                    direction /= np.linalg.norm(direction)
                    g_norm = np.linalg.norm(g)
                    if self.angular == "uniform" or g_norm == 0.0:
                        break
                    if rng.random() < abs(g @ direction) / g_norm:
                        break
                delta = p * (g @ direction) * direction
                v[i] -= delta
                v[j] += delta
            collisions += 1
        return UlamState(float(until), v, collisions)
