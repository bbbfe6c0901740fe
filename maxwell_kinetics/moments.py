"""Moments of a solution from its characteristic function near q = 0.

G(q) = ⟨e^{i q v_x}⟩ is the characteristic function of one Cartesian component of the rescaled
velocity (unit variance per component).  Where G is analytic at q = 0 it is the series

    G(q) = Σ_n C_n q^{2n} (+ odd terms, whose real part vanishes),  ⟨v_x^{2n}⟩ = (−1)^n (2n)! C_n,

and in d dimensions the speed moments follow from the isotropy, ⟨v_x^{2n}⟩ = ⟨|v|^{2n}⟩ ⟨cos^{2n} θ⟩
with ⟨cos^{2n} θ⟩ = Γ(d/2) Γ(n + ½) / (√π Γ(n + d/2)) over the unit sphere (d = 2: (2n−1)!!/(2n)!!,
d = 3: 1/(2n + 1)).  ⟨v_x²⟩ = 1 by construction (the solver keeps G''(0) = −1 exactly).

The estimator reads w = Re G − e^{−q²/2} = Σ_{n≥2} (C_n − (−½)^n/n!) q^{2n}, which the solver
stores without cancellation, on the grid's small-q points.  Two things limit the range of q where
the series can be read:

* from above, the non-analytic |q|^{2s*} term of the scaling solution (1D: |q|³), which builds up
  in a boundary layer that moves toward q = 0 as τ grows (the rescaled moments of order ≥ 2s*
  grow exponentially in τ);
* from below, the end of the grid: an O(q²) artefact (about 4e-22 q² at the default grid) that
  dominates w/q⁴ as q → 0, and the relative rounding of w.

So the window is chosen per moment, automatically: w/q⁴ is fitted by least squares, on windows
of one decade in q stepped by a quarter decade, against c q^{−2} (the artefact) plus a polynomial
in q² of degree n_max (two terms more than the orders asked, to absorb the truncation).  Each
window gives an estimate of every C_n; the estimate kept for C_n is that of the window where it
agrees best with the two neighbouring windows, and that disagreement (the larger of the two) is
its error estimate.  The error estimate measures the choice of window only, not the solver's
discretisation error of G (at the default grid that is about 1e-8 relative for C₂ at τ ≤ 200).

A moment is reported as NaN, with its reason, when

* G is not analytic to that order: the local exponent of the residual
  |w − Σ_{m<n} (C_m − (−½)^m/m!) q^{2m}| on the best window is below 2n (the moment diverges,
  e.g. G = (1 + |q|) e^{−|q|} has w ∝ |q|³ and no fourth moment), or
* the windows do not agree to better than 1e-3 relative (the analytic range left between the
  non-analytic term and the grid's floor is too short to read the coefficient).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_dimension,
    check_real_array,
)

__all__ = ["Moments", "check_orders", "series_estimate", "sphere_cos_moment"]

#: Windows of one decade in q, stepped by a quarter decade.
WINDOW_DECADES = 1.0
WINDOW_STEP = 0.25
#: The highest q a window may reach (the series' truncation there is absorbed by the fit's extra
#: terms; beyond it, it is not).
Q_TOP = 0.3
#: The relative agreement between neighbouring windows above which a coefficient counts as not
#: resolved.
RESOLVED = 1e-3
#: How far below 2n the residual's local exponent may fall before the moment counts as divergent.
EXPONENT_SLACK = 0.2


def check_orders(orders) -> tuple[int, ...]:
    """Check moment orders: even positive integers.

    Parameters
    ----------
    orders : int or iterable of int
        One order or several (bools are refused).

    Returns
    -------
    tuple of int
        The orders, in the given sequence.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``orders``, if it is empty or holds anything but even positive integers.
    """
    values = (orders,) if np.isscalar(orders) else tuple(orders)
    ok = len(values) > 0 and all(
        not isinstance(n, bool) and isinstance(n, (int, np.integer)) and n > 0 and n % 2 == 0
        for n in values)
    if not ok:
        raise InvalidArgumentError("orders", orders, "even positive integers, e.g. (2, 4, 6)")
    return tuple(int(n) for n in values)


def sphere_cos_moment(dimension: int, n: int) -> float:
    """⟨cos^{2n} θ⟩ over the unit sphere in ``dimension`` d: Γ(d/2) Γ(n + ½)/(√π Γ(n + d/2)),
    evaluated as the product Π_{k<n} (2k + 1)/(d + 2k) (exactly 1 in d = 1, 1/d for n = 1).

    Parameters
    ----------
    dimension : int
        Space dimension d ≥ 1.
    n : int
        Half the order: the moment of cos^{2n} θ.

    Returns
    -------
    float
        ⟨cos^{2n} θ⟩, which links ⟨v_x^{2n}⟩ = ⟨|v|^{2n}⟩ ⟨cos^{2n} θ⟩ for an isotropic law.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``dimension`` is not an integer >= 1 or ``n`` not an integer >= 0 (booleans
        refused).
    """
    d = check_count(dimension, "dimension", 1)
    n = check_count(n, "n", 0)
    return math.prod((2 * k + 1) / (d + 2 * k) for k in range(n))


def _window_fits(q, w, n_max):
    """Least-squares coefficients a_2 .. a_{n_max+2} of w ≈ c q² + Σ a_m q^{2m} (fitted as w/q⁴)
    on every window: returns (lows, highs, a) with a of shape (windows, n_max + 1).

    The grid is geometric, so in the scaled variable x = q/q_top (q_top: the window's largest
    point) every window has the same points and one pseudo-inverse serves them all."""
    s = np.log(q)
    h = float(s[1] - s[0])
    if not np.allclose(np.diff(s), h, rtol=1e-9, atol=1e-12):
        raise InvalidArgumentError("q", "a non-geometric grid", "the solver's geometric grid")
    length = int(round(WINDOW_DECADES * math.log(10.0) / h)) + 1
    step = max(1, int(round(WINDOW_STEP * math.log(10.0) / h)))
    first = int(math.ceil(0.5 * math.log(10.0) / h))  # skip half a decade at the grid's start
    last = int(np.searchsorted(q, min(Q_TOP, float(q[-1])), side="right"))  # exclusive
    starts = np.arange(first, last - length + 1, step)
    if starts.size == 0 or length < n_max + 4:
        return np.empty(0), np.empty(0), np.empty((0, n_max + 1))
    x = np.exp(h * (np.arange(length) - (length - 1)))
    A = np.stack([x**-2.0] + [x ** (2.0 * k) for k in range(n_max + 1)], axis=1)
    pinv = np.linalg.pinv(A)
    y = w / q**4
    index = starts[:, None] + np.arange(length)[None, :]
    b = y[index] @ pinv.T  # (windows, columns)
    top = q[starts + length - 1]
    a = b[:, 1:] / top[:, None] ** (2.0 * np.arange(n_max + 1))[None, :]
    return q[starts], top, a


@dataclass(frozen=True)
class SeriesEstimate:
    """C_n (n = 2 .. n_max) of one G: ``values``, ``errors`` (absolute), ``windows`` (q_lo, q_hi
    per n) and ``reasons`` ("" where the value is a number, else why it is NaN)."""

    values: np.ndarray
    errors: np.ndarray
    windows: np.ndarray
    reasons: tuple[str, ...]


def series_estimate(q, w, n_max: int) -> SeriesEstimate:
    """Taylor coefficients C_2 .. C_{n_max} of G from w = Re G − e^{−q²/2}.

    G(q) = Σ_n C_n q^{2n} near q = 0, with q the rescaled wave number; the windowed least-squares
    method, the choice of window and the rules for NaN are those of the module docstring.

    Parameters
    ----------
    q : array_like
        The solver's geometric grid of rescaled wave numbers (increasing, q > 0).
    w : array_like
        Re G − e^{−q²/2} on ``q`` (stored without cancellation by the solver).
    n_max : int
        Highest index n of C_n to estimate (n_max ≥ 2).

    Returns
    -------
    SeriesEstimate
        ``values`` and absolute ``errors`` of C_n (n = 2 .. n_max; NaN where not resolved),
        ``windows`` (q_lo, q_hi per n) and ``reasons`` ("" for a number, else why it is NaN).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``q`` is not a geometric grid of finite q > 0 (at least two points), ``w`` is not one
        finite real value per point, or ``n_max`` is not an integer >= 2.
    """
    q, w = _grid_and_values(q, w, "w")
    n_max = check_count(n_max, "n_max", 2)
    lows, highs, fits = _window_fits(q, w, n_max)
    gauss = np.array([(-0.5) ** n / math.factorial(n) for n in range(2, n_max + 1)])
    m = n_max - 1
    values = np.full(m, np.nan)
    errors = np.full(m, np.nan)
    windows = np.full((m, 2), np.nan)
    reasons = ["the grid has too few points near q = 0 for any window"] * m
    if len(fits) < 3:
        return SeriesEstimate(values, errors, windows, tuple(reasons))
    a = fits[:, :m]  # (windows, m): a_2 .. a_{n_max}
    spread = np.maximum(np.abs(a[1:-1] - a[:-2]), np.abs(a[1:-1] - a[2:]))
    for j in range(m):
        n = j + 2
        i = int(np.nanargmin(spread[:, j])) + 1
        lo, hi = float(lows[i]), float(highs[i])
        c = a[i, j] + gauss[j]
        err = float(spread[i - 1, j])
        windows[j] = (lo, hi)
        beta = _residual_exponent(q, w, lo, hi, a[i, :j])
        if beta < 2 * n - EXPONENT_SLACK:
            reasons[j] = (f"not analytic to order {2 * n} on the resolved range: w minus the "
                          f"lower terms ∝ |q|^{beta:.2f} near q = 0, exponent below {2 * n} (the "
                          "moment diverges, or has grown beyond what the grid resolves: the "
                          "|q|^{2s*} term of the scaling solution)")
        elif not err <= RESOLVED * abs(c):
            reasons[j] = (f"not resolved: the windows' estimates of C_{n} disagree by "
                          f"{err / abs(c):.1e} relative (best window q in [{lo:.1e}, {hi:.1e}]); "
                          "the analytic range between the |q|^{2s*} term and the grid's floor "
                          "is too short")
        else:
            values[j], errors[j], reasons[j] = c, err, ""
    return SeriesEstimate(values, errors, windows, tuple(reasons))


def _grid_and_values(q, w, name: str):
    """The checked geometric grid q and values on it (one row, or rows of its length)."""
    q = check_real_array(q, "q", ndim=1, min_size=2)
    if np.any(q <= 0) or np.any(np.diff(q) <= 0):
        raise InvalidArgumentError("q", q.tolist()[:20], "the solver's increasing grid of q > 0")
    w = check_real_array(w, name)
    if w.ndim not in (1, 2) or w.shape[-1] != q.size:
        raise InvalidArgumentError(name, f"shape {w.shape}", f"{q.size} values per row, one "
                                   "per q")
    return q, w


def _residual_exponent(q, w, lo, hi, lower) -> float:
    """Least-squares slope of ln|w − Σ lower_m q^{2(m+2)}| against ln q on [lo, hi]."""
    sel = (q >= lo) & (q <= hi)
    qs = q[sel]
    r = w[sel] - sum(c * qs ** (2 * (k + 2)) for k, c in enumerate(lower))
    if np.any(r == 0):
        return math.inf
    lx, ly = np.log(qs), np.log(np.abs(r))
    lx = lx - lx.mean()
    return float(np.dot(lx, ly - ly.mean()) / np.dot(lx, lx))


@dataclass(frozen=True)
class Moments:
    """Moments of a kinetic result at its saved times, rescaled by the velocity scale of each
    time (the one moment type of :class:`maxwell_kinetics.kinetic_result.KineticResult`).

    Rescaled: v₀² is the per-component variance, so ⟨x²⟩ = 1 for x = v/v₀ and in d dimensions
    ⟨|v|²⟩/v₀² = d.  Produced by :meth:`maxwell_kinetics.solution.Solution.moments` (even
    orders read from G near q = 0, time τ, v₀ = e^{−Λτ/2}) and by
    :meth:`maxwell_kinetics.boltzmann_solution.BoltzmannSolution.moments` (central moments of
    any order k ≥ 0 summed on the velocity grid, time t, v₀ = √⟨(v − u)²⟩, ``errors`` 0).
    :meth:`raw` gives the moments in the result's own velocity units (``values`` × v₀^k).

    A ``Moments`` is not an array: indexing it, ``len``, iteration and ``numpy.asarray`` raise
    a TypeError that names ``values`` and :meth:`raw` (``BoltzmannSolution.moments`` returned
    an array of raw central moments before it returned a ``Moments``).

    Attributes
    ----------
    orders : tuple of int
        The orders n.
    times : numpy.ndarray
        The saved times of the rows, shape (T,), in the unit ``time_name`` names (the attribute
        ``tau`` reads them for a result in τ).
    dimension : int
        Space dimension d.
    values : numpy.ndarray
        Shape (T, len(orders)): ``values[k, j]`` = ⟨|v|^n⟩ / v₀^n for n = ``orders[j]`` at
        ``times[k]`` (d = 1: ⟨x^n⟩); NaN where not resolved.
    component : numpy.ndarray
        Same shape: ⟨v_x^n⟩/v₀^n of one Cartesian component (equal to ``values`` in d = 1).
    errors : numpy.ndarray
        Same shape: absolute error estimates of ``values`` (from the choice of window only; see
        the module docstring; 0 for a velocity-grid result, whose sums are exact on its grid).
    windows : numpy.ndarray
        Shape (T, len(orders), 2): the q window read for each value (NaN for order 2, which
        is exact, and for a velocity-grid result).
    reasons : tuple of tuple of str
        ``reasons[k][j]``: "" for a number, else why the value is NaN.
    time_name : str, default "tau"
        ``"tau"`` (collisions per particle) or ``"t"`` (physical time).
    scale : numpy.ndarray, optional
        v₀ at each row, shape (T,): the velocity scale the values are rescaled by (None when
        not known: :meth:`raw` then raises).
    """

    orders: tuple[int, ...]
    times: np.ndarray
    dimension: int
    values: np.ndarray
    component: np.ndarray
    errors: np.ndarray
    windows: np.ndarray
    reasons: tuple[tuple[str, ...], ...]
    time_name: str = "tau"
    scale: np.ndarray | None = None

    @property
    def tau(self) -> np.ndarray:
        """The saved τ of the rows (``times``), for moments of a result in τ.

        Raises
        ------
        AttributeError
            For moments of a result in physical time t (read ``times``).
        """
        if self.time_name != "tau":
            raise AttributeError(f"these moments are at physical times {self.time_name}, not "
                                 "collisions per particle tau: read .times")
        return self.times

    def raw(self) -> np.ndarray:
        """The moments in the result's velocity units: ``values[k, j] * scale[k]**n``.

        Returns
        -------
        numpy.ndarray
            Shape (T, len(orders)); for a :class:`BoltzmannSolution
            <maxwell_kinetics.boltzmann_solution.BoltzmannSolution>` the central moments
            ⟨(v − u)^n⟩ (initial ⟨v²⟩ = 1).

        Raises
        ------
        ValueError
            When ``scale`` is not known.
        """
        if self.scale is None:
            raise ValueError("these moments carry no velocity scale: no raw moments")
        return self.values * np.asarray(self.scale, dtype=float)[:, None] ** np.asarray(
            self.orders, dtype=float)

    def _not_an_array(self, *args):
        raise TypeError("Moments is not an array: read .values (rescaled by v0) or .raw() "
                        "(in the result's velocity units), shape (times, orders)")

    __getitem__ = __iter__ = __len__ = _not_an_array

    def __bool__(self) -> bool:
        return True

    def __array__(self, *args, **kwargs):
        self._not_an_array()

    def kurtosis(self) -> np.ndarray:
        """⟨|v|⁴⟩/⟨|v|²⟩² at each saved time (d = 1: ⟨x⁴⟩/⟨x²⟩², 3 for a Gaussian; d = 2: 2).

        Returns
        -------
        numpy.ndarray
            Shape (T,): ``values`` of order 4 divided by d² (NaN where that moment is).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``orders``, if 4 is not among them.
        """
        if 4 not in self.orders:
            raise InvalidArgumentError("orders", self.orders, "orders that include 4")
        four = self.values[:, self.orders.index(4)]
        return four / float(self.dimension) ** 2

    def to_dict(self) -> dict:
        """A JSON-able dict of the fields (NaN written as None).

        Returns
        -------
        dict
            Keys ``orders``, the time name (``tau`` or ``t``), ``dimension``, ``values``,
            ``component``, ``errors``, ``windows`` and ``reasons``, as nested lists.
        """
        def clean(a):
            return [None if not np.isfinite(x) else float(x) for x in np.ravel(a)]

        shape = self.values.shape
        return {
            "orders": list(self.orders),
            self.time_name: [float(t) for t in self.times],
            "dimension": self.dimension,
            "values": np.reshape(np.array(clean(self.values), dtype=object), shape).tolist(),
            "component": np.reshape(np.array(clean(self.component), dtype=object),
                                    shape).tolist(),
            "errors": np.reshape(np.array(clean(self.errors), dtype=object), shape).tolist(),
            "windows": np.reshape(np.array(clean(self.windows), dtype=object),
                                  self.windows.shape).tolist(),
            "reasons": [list(r) for r in self.reasons],
        }


def moments_of(q, w_rows, tau, dimension: int, orders, v0=None) -> Moments:
    """:class:`Moments` of the rows ``w_rows[k]`` = Re G − e^{−q²/2} at ``tau[k]`` (``v0``: the
    velocity scale at each, or None; the ``scale`` of the result).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``orders`` are not even positive integers, ``dimension`` is not 1, 2 or 3, ``q`` is
        not the solver's grid, or ``w_rows`` is not one finite row per time in ``tau``.
    """
    orders = check_orders(orders)
    d = check_dimension(dimension)
    q, w_rows = _grid_and_values(q, w_rows, "w_rows")
    tau = check_real_array(tau, "tau", ndim=1)
    if np.ndim(w_rows) != 2 or len(w_rows) != len(tau):
        raise InvalidArgumentError("w_rows", f"shape {np.shape(w_rows)}",
                                   f"one row per time ({len(tau)})")
    n_max = max(2, max(orders) // 2)
    T, K = len(tau), len(orders)
    values = np.full((T, K), np.nan)
    component = np.full((T, K), np.nan)
    errors = np.full((T, K), np.nan)
    windows = np.full((T, K, 2), np.nan)
    reasons = []
    for k in range(T):
        est = series_estimate(q, w_rows[k], n_max) if max(orders) > 2 else None
        row = []
        for j, order in enumerate(orders):
            n = order // 2
            scale = math.factorial(order) * (-1) ** n
            if n == 1:
                comp, err, why = 1.0, 0.0, ""
            else:
                comp = scale * est.values[n - 2]
                err = math.factorial(order) * est.errors[n - 2]
                why = est.reasons[n - 2]
                windows[k, j] = est.windows[n - 2]
            cos = sphere_cos_moment(d, n)
            component[k, j] = comp
            values[k, j] = comp / cos
            errors[k, j] = err / cos
            row.append(why)
        reasons.append(tuple(row))
    return Moments(orders, np.asarray(tau, dtype=float).copy(), d, values, component, errors,
                   windows, tuple(reasons), "tau",
                   None if v0 is None else np.asarray(v0, dtype=float))
