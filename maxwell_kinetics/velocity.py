"""Velocity space: the density P(x) from the rescaled characteristic function G(q) (pyfftw).

Conventions
---------------------
P̂(k) = ∫ e^{ikv} P(v) dv, so the inverse transform carries e^{−iqx} and a factor 1/(2π):

    P(x) = (1/2π) ∫_{−∞}^{∞} e^{−iqx} G(q) dq = (1/π) Re ∫_0^∞ e^{−iqx} G(q) dq,

where the second form uses G(−q) = conj G(q) (P is real).  Callables ``G`` are only ever
evaluated at q ≥ 0; they may return real or complex values (NumPy arrays in, arrays out).

Grid of :func:`inverse_transform`
---------------------------------
q_j = j dq, j = −M/2 .. M/2 (M a power of two), with dq = 2π / L: the x grid is periodic with
period L = 2π/dq and spacing dx = L / M, and x_k = k dx for k = −M/2 .. M/2 − 1 is returned in
increasing order (the FFT output is ``fftshift``-ed).  M is the smallest power of two with
M dq / 2 ≥ ``q_max``; the actual cut-off q_c = M dq / 2 ≥ q_max is reported.  The trapezoid sum

    P_L(x_k) = (dq / 2π) Σ_j e^{−2πi jk/M} G(q_j)

is computed as a real inverse FFT (FFTW c2r, plans cached per M) of the half-spectrum
conj G(q_j), j = 0..M/2; the Nyquist term j = M/2 enters once with its real part only (FFTW's
c2r convention; it is G(q_c), negligible when G has decayed).

Error sources
-------------
* **Aliasing** (Poisson summation): the trapezoid sum is exactly Σ_n P(x + nL) of the truncated
  integrand, so a density with an x⁻⁴ tail (f(x) = 2/(π(1+x²)²), i.e. the |q|³ kink of f̂ at
  q = 0) is polluted by ≈ (2/π) Σ_{n≠0} (x + nL)⁻⁴.  The kink is not an extra error of the
  trapezoid rule: its whole effect is this alias of the tail.  With the default L = 1000 this is
  ≈ 1.3e-12 for |x| ≤ 10, but *relatively* it grows like (x/(L − x))⁴ toward x = L/2: fit tails
  well inside |x| ≪ L/2 (or use :func:`density_at`, which has no aliasing).
* **Truncation at q_c**: the omitted (1/π) Re ∫_{q_c}^∞ e^{−iqx} G dq.  Negligible for f̂ and the
  Gaussian (G(50) < 1e-20), but for a density with a jump (the ``asymmetric`` law, G ~ i e^{−iq}/q)
  it is ≈ 1/(π q_c |x − x_jump|) away from the jump, and O(1) Gibbs oscillations at the jump.
* Round-off ≈ 1e-16 · (1/π) ∫ |G| dq.

Isotropic laws in d dimensions: the speed (:func:`speed_density_at`)
----------------------------------------------------------------------
For an isotropic law in d = 1, 2, 3 with characteristic function E[e^{ik·v}] = Φ(|k|) (real),
the density of the vector v depends on |v| only and is the radial (Hankel) inverse transform

    f(v) = (2π)^{−d/2} v^{1−d/2} ∫_0^∞ k^{d/2} J_{d/2−1}(kv) Φ(k) dk,

that is (:func:`radial_density_at`)

    d = 1:  f(v) = (1/π)    ∫_0^∞ cos(kv) Φ(k) dk,
    d = 2:  f(v) = (1/2π)   ∫_0^∞ k J₀(kv) Φ(k) dk,
    d = 3:  f(v) = (1/2π²v) ∫_0^∞ k sin(kv) Φ(k) dk = (1/2π²) ∫_0^∞ k² j₀(kv) Φ(k) dk,

j₀(x) = sin x / x (so v = 0 needs no limit).  The density of the speed s = |v| is
P(s) = S_d s^{d−1} f(s) with S_1 = 2, S_2 = 2π, S_3 = 4π (∫_0^∞ P ds = 1).  Φ(|k|) restricted to
a line is the characteristic function of one Cartesian component, so the component density is
:func:`density_at` of the same Φ.  In d = 1 the speed |x| sees only the even part of the law,
whose characteristic function is Re G: the d = 1 formulas use Re G (so P(s) = f(s) + f(−s)
also for asymmetric laws), and so do d = 2, 3 (isotropic laws have real Φ).
Units are those of Φ's argument: for the solver's rescaled G(q) = Φ(q / v₀), v is the rescaled
velocity v / v₀ (unit variance per component, so ⟨s²⟩ = d).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pyfftw
import pyfftw.builders
from scipy.special import j0 as bessel_j0

from particles.validation import InvalidArgumentError, check_count, check_positive

__all__ = [
    "MAX_QUADRATURE_NODES",
    "check_quadrature",
    "quadrature_nodes",
    "inverse_transform",
    "density_at",
    "invert",
    "cut_at",
    "tail_exponent",
    "radial_density_at",
    "speed_density_at",
]

_PLANS: dict[int, pyfftw.FFTW] = {}


def _irfft_plan(m: int) -> pyfftw.FFTW:
    plan = _PLANS.get(m)
    if plan is None:
        buf = pyfftw.empty_aligned(m // 2 + 1, dtype="complex128")
        plan = pyfftw.builders.irfft(buf, n=m, planner_effort="FFTW_ESTIMATE", threads=1)
        _PLANS[m] = plan
    return plan


#: Most Gauss–Legendre nodes of one quadrature of :func:`density_at` or
#: :func:`radial_density_at` (2**24: about 2.7 GB at :data:`BYTES_PER_NODE`).  The panels have
#: width π / max|x|, so the node count grows like q_max · max|x| · nodes_per_panel / π: with the
#: solver's q_max ≈ 35 and 16 nodes per panel, |x| up to about 9e4.  Far beyond that the density
#: is below the round-off of the transform anyway (a relative error growing like 1/P).
MAX_QUADRATURE_NODES = 2**24

#: Seconds per quadrature node and value asked for of :func:`density_at` and
#: :func:`radial_density_at` (a complex exponential or a cosine and a product each; measured
#: for density_at on one core: 4.0e-8 s with 2·10⁵ values and 1072 nodes, and with 2·10⁴ values
#: and 8448 nodes; about 1e-7 on a loaded machine).
SECONDS_PER_NODE_VALUE = 4e-8
#: A density estimated to take longer than this (one day) is refused before any work.
MAX_QUADRATURE_SECONDS = 86400.0
#: Peak bytes per quadrature node when G is a :class:`~maxwell_kinetics.solution.Solution`'s
#: interpolant (measured with tracemalloc: 155 for 3.4e5 and 1.3e6 nodes).
BYTES_PER_NODE = 160.0


def quadrature_nodes(q_max: float, v_max: float, nodes_per_panel: int = 16,
                     radial: bool = False) -> float:
    """Number of Gauss–Legendre nodes of :func:`density_at` (``radial`` False) or
    :func:`radial_density_at` (True) for a largest |x| of ``v_max``, as a float (inf for an
    infinite one), computed without building anything.

    Parameters
    ----------
    q_max : float
        Cut-off of the q integral.
    v_max : float
        Largest |x| (or speed) asked for.
    nodes_per_panel : int, default 16
        Gauss–Legendre points per panel.
    radial : bool, default False
        Count the 3 extra panels of the radial transform.

    Returns
    -------
    float
    """
    width = min(0.5, math.pi / max(1.0, float(v_max)))
    if width == 0.0:
        return math.inf
    panels = float(q_max) / width
    panels = math.ceil(panels) if math.isfinite(panels) else panels
    return (panels + (3 if radial else 0)) * float(nodes_per_panel)


def check_quadrature(q_max: float, values, name: str, nodes_per_panel: int = 16,
                     radial: bool = False, shown=None) -> float:
    """Refuse, before any work, a density whose quadrature would exceed
    :data:`MAX_QUADRATURE_NODES` nodes or the memory available, or take more than
    :data:`MAX_QUADRATURE_SECONDS` for all the values asked for (:data:`SECONDS_PER_NODE_VALUE`
    per node and value): InvalidArgumentError naming ``name`` (the caller's argument), with the
    largest value or count accepted.  Returns the node count.

    Parameters
    ----------
    q_max : float
        Cut-off of the q integral.
    values : numpy.ndarray
        The finite velocities or speeds asked for.
    name : str
        The argument to name in the error.
    nodes_per_panel : int, default 16
        Gauss–Legendre points per panel.
    radial : bool, default False
        :func:`radial_density_at` (3 more panels).
    shown : object, optional
        The value to show in the error (default: the largest |value|).

    Returns
    -------
    float
        The number of nodes.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``name``, when the quadrature is too large.
    """
    from particles.budget import available_memory, format_bytes

    v_max = float(np.max(np.abs(values), initial=0.0))
    nodes = quadrature_nodes(q_max, v_max, nodes_per_panel, radial)
    limit = min(float(MAX_QUADRATURE_NODES), available_memory() / BYTES_PER_NODE)
    if not nodes <= limit:
        panels = limit / float(nodes_per_panel) - (3 if radial else 0)
        largest = math.pi * max(panels - 1.0, 1.0) / float(q_max)
        raise InvalidArgumentError(
            name, v_max if shown is None else shown,
            f"values with |{name}| <= {largest:.3g}: the quadrature of the inverse transform "
            f"has panels of width pi/max|{name}| up to q_max = {float(q_max):.4g}, "
            f"{nodes:.3g} nodes here (about {format_bytes(nodes * BYTES_PER_NODE)}), at most "
            f"{limit:.3g}",
        )
    count = max(1, int(np.size(values)))
    seconds = SECONDS_PER_NODE_VALUE * nodes * count
    if not seconds <= MAX_QUADRATURE_SECONDS:
        most = MAX_QUADRATURE_SECONDS / (SECONDS_PER_NODE_VALUE * nodes)
        raise InvalidArgumentError(
            name, f"{count} values up to |{name}| = {v_max:.3g}",
            f"at most {most:.3g} values at this largest |{name}|: the quadrature has "
            f"{nodes:.3g} nodes, about {SECONDS_PER_NODE_VALUE:.2g} s per node and value, "
            f"{seconds / 3600.0:.3g} h here, at most one day (ask in parts)",
        )
    return nodes


def _evaluate(G: Callable, q: np.ndarray) -> np.ndarray:
    if not callable(G):
        raise InvalidArgumentError("G", G, "a callable G(q) of an array of q >= 0")
    try:
        values = np.asarray(G(q), dtype=complex)
        if values.shape != q.shape:
            values = np.broadcast_to(values, q.shape).astype(complex)
    except (TypeError, ValueError):  # a string, a wrong shape: not one number per q
        raise InvalidArgumentError("G", G, "a callable returning one number G(q) per q (an "
                                   "array of the shape of q, or a scalar)") from None
    if not np.all(np.isfinite(values)):
        raise InvalidArgumentError("G", G, "finite values G(q) for q >= 0")
    return values


def inverse_transform(
    G: Callable, q_max: float = 50.0, period: float = 1000.0
) -> tuple[np.ndarray, np.ndarray]:
    """P(x) = (1/2π) ∫ e^{−iqx} G(q) dq on the periodic FFT grid described in the module docstring.

    ``q_max`` is the smallest cut-off accepted, ``period`` = L = 2π/dq the period of the x grid.
    Returns ``(x, P)`` with x increasing from −L/2 to L/2 − dx, dx = L/M.  The sum is a real
    inverse FFT (FFTW c2r through pyfftw) of conj G on q_j = j dq, scaled by M dq / 2π.

    Parameters
    ----------
    G : callable
        The rescaled characteristic function G(q) (q = k·v0, P̂(k) = ∫ e^{ikv} P(v) dv),
        called on an array of q ≥ 0; real or complex values.
    q_max : float, default 50.0
        Smallest cut-off accepted (> 0); the actual one is M dq / 2 ≥ q_max.
    period : float, default 1000.0
        Period L of the x grid (> 0); sets dq = 2π / L and the aliasing error.

    Returns
    -------
    x : numpy.ndarray
        Shape (M,): rescaled velocities x = v / v0, increasing.
    P : numpy.ndarray
        Shape (M,): the density at ``x`` (periodised: Σ_n P(x + nL)).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``q_max`` or ``period`` is not positive, if M would exceed 2**24 (naming ``q_max``),
        if ``period`` is below 16π/q_max (fewer than 8 nodes of q below q_max), or if ``G`` is
        not callable or does not return one finite value per q.
    """
    q_max = check_positive(q_max, "q_max")
    period = check_positive(period, "period")
    dq = 2.0 * math.pi / period
    m = 2 ** max(4, math.ceil(math.log2(2.0 * q_max / dq)))
    if m > 2**24:
        raise InvalidArgumentError(
            "q_max", q_max, f"q_max * period / pi <= 2**24 (got {q_max * period / math.pi:.3g})"
        )
    if not q_max * period / math.pi >= 16.0:  # else no node of q inside [0, q_max] but 0
        raise InvalidArgumentError("period", period, f"a period >= 16 pi / q_max = "
                                   f"{16.0 * math.pi / q_max:.3g} (at least 8 nodes of q in "
                                   "[0, q_max])")
    q = dq * np.arange(m // 2 + 1)
    half = np.conj(_evaluate(G, q))
    plan = _irfft_plan(m)
    # irfft computes (1/M) Σ_j X_j e^{+2πijk/M} over the Hermitian extension of X: with
    # X_j = conj G(q_j) this equals (1/M) Σ_j G(q_j) e^{−2πijk/M} (a real number).
    P = np.array(plan(half), copy=True) * (m * dq / (2.0 * math.pi))
    x = (period / m) * (np.arange(m) - m // 2)
    return x, np.fft.fftshift(P)


def density_at(G: Callable, x, q_max: float = 50.0, nodes_per_panel: int = 16) -> np.ndarray:
    """P(x) = (1/π) Re ∫_0^{q_max} e^{−iqx} G(q) dq by composite Gauss–Legendre quadrature.

    No aliasing (use it for tails); the kink of G at q = 0 sits at the end of the integration
    range, so it costs no accuracy.  Panels have width ≤ min(1/2, π / max|x|) so that every
    panel sees at most half an oscillation of e^{−iqx}; ``nodes_per_panel`` Gauss points each.
    The only errors are the truncation at ``q_max`` (see the module docstring) and round-off.

    Parameters
    ----------
    G : callable
        The rescaled characteristic function G(q) (q = k·v0, P̂(k) = ∫ e^{ikv} P(v) dv),
        called on an array of q ≥ 0; real or complex values.
    x : array_like
        Finite rescaled velocities x = v / v0 (any shape).
    q_max : float, default 50.0
        Cut-off of the q integral (> 0).
    nodes_per_panel : int, default 16
        Gauss–Legendre points per panel.

    Returns
    -------
    numpy.ndarray
        P(x), float, of the shape of ``x``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``q_max`` is not positive, ``nodes_per_panel`` is not a count >= 1, ``x`` is not
        finite or so large (or so many values) that the quadrature would exceed
        :data:`MAX_QUADRATURE_NODES` nodes, the memory available or one day
        (:func:`check_quadrature`, naming ``x``), or ``G`` is not
        callable or returns non-finite values.
    """
    q_max = check_positive(q_max, "q_max")
    npp = check_count(nodes_per_panel, "nodes_per_panel", 1)
    x = real_array(x, "x", "an array of finite real velocities")
    if not np.all(np.isfinite(x)):
        raise InvalidArgumentError("x", x.ravel()[~np.isfinite(x.ravel())][:3].tolist(),
                                   "finite velocities")
    check_quadrature(q_max, x, "x", npp)
    xf = x.ravel()
    width = min(0.5, math.pi / max(1.0, float(np.max(np.abs(xf), initial=0.0))))
    panels = math.ceil(q_max / width)
    t, w = np.polynomial.legendre.leggauss(npp)
    edges = np.linspace(0.0, q_max, panels + 1)
    half = 0.5 * np.diff(edges)
    q = (edges[:-1, None] + half[:, None] * (t[None, :] + 1.0)).ravel()
    wq = (half[:, None] * w[None, :]).ravel() * _evaluate(G, q)
    out = np.empty(xf.shape)
    chunk = max(1, 2_000_000 // len(q))
    for i in range(0, len(xf), chunk):
        xs = xf[i : i + chunk]
        out[i : i + chunk] = (np.exp(-1j * np.outer(xs, q)) @ wq).real / math.pi
    return out.reshape(x.shape)


def tail_exponent(x, P, window: tuple[float, float]) -> float:
    """Least-squares slope of ln P against ln x over the points with window[0] ≤ x ≤ window[1].

    For the scaling solution the local slope is −4x²/(1 + x²) (−3.96 at x = 10, −3.9996 at
    x = 100), so a fit over a finite window returns slightly less than 4 in magnitude.

    Parameters
    ----------
    x : array_like
        Rescaled velocities.
    P : array_like
        Density at ``x`` (same shape), positive in the window.
    window : tuple of float
        (x_lo, x_hi) with 0 < x_lo < x_hi < inf.

    Returns
    -------
    float
        The fitted slope d ln P / d ln x (≈ −4 for the x⁻⁴ tail of the scaling solution).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``P`` if its shape differs from that of ``x`` or it is not positive in the
        window; naming ``window`` if it is not a pair 0 < x_lo < x_hi < inf or holds fewer
        than 2 points.
    """
    x = np.asarray(x, dtype=float)
    P = np.asarray(P, dtype=float)
    if x.shape != P.shape:
        raise InvalidArgumentError("P", f"shape {P.shape}", f"the shape of x, {x.shape}")
    try:
        lo, hi = (float(v) for v in window)
    except (TypeError, ValueError):
        raise InvalidArgumentError("window", window, "a pair (x_lo, x_hi)") from None
    if not (0.0 < lo < hi and math.isfinite(hi)):
        raise InvalidArgumentError("window", window, "0 < x_lo < x_hi < inf")
    sel = (x >= lo) & (x <= hi)
    if np.count_nonzero(sel) < 2:
        raise InvalidArgumentError("window", window, "a window containing at least 2 grid points")
    if np.any(P[sel] <= 0.0):
        raise InvalidArgumentError("P", "non-positive values in the window", "P > 0 to fit ln P")
    slope, _ = np.polyfit(np.log(x[sel]), np.log(P[sel]), 1)
    return float(slope)


def cut_at(G: Callable, q_max: float) -> Callable:
    """``G`` cut at the grid's end: a callable equal to ``G(q)`` where |q| ≤ ``q_max`` and 0
    beyond (complex values), ``G`` called on the q inside only.

    Parameters
    ----------
    G : callable
        A characteristic function G(q) on |q| ≤ ``q_max``.
    q_max : float
        The cut.

    Returns
    -------
    callable
        q ↦ G(q) inside the cut, 0 beyond, as a complex array of the shape of q.
    """
    def cut(q):
        q = np.asarray(q, dtype=float)
        out = np.zeros(q.shape, dtype=complex)
        inside = np.abs(q) <= q_max
        out[inside] = G(q[inside])
        return out

    return cut


def invert(
    G: Callable, q_max: float = 50.0, x=None, period: float = 1000.0
) -> tuple[np.ndarray, np.ndarray]:
    """Density of x = v / v0 from G: ``(x, P)``.

    ``x=None``: the FFT grid of :func:`inverse_transform` (cut-off ≥ ``q_max``, period
    ``period``).  Otherwise P at the given x by :func:`density_at` (no aliasing, cut-off exactly
    ``q_max``), returned as ``(x, P)`` with x as a float array.

    Parameters
    ----------
    G : callable
        The rescaled characteristic function G(q) (q = k·v0, P̂(k) = ∫ e^{ikv} P(v) dv),
        called on an array of q ≥ 0; real or complex values.
    q_max : float, default 50.0
        Cut-off of the q integral.
    x : array_like, optional
        Rescaled velocities at which to evaluate; None for the FFT grid.
    period : float, default 1000.0
        Period of the FFT grid (used only when ``x`` is None).

    Returns
    -------
    x, P : numpy.ndarray
        The velocities and the density there.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For invalid arguments (from :func:`inverse_transform` or :func:`density_at`).
    """
    if x is None:
        return inverse_transform(G, q_max=q_max, period=period)
    x = real_array(x, "x", "an array of finite real velocities")
    return x, density_at(G, x, q_max=q_max)


#: Surface of the unit sphere in d = 1, 2, 3 (the "sphere" of d = 1 is the two points ±1).
_SPHERE = {1: 2.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}


def real_array(values, name: str, expected: str) -> np.ndarray:
    """``values`` as a float array, refusing (InvalidArgumentError naming ``name``) booleans,
    complex numbers, strings and ragged or non-numeric input, which ``np.asarray(...,
    dtype=float)`` would turn into numbers (True → 1.0, "5" → 5.0) or a raw TypeError."""
    if isinstance(values, np.ndarray) and values.dtype.kind in "iuf":
        return values.astype(float)
    try:
        raw = np.asarray(values, dtype=object)
    except (TypeError, ValueError):
        raise InvalidArgumentError(name, values, expected) from None
    for item in raw.ravel():  # a True in a list of floats would become 1.0
        if isinstance(item, (bool, np.bool_)) or not isinstance(item, (int, float, np.integer,
                                                                        np.floating)):
            raise InvalidArgumentError(name, values, expected)
    return raw.astype(float)


def check_speeds(s, name: str) -> np.ndarray:
    """Speeds as a float array: finite and ≥ 0, or InvalidArgumentError naming ``name``
    (also for booleans, complex numbers and strings)."""
    out = real_array(s, name, "an array of finite speeds >= 0")
    bad = ~(np.isfinite(out) & (out >= 0.0))
    if np.any(bad):
        raise InvalidArgumentError(name, out[bad].ravel()[:3].tolist(), "finite speeds >= 0")
    return out + 0.0  # -0.0 is the speed 0


def _check_dimension(dimension) -> int:
    if isinstance(dimension, bool) or dimension not in (1, 2, 3):
        raise InvalidArgumentError("dimension", dimension, "1, 2 or 3")
    return int(dimension)


def _radial_nodes(q_max: float, v_max: float, nodes_per_panel: int):
    """Gauss–Legendre nodes and weights on [0, q_max]: panels of width ≤ min(1/2, π/v_max)
    (at most half an oscillation of cos(kv), J₀(kv) or sin(kv) each), the first one split
    geometrically toward k = 0 (at widths w/64, w/16, w/4) for the non-analytic |k|^β terms
    of Φ there."""
    width = min(0.5, math.pi / max(1.0, v_max))
    panels = math.ceil(q_max / width)
    edges = np.linspace(0.0, q_max, panels + 1)
    first = edges[1]
    edges = np.concatenate([[0.0], first * np.array([1 / 64, 1 / 16, 1 / 4]), edges[1:]])
    t, w = np.polynomial.legendre.leggauss(nodes_per_panel)
    half = 0.5 * np.diff(edges)
    q = (edges[:-1, None] + half[:, None] * (t[None, :] + 1.0)).ravel()
    return q, (half[:, None] * w[None, :]).ravel()


def radial_density_at(G: Callable, v, dimension: int, q_max: float = 50.0,
                      nodes_per_panel: int = 16, *, name: str = "v") -> np.ndarray:
    """Density f(v) of an isotropic law in d = ``dimension`` at |v| = ``v`` (module docstring).

    ``G`` is the radial profile Φ(k), k ≥ 0 (its real part is used), cut at ``q_max``.
    Composite Gauss–Legendre quadrature as in :func:`density_at` (panels of width
    ≤ min(1/2, π / max v), no aliasing), with the first panel refined toward k = 0.  Errors: the
    truncation at ``q_max`` and round-off ≈ 1e-16 · c_d ∫ k^{d−1}|Φ| dk, which the oscillating
    integrand turns into a *relative* error growing with v like 1/f(v).

    Parameters
    ----------
    G : callable
        The radial profile Φ(k) of the characteristic function E[e^{ik·v}] = Φ(|k|), called
        on an array of k ≥ 0 (for the solver's G(q), v is the rescaled velocity).
    v : array_like
        Finite speeds |v| ≥ 0 (any shape).
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    q_max : float, default 50.0
        Cut-off of the k integral (> 0).
    nodes_per_panel : int, default 16
        Gauss–Legendre points per panel (≥ 1).
    name : str, default "v"
        The name under which a bad ``v`` is reported (the caller's argument).

    Returns
    -------
    numpy.ndarray
        f(v), the density of the vector v at |v| = ``v``, of the shape of ``v``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``dimension`` is not 1, 2 or 3, ``q_max`` is not positive, ``nodes_per_panel`` is
        not a count ≥ 1, ``v`` holds a negative or non-finite speed or one so large that the
        quadrature would exceed :data:`MAX_QUADRATURE_NODES` nodes, the memory available or
        (with the number of speeds) one day (:func:`check_quadrature`), or ``G`` is not
        callable or returns non-finite values.
    """
    d = _check_dimension(dimension)
    q_max = check_positive(q_max, "q_max")
    npp = check_count(nodes_per_panel, "nodes_per_panel", 1)
    v = check_speeds(v, name)
    check_quadrature(q_max, v, name, npp, radial=True)
    vf = v.ravel()
    q, wq = _radial_nodes(q_max, float(np.max(vf, initial=0.0)), npp)
    phi = _evaluate(G, q).real
    if d == 1:
        weights, norm = wq * phi, 1.0 / math.pi
    elif d == 2:
        weights, norm = wq * q * phi, 1.0 / (2.0 * math.pi)
    else:
        weights, norm = wq * q * q * phi, 1.0 / (2.0 * math.pi**2)
    out = np.empty(vf.shape)
    chunk = max(1, 2_000_000 // len(q))
    for i in range(0, len(vf), chunk):
        kv = np.outer(vf[i : i + chunk], q)
        if d == 1:
            kernel = np.cos(kv)
        elif d == 2:
            kernel = bessel_j0(kv)
        else:
            kernel = np.sinc(kv / math.pi)  # sin(kv)/(kv), = 1 at kv = 0
        out[i : i + chunk] = norm * (kernel @ weights)
    return out.reshape(v.shape)


def speed_density_at(G: Callable, s, dimension: int, q_max: float = 50.0,
                     nodes_per_panel: int = 16) -> np.ndarray:
    """Density P(s) = S_d s^{d−1} f(s) of the speed s = |v| of an isotropic law in d dimensions.

    f is :func:`radial_density_at` (same arguments and errors); S_1 = 2, S_2 = 2π, S_3 = 4π.
    In d = 3 this is P(s) = (2/π) s ∫_0^∞ k sin(ks) Φ(k) dk, in d = 2 P(s) = s ∫_0^∞ k J₀(ks)
    Φ(k) dk, in d = 1 P(s) = (2/π) ∫_0^∞ cos(ks) Re Φ(k) dk.  Speeds must be finite and ≥ 0.

    Parameters
    ----------
    G : callable
        The radial profile Φ(k), called on an array of k ≥ 0.
    s : array_like
        Finite speeds ≥ 0 (any shape).
    dimension : int
        Space dimension d ∈ {1, 2, 3}.
    q_max : float, default 50.0
        Cut-off of the k integral (> 0).
    nodes_per_panel : int, default 16
        Gauss–Legendre points per panel.

    Returns
    -------
    numpy.ndarray
        P(s), normalised so that ∫_0^∞ P ds = 1, of the shape of ``s``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For invalid arguments, as for :func:`radial_density_at` (a bad speed is reported as
        ``s``).
    """
    d = _check_dimension(dimension)
    s = check_speeds(s, "s")
    f = radial_density_at(G, s, d, q_max=q_max, nodes_per_panel=nodes_per_panel, name="s")
    return _SPHERE[d] * s ** (d - 1) * f
