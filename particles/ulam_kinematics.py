"""Collision kinematics of the Ulam engine in d = 2 and 3: the angular variables of the events,
drawn in advance, the complex plane rule of d = 2 and the vector rule.

d dimensions, ``dimension`` = 2 or 3.  Velocities have shape (N, d).  A collision of
(a, b) with g = v_a − v_b and a unit vector n applies v_a' = v_a − p (g·n) n, v_b' = v_b + p (g·n) n
(:func:`collide_vectors`; operations in a fixed order, dot products summed column by column, so
the fast path and :func:`~particles.pair_schedule.collide_sequential_vectors` agree bit for bit).
The same window scheme is used; each event's angular variables are drawn with the window, in
advance (:func:`draw_angles`).

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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .validation import check_choice

__all__ = [
    "scatter_rows",
    "AngularDraws",
    "ANGULAR_MODELS",
    "draw_angles",
    "collision_directions",
    "collide_vectors",
    "collide_complex",
    "plane_transfer",
]

#: Angular models of the d-dimensional collisions (module docstring).
ANGULAR_MODELS = ("uniform", "hard")


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


def scatter_rows(v: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """``v[rows] = values`` for a C-contiguous (N, d) ``v`` and distinct ``rows``, through 1-D
    views: NumPy's row-wise fancy assignment on (N, d) arrays is ~50x slower (measured,
    N = 1e6, 2e4 rows).  d = 2 moves each row as one 16-byte complex; otherwise per component.

    Parameters
    ----------
    v : numpy.ndarray
        (N, d) float64 velocities, C-contiguous; written in place.
    rows : numpy.ndarray
        Distinct row indices (int).
    values : numpy.ndarray
        (len(rows), d) new velocities of those rows.
    """
    d = v.shape[1]
    if d == 2:
        v.view(np.complex128).reshape(-1)[rows] = values.view(np.complex128).reshape(-1)
        return
    flat = v.reshape(-1)
    base = rows * d
    for c in range(d):
        flat[base + c] = values[:, c]


def collide_pairs_vectors(v, fired, draws: AngularDraws, angular: str, p: float) -> None:
    """Collide the pairs ``fired`` = [a_0, b_0, a_1, b_1, …] (all distinct) with the events'
    ``draws``: one ``np.take`` gather and one scatter (row-wise fancy indexing of (N, d) arrays
    is slow, see :func:`scatter_rows`)."""
    vv = np.take(v, fired, axis=0)
    va, vb = vv[0::2], vv[1::2]
    n = collision_directions(va - vb, draws, angular)
    collide_vectors(va, vb, n, p)
    scatter_rows(v, fired, vv)


def subset_draws(draws: AngularDraws, rows) -> AngularDraws:
    """The draws of the events ``rows`` (in that order)."""
    def take(a, axis=None):
        return None if a is None else np.take(a, rows, axis=axis)

    return AngularDraws(take(draws.z, 0), take(draws.eta), take(draws.sine))


def as_complex(v: np.ndarray) -> np.ndarray:
    """The (N,) complex128 view v_x + i v_y of a C-contiguous (N, 2) float array."""
    return v.view(np.complex128).reshape(-1)


def check_angular(angular) -> str:
    """``angular`` when it is one of :data:`ANGULAR_MODELS` (else InvalidArgumentError)."""
    return check_choice(angular, "angular", ANGULAR_MODELS)
