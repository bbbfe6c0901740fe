"""The result of :func:`maxwell_kinetics.solver.solve`: G(q, τ) on the grid at the saved τ
(:class:`Solution`, with its evaluation, distances to f̂, densities, moments, and its saved
form), and the time-integration settings it records (:class:`SolverOptions`).

Nothing here integrates: the module holds no JAX code at import, so a saved solution loads
without the solver.  The rescaled equation, the scheme and its conventions are described in
:mod:`maxwell_kinetics.solver`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from particles import persistence, validation
from particles.validation import InvalidArgumentError, check_positive, check_real, check_real_array

from .deviation import reference
from .exact import f_hat
from .grid import Resolution
from .kinetic_result import pick_time, plot_densities, time_by_keyword
from .model import MaxwellModel

__all__ = ["Solution", "SolverOptions"]


def _record_flag(meta: dict, key: str, default: bool) -> bool:
    """``meta[key]`` if it is a bool, ``default`` if absent; TypeError otherwise."""
    value = meta.get(key, default)
    if not isinstance(value, bool):
        raise TypeError(f"{key} is {value!r}, not true or false")
    return value


@dataclass(frozen=True)
class SolverOptions:
    """Time-integration settings of :func:`~maxwell_kinetics.solver.solve`.

    Attributes
    ----------
    rtol, atol : float, default 1e-11 and 1e-13
        Relative and absolute tolerances of diffrax's PID step-size controller (RMS norm over
        the grid), > 0; ``rtol`` < 1 too (a relative error of 1 or more controls nothing).
    window : float, default 2.0
        Target length in τ of one semi-Lagrangian window (rounded so that the grid moves by a
        whole number of cells), > 0.
    max_steps_per_window : int, default 100000
        Most ODE steps diffrax may take in one window.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If ``rtol``, ``atol`` or ``window`` is not a positive number, ``rtol`` or ``atol`` not
        below 1, or ``max_steps_per_window`` not an integer >= 1.
    """

    rtol: float = 1e-11
    atol: float = 1e-13
    window: float = 2.0
    max_steps_per_window: int = 100_000

    def __post_init__(self):
        if not check_positive(self.rtol, "rtol") < 1.0:
            raise InvalidArgumentError("rtol", self.rtol, "a relative tolerance in (0, 1)")
        if not check_positive(self.atol, "atol") < 1.0:  # G is O(1): atol >= 1 controls nothing
            raise InvalidArgumentError("atol", self.atol, "an absolute tolerance in (0, 1)")
        check_positive(self.window, "window")
        validation.check_count(self.max_steps_per_window, "max_steps_per_window", 1)


#: Version of the saved Solution format (2: particles.persistence, hashed; 1 still loads).
_SOLUTION_VERSION = 2


def deviation_from_f_hat(q: np.ndarray, m3: float) -> np.ndarray:
    """g(q) − f̂(q) without cancellation at small q (Taylor series of e^{−q²/2} − f̂ below 0.05)."""
    q = np.asarray(q, dtype=float)
    out = reference(q, m3).astype(complex) - f_hat(q)
    small = q < 0.05
    if np.any(small):
        nmax = 20
        # Taylor coefficients of e^{−q²/2} − (1 + q) e^{−q}; those of f̂ are (−1)^n (1 − n)/n!.
        diff = np.array([(-1) ** n * (n - 1) / math.factorial(n) for n in range(nmax)])
        for m in range(nmax // 2):
            diff[2 * m] += (-0.5) ** m / math.factorial(m)
        diff[:3] = 0.0  # identical through q²
        qs = q[small]
        out[small] = np.polynomial.polynomial.polyval(qs, diff) - 1j * (m3 / 6.0) * qs**3 * np.exp(
            -0.5 * qs * qs
        )
    return out



@dataclass(frozen=True)
class Solution:
    """G(q, τ) on the grid at the saved τ, with evaluation and diagnostics.

    ``G[k, j]`` is G(q_j, tau[k]) for the grid q_j = e^{s_min + j h} (q ≥ 0; G(−q) = conj G(q)).
    ``deviation[k, j]`` is G − f̂ at the same points, computed without the cancellation of
    G − f̂ ≈ (1 − q²/2) − (1 − q²/2) at small q (it is what :meth:`evaluate` interpolates and,
    for ``dimension`` 1, what the distances to f̂ use; they refuse ``dimension`` ≥ 2).
    G(q, τ) = P̂(q / v0(τ), τ) with P̂(k) = ∫ e^{ikv} P(v) dv, q = k·v0(τ); the properties
    ``q`` (the grid) and ``model`` (the :class:`~maxwell_kinetics.model.MaxwellModel`) are
    derived.  Returned by :func:`~maxwell_kinetics.solver.solve`; saved and loaded with
    :meth:`save` and :meth:`load`.

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1].
    initial : str
        Name of the initial law.
    resolution : maxwell_kinetics.grid.Resolution
        The q grid.
    tau : numpy.ndarray
        Saved collisions per particle τ, shape (T,).
    G : numpy.ndarray
        Complex, shape (T, n): G on the grid.
    deviation : numpy.ndarray
        Complex, shape (T, n): G − f̂ on the grid.
    skewness : float, default 0.0
        m₃ = ⟨x³⟩ of the initial law (conserved).
    options : SolverOptions
        The time-integration settings used.
    seconds : float, default 0.0
        Wall-clock time of the solve.
    dimension : int, default 1
        Space dimension d.
    angular : str, default "uniform"
        Angular model (d ≥ 2).
    angular_rule : str, default "accurate"
        The η rule of the solve (d = 1: exact, η ≡ 1).
    angular_nodes : int, default 1
        The ``angular_nodes`` of the solve, the scale of its η rule (d = 1: 1, η ≡ 1).
    builtin_law : bool, default True
        True when ``initial`` names the built-in law of :mod:`particles.initial` that was
        solved; False for a user's law (:func:`particles.initial.law_from_characteristic`),
        whatever its name, so that a user law is never matched to a built-in by name
        (:meth:`initial_law`).
    """

    restitution: float
    initial: str
    resolution: Resolution
    tau: np.ndarray
    G: np.ndarray = field(repr=False)
    deviation: np.ndarray = field(repr=False)
    skewness: float = 0.0
    options: SolverOptions = field(default_factory=SolverOptions)
    seconds: float = 0.0
    dimension: int = 1
    angular: str = "uniform"
    angular_rule: str = "accurate"  # the η rule of solve (d = 1: exact, η ≡ 1)
    angular_nodes: int = 1  # the scale of the η rule of solve (d = 1: 1, η ≡ 1)
    builtin_law: bool = True  # initial names the built-in law solved (False: a user's law)

    def __repr__(self) -> str:
        """One line: r, the law, d, the grid and the saved τ."""
        tau = np.asarray(self.tau)
        angular = "" if self.dimension == 1 else f", angular={self.angular!r}"
        return (f"Solution(restitution={self.restitution:g}, initial={self.initial!r}, "
                f"dimension={self.dimension}{angular}, resolution={self.resolution.name!r}, "
                f"{tau.size} times tau = {tau[0]:g}..{tau[-1]:g})")

    def initial_law(self):
        """The built-in initial law this solution started from, with its CDF and sampler, or
        None for a user's law (known by its characteristic function only, even when its name
        is a built-in one) and for a name that is no built-in law.

        Returns
        -------
        particles.initial.InitialLaw or None
            The law.
        """
        from particles.initial import LAWS

        return LAWS.get(self.initial) if self.builtin_law else None

    @property
    def times(self) -> np.ndarray:
        """The saved times (``tau``, collisions per particle) as a float array
        (:class:`~maxwell_kinetics.kinetic_result.KineticResult`)."""
        return np.asarray(self.tau, dtype=float)

    @property
    def time_name(self) -> str:
        """``"tau"``: the times are collisions per particle τ."""
        return "tau"

    @property
    def velocity_scale(self) -> np.ndarray:
        """v₀(τ) = e^{−Λτ/2} at each saved τ, the standard deviation of one component (unit
        initial variance; Λ = :meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`)."""
        rate = self.model.energy_rate(self.dimension, self.angular)
        return np.exp(-0.5 * rate * self.times)

    @property
    def energy(self) -> np.ndarray:
        """⟨|v|²⟩ = d v₀² = d e^{−Λτ} at each saved τ (unit initial variance per component)."""
        return self.dimension * self.velocity_scale**2

    @property
    def q(self) -> np.ndarray:
        """The grid's rescaled wave numbers q_j (``resolution.q``)."""
        return self.resolution.q

    @property
    def model(self) -> MaxwellModel:
        """The :class:`~maxwell_kinetics.model.MaxwellModel` of ``restitution``."""
        return MaxwellModel(self.restitution)

    def time_index(self, tau_index: int | None = None, tau: float | None = None) -> int:
        """The non-negative index of a saved time, chosen by index ``tau_index`` (negative
        counts from the end, as in Python) or by value ``tau`` (one of the saved times
        ``self.tau``, to a relative 1e-12); neither: the last time.  Every method of
        :class:`Solution` that takes ``tau_index`` also takes ``tau`` and resolves them here.

        Parameters
        ----------
        tau_index : int, optional
            Index into the saved times, −T ≤ tau_index < T.
        tau : float, optional
            A saved time τ.

        Returns
        -------
        int
            The index in [0, T).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``tau_index`` when it is not an integer (a bool included) or out of range,
            ``tau`` when it is not one of the
            saved times (they are listed), and ``tau`` when both are given.
        """
        n = len(self.tau)
        if tau is not None:
            if tau_index is not None:
                raise InvalidArgumentError("tau", tau, "either tau or tau_index, not both "
                                           f"(tau_index={tau_index!r} was given too)")
            saved = np.asarray(self.tau, dtype=float)
            shown = ", ".join(f"{t:g}" for t in saved)
            if len(shown) > 200:
                shown = shown[:200] + "..."
            if (isinstance(tau, (bool, np.bool_))
                    or not isinstance(tau, (int, float, np.integer, np.floating))
                    or not np.isfinite(float(tau))):
                raise InvalidArgumentError("tau", tau, f"one of the saved times: {shown}")
            match = np.flatnonzero(np.abs(saved - float(tau)) <= 1e-12 * np.abs(saved))
            if match.size == 0:
                raise InvalidArgumentError("tau", tau, f"one of the saved times: {shown}")
            return int(match[0])
        if tau_index is None:
            return n - 1
        if (isinstance(tau_index, (bool, np.bool_))
                or not isinstance(tau_index, (int, np.integer))):
            hint = (f" (a time goes by keyword: tau={tau_index!r})"  # BoltzmannSolution's slot
                    if isinstance(tau_index, (float, np.floating)) else "")
            raise InvalidArgumentError("tau_index", tau_index,
                                       f"an integer index into {n} saved times{hint}")
        if not -n <= tau_index < n:
            raise InvalidArgumentError("tau_index", tau_index, f"an index into {n} saved times")
        return tau_index % n

    def evaluate(self, q, tau_index: int | None = None, *, tau: float | None = None) -> np.ndarray:
        """G(q) at arbitrary real q, |q| ≤ q_max, by Lagrange interpolation in s = ln|q|.

        Inside the grid G = f̂ + (G − f̂), the deviation interpolated at O(h^order) accuracy;
        below q_min, G = g (the reference, exact to O(q³)).

        Parameters
        ----------
        q : array_like
            Real rescaled wave numbers q = k·v0(τ) with |q| ≤ q_max (any shape; negative q
            gives conj G(|q|)).
        tau_index : int, optional
            Index of the saved τ (negative counts from the end); default the last.
        tau : float, optional
            The saved τ itself, instead of ``tau_index`` (:meth:`time_index`).

        Returns
        -------
        numpy.ndarray
            Complex G(q), of the shape of ``q``.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``q`` if a value is not a finite real number or beyond the grid's end, or
            ``tau_index`` if it is out of range.
        """
        grid = self.resolution
        q = check_real_array(q, "q", finite=False)  # no bool, complex or string
        a = np.abs(q)
        if np.any(~np.isfinite(a)) or np.any(a > grid.q_max * (1 + 1e-12)):
            bad = q[~(np.isfinite(a) & (a <= grid.q_max * (1 + 1e-12)))].ravel()[:3]
            raise InvalidArgumentError(
                "q", bad.tolist(), f"|q| <= q_max={grid.q_max:.6g} (the grid's end)"
            )
        out = np.array(reference(a, self.skewness), dtype=complex)  # G = g below q_min
        inside = a >= grid.q_min
        dev = self.deviation[self.time_index(tau_index, tau)]
        out[inside] = f_hat(a[inside]) + self._interpolate(dev, a[inside])
        return np.where(q < 0, np.conj(out), out)

    def _interpolate(self, values: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Lagrange interpolation in s = ln q of grid ``values`` at q_min ≤ q ≤ q_max."""
        grid = self.resolution
        order = grid.order
        pos = (np.log(q) - grid.s_min) / grid.h
        first = np.clip(np.floor(pos) - order // 2 + 1, 0, grid.n - order).astype(int)
        x = pos - first  # position within the stencil, in cells
        out = np.zeros(x.shape, dtype=complex)
        for k in range(order):
            wk = np.ones_like(x)
            for m in range(order):
                if m != k:
                    wk *= (x - m) / (k - m)
            out += wk * values[first + k]
        return out

    def _require_one_dimension(self, what: str) -> None:
        if self.dimension != 1:
            raise InvalidArgumentError(
                "dimension", self.dimension,
                f"dimension 1 for {what}: f̂ = (1 + |q|) e^{{−|q|}} is the scaling solution of "
                "the one-dimensional equation only (none is known in closed form for d >= 2)",
            )

    def sup_error(self, tau_index: int | None = None, *,
                  tau: float | None = None) -> np.ndarray | float:
        """sup over q ≥ 0 of |G(q, τ) − f̂(q)|: on the grid, refined 16× around the maximum.

        Only for ``dimension`` 1 (InvalidArgumentError naming ``dimension`` otherwise): f̂ is
        the scaling solution of the one-dimensional equation, and in d ≥ 2 the distance to it
        does not tend to zero.

        Parameters
        ----------
        tau_index : int, optional
            One saved time; None (and no ``tau``) for all.
        tau : float, optional
            One saved time by value (:meth:`time_index`).

        Returns
        -------
        float or numpy.ndarray
            The sup at that time, or shape (T,) for all times.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``dimension`` when d ≥ 2, or ``tau_index`` when out of range.
        """
        self._require_one_dimension("sup_error")
        if tau_index is None and tau is None:
            return np.array([self.sup_error(k) for k in range(len(self.tau))])
        return self._weighted_sup(self.time_index(tau_index, tau), 0.0, self.resolution.q_min)

    def fourier_distance(self, s: float, tau_index: int | None = None, q_low: float | None = None,
                         *, tau: float | None = None):
        """d_s(G, f̂) = sup_q |G − f̂| / q^s over q ∈ [q_low, q_max] (default q_low = q_min).

        Restricting the sup to q ≥ q_low gives a lower bound of the full metric, so it obeys the
        contraction bound too; small q_low makes the value sensitive to round-off (|ΔG| ~ 1e-16
        divided by q_low^s) and to the grid's cut at q_min.  Only for ``dimension`` 1,
        as :meth:`sup_error`.  The contraction bound d_s(G(τ), f̂) ≤ e^{−γ(s)τ} d_s(G(0), f̂)
        for s ∈ (2, 3) is that of Bobylev, Cercignani & Toscani (J. Stat. Phys. 2003).

        Parameters
        ----------
        s : float
            Exponent of the metric.
        tau_index : int, optional
            One saved time; None (and no ``tau``) for all.
        q_low : float, optional
            Lower end of the sup; None for the grid's q_min.
        tau : float, optional
            One saved time by value (:meth:`time_index`).

        Returns
        -------
        float or numpy.ndarray
            d_s at that time, or shape (T,) for all times.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``dimension`` when d ≥ 2, ``s`` or ``q_low`` when not a finite real number
            (a bool or a complex number included; ``s`` also when q^s overflows there),
            ``q_low`` at or beyond the grid's end q_max, or ``tau_index`` when out of range.
        """
        self._require_one_dimension("fourier_distance")
        s = check_real(s, "s")
        if q_low is not None:
            q_low = check_real(q_low, "q_low")
            if not q_low < self.resolution.q_max:
                raise InvalidArgumentError(
                    "q_low", q_low, f"q_low < q_max={self.resolution.q_max:.6g} (the grid's end)")
        low = max(self.resolution.q_min, self.resolution.q_min if q_low is None else q_low)
        if not abs(s) * max(-math.log(low), math.log(self.resolution.q_max)) < 700.0:
            raise InvalidArgumentError("s", s, f"an exponent with q^s finite and non-zero on "
                                       f"[{low:.3g}, {self.resolution.q_max:.3g}]")
        if tau_index is None and tau is None:
            return np.array([self.fourier_distance(s, k, q_low) for k in range(len(self.tau))])
        q_low = self.resolution.q_min if q_low is None else q_low
        return self._weighted_sup(self.time_index(tau_index, tau), s, q_low)

    def _weighted_sup(self, k: int, s: float, q_low: float) -> float:
        q = self.q
        keep = q >= q_low
        diff = np.abs(self.deviation[k][keep]) / q[keep] ** s
        j = int(np.argmax(diff))
        qk = q[keep]
        lo, hi = qk[max(j - 1, 0)], qk[min(j + 1, qk.size - 1)]
        fine = np.exp(np.linspace(np.log(lo), np.log(hi), 33))
        fine_diff = np.abs(self._interpolate(self.deviation[k], fine)) / fine**s
        return float(max(diff[j], fine_diff.max()))

    def density(self, x=None, tau_index: int | None = None, *, tau: float | None = None,
                time: float | None = None):
        """Velocity-space density P(x, τ) of the rescaled velocity x = v / v0: returns ``(x, P)``.

        Units: x = v / v0(τ) with v0² = ⟨v²⟩ = e^{−2λτ} (unit initial variance), so P has unit
        variance; the density of v itself is P(v / v0) / v0.  For ``dimension`` d ≥ 2, x is one
        Cartesian component and v0² = e^{−Λτ} its variance
        (:meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`).

        Sign and normalisation: the characteristic function is P̂(k) = ∫ e^{ikv} P(v) dv
        (so G(q) = E[e^{iqx}]), and its inverse carries e^{−iqx} and 1/(2π):

            P(x) = (1/2π) ∫_{−∞}^{∞} e^{−iqx} G(q) dq = (1/π) Re ∫_0^{q_max} e^{−iqx} G(q) dq,

        using G(−q) = conj G(q) and cutting G at the grid's end q_max.

        ``x=None``: on the grid of the FFT of :func:`maxwell_kinetics.velocity.inverse_transform`
        (a trapezoid sum with spacing dq, period L = 2π/dq = 1000 in x).  Given x, P is computed
        there by Gauss–Legendre quadrature (no aliasing).  Error sources
        (aliasing of the x⁻⁴ tail, the cut at q_max): :mod:`maxwell_kinetics.velocity`.  In
        d = 1 with a built-in law, on the grid and at x alike, the never-collided particles
        (weight e^{−τ}, the law stretched by e^{λτ}) are added exactly and only the rest is
        transformed, as in :meth:`histogram`
        (:func:`~maxwell_kinetics.kinetic_histogram.solution_density`): at τ = 0 P is the
        initial law's density to round-off away from its jumps, never negative, no Gibbs
        ringing.  The band-limited transform of all of G (no frequency above q_max):
        :func:`~maxwell_kinetics.kinetic_histogram.band_limited_density`.

        Parameters
        ----------
        x : array_like, optional
            Rescaled velocities at which to evaluate P; None for the FFT grid.
        tau_index : int, optional
            Index of the saved τ (negative counts from the end); default the last.
        tau : float, optional
            The saved τ itself, instead of ``tau_index`` (:meth:`time_index`).
        time : float, optional
            The same as ``tau`` (the keyword every kinetic result takes).

        Returns
        -------
        x, P : numpy.ndarray
            The velocities and the density there.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``x`` if it is not an array of finite real numbers, or so large that the
            quadrature would exceed :data:`maxwell_kinetics.velocity.MAX_QUADRATURE_NODES` nodes
            or the memory available (panels of width π / max|x|: |x| up to about 9e4), or with
            so many points that it would take more than one day (the checks run before any
            work); naming ``tau_index`` if it is out of range; naming ``time`` when ``tau`` is
            given too.
        """
        from .kinetic_histogram import solution_density

        tau = pick_time("tau", tau, time)
        return solution_density(self, self.time_index(tau_index, tau), x)

    def _truncated(self, tau_index: int):
        """G(q) at saved time ``tau_index`` as a callable, zero beyond the grid's end q_max
        (|G| < 1e-13 there once near the scaling solution)."""
        from .velocity import cut_at

        k = self.time_index(tau_index)
        return cut_at(lambda q: self.evaluate(q, k), self.resolution.q_max)

    def speed_density(self, s, tau_index: int | None = None, *, tau: float | None = None):
        """Density of the rescaled speed |v| / v0 in d = ``dimension``: returns ``(s, P)``.

        Units: v0² = e^{−Λτ} is the variance of one component (unit initial variance per
        component, Λ = :meth:`~maxwell_kinetics.model.MaxwellModel.energy_rate`; d = 1:
        Λ = 2λ), so ⟨s²⟩ = d and ∫_0^∞ P ds = 1; the density of |v| itself is P(|v| / v0) / v0.

        G(q) is the radial profile Φ(|k|) of the isotropic characteristic function
        E[e^{ik·v/v0}], and P(s) = S_d s^{d−1} f(s) with f its radial inverse transform, G cut
        at the grid's end q_max as in :meth:`density` (Gauss–Legendre panels, no aliasing; the
        formulas and the errors: :func:`maxwell_kinetics.velocity.speed_density_at`).  In
        d = 1 it is the density of |x|, P(s) + P(−s) of :meth:`density` (its exact free part).

        Parameters
        ----------
        s : array_like
            Rescaled speeds |v| / v0 ≥ 0, finite.
        tau_index : int, optional
            Index of the saved τ (negative counts from the end); default the last.
        tau : float, optional
            The saved τ itself, instead of ``tau_index`` (:meth:`time_index`).

        Returns
        -------
        s, P : numpy.ndarray
            The speeds (as a float array) and the speed density there.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``s`` for a negative, non-finite, boolean or complex speed or one so large
            that the quadrature would exceed
            :data:`maxwell_kinetics.velocity.MAX_QUADRATURE_NODES` nodes or the memory
            available (about 9e4; checked before any work), or ``tau_index`` when out of range.
        """
        from .velocity import check_quadrature, check_speeds, speed_density_at

        s, k = check_speeds(s, "s"), self.time_index(tau_index, tau)
        if self.dimension == 1 and check_quadrature(self.resolution.q_max, s, "s"):  # names s
            return s, self.density(s, k)[1] + self.density(-s, k)[1]
        return s, speed_density_at(self._truncated(k), s, self.dimension,
                                   q_max=self.resolution.q_max)

    def moments(self, orders=(2, 4, 6), tau_index: int | None = None, *,
                tau: float | None = None, time: float | None = None):
        """Even moments at the saved τ, read from G near q = 0: a
        :class:`~maxwell_kinetics.moments.Moments`.

        ``values[k, j]`` is ⟨|v|^n⟩/v₀^n for n = ``orders[j]`` at ``tau[k]`` (d = 1: ⟨x^n⟩ of the
        rescaled velocity x = v/v₀), ``component`` the moments of one Cartesian component,
        ``errors`` their error estimates.  v₀² is the variance of one component, so the order-2
        values are 1 (d = 1) and d.  The q window is chosen per moment and per τ between the
        non-analytic |q|^{2s*} term and the grid's floor (method, and the cases returned as NaN
        with a reason: :mod:`maxwell_kinetics.moments`).  ``orders``: even positive integers
        (InvalidArgumentError naming ``orders`` otherwise); ``tau_index``: one saved time, or
        None for all.

        Parameters
        ----------
        orders : sequence of int, default (2, 4, 6)
            Even positive orders n.
        tau_index : int, optional
            One saved time; None (and no ``tau``) for all.
        tau : float, optional
            One saved time by value (:meth:`time_index`).
        time : float, optional
            The same as ``tau``.

        Returns
        -------
        maxwell_kinetics.moments.Moments
            One row per selected time (``scale`` = v₀(τ), :attr:`velocity_scale`).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``orders`` or ``tau_index`` when invalid, ``time`` with ``tau``.
        """
        from .moments import moments_of

        tau = pick_time("tau", tau, time)
        idx = (range(len(self.tau)) if tau_index is None and tau is None
               else [self.time_index(tau_index, tau)])
        q = self.q
        ref = deviation_from_f_hat(q, self.skewness)
        rows = [(self.deviation[k] - ref).real for k in idx]
        return moments_of(q, rows, self.tau[list(idx)], self.dimension, orders,
                          self.velocity_scale[list(idx)])

    @time_by_keyword("tau_index={value} (an index into tau) or tau={value} (a saved time)")
    def histogram(self, edges, *, tau_index: int | None = None, tau: float | None = None,
                  time: float | None = None):
        """The kinetic prediction on the bins ``edges`` at one saved time, as the
        :class:`particles.observables.Histogram` that particle runs return: ``density`` = the
        bin probability ∫_a^b P(x, τ) dx divided by the width (G cut at the grid's end q_max, as
        in :meth:`density`; in d = 1 the never-collided particles of a built-in law exactly,
        from its CDF, so at τ = 0 it is the initial law's to round-off), ``error`` = the
        solver's estimate of the numerical error of that bin probability (grid and cut at
        q_max), divided by the width, ``count`` 0, ``samples`` 0, ``v0`` = v0(τ).
        :meth:`~particles.observables.Histogram.distance` adds ``error`` in quadrature to the
        sample's statistical error, and warns
        (:class:`~particles.observables.NumericalErrorWarning`) where it is the larger: then
        solve on a finer ``resolution``.

        x = v/v0(τ) with v0² the variance of one component (e^{−2λτ} in d = 1): in the kinetic
        theory the energy per component itself, so this is the particle runs' convention
        x = v/√E (:func:`particles.observables.rescaled_histogram`; one Cartesian component in
        d ≥ 2), and ``run.histograms[i].distance(sol.histogram(edges, tau=...))`` compares them
        (:meth:`particles.observables.Histogram.distance`).  Method and conventions:
        :mod:`maxwell_kinetics.kinetic_histogram`.

        Parameters
        ----------
        edges : array_like
            At least two finite, strictly increasing bin edges in x.
        tau_index : int, optional
            Index of the saved τ (negative counts from the end); default the last.
        tau : float, optional
            The saved τ itself, instead of ``tau_index`` (:meth:`time_index`).
        time : float, optional
            The same as ``tau``.

        Returns
        -------
        particles.observables.Histogram
            The predicted histogram, ``error`` its numerical error.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``edges`` (not increasing, not finite, fewer than 2), ``tau`` (not a saved
            time), ``tau_index`` (out of range) or ``time`` (given with ``tau``).
        TypeError
            For a second positional argument (the time is keyword-only), naming the keywords.
        """
        from .kinetic_histogram import check_edges, solution_histogram

        tau = pick_time("tau", tau, time)
        edges = check_edges(edges)
        return solution_histogram(self, self.time_index(tau_index, tau), edges)

    def to_xarray(self, x=None):
        """The solution as an ``xarray.Dataset`` (needs the optional ``xarray`` extra):
        ``G`` and ``deviation`` (G − f̂) over (``tau``, ``q``), complex, and ``density``
        P(x, τ) over (``tau``, ``x``); attributes ``restitution``, ``initial``, ``dimension``,
        ``angular`` and ``resolution`` (JSON).

        Parameters
        ----------
        x : array_like, optional
            The rescaled velocities of ``density`` (finite reals); default 801 points on
            [−20, 20] (the FFT grid of :meth:`density` holds 16 384 points over ±500, nearly
            all of them in the far tail).

        Returns
        -------
        xarray.Dataset
            The labelled arrays.

        Raises
        ------
        ImportError
            When xarray is not installed, naming the extra to install
            (``pip install 'maxwell-kinetics[xarray]'``).
        particles.validation.InvalidArgumentError
            Naming ``x`` when it is not an array of finite reals.
        """
        from .kinetic_histogram import solution_to_xarray

        return solution_to_xarray(self, x)

    @property
    def kurtosis(self) -> np.ndarray:
        """⟨|v|⁴⟩/⟨|v|²⟩² at each saved τ, shape (T,) (d = 1: ⟨x⁴⟩/⟨x²⟩², 3 for a Gaussian;
        d = 2: 2; d = 3: 5/3), from :meth:`moments`; NaN where the fourth moment is not
        resolved.  A property (an array, as on every kinetic result): it was a method."""
        return self.moments(orders=(2, 4)).kurtosis()

    def plot(self, ax=None):
        """P(x, τ) on a log scale at every saved τ
        (:func:`maxwell_kinetics.kinetic_result.plot_densities`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            The panel; default the one panel of a new figure (made without pyplot).

        Returns
        -------
        matplotlib.axes.Axes
            The panel, one line per saved τ.
        """
        return plot_densities(self, ax)

    # -- persistence --------------------------------------------------------------------
    def to_record(self) -> tuple[dict, dict[str, np.ndarray]]:
        """(meta, arrays): the JSON-able parameters and the arrays ``tau``, ``G``, ``deviation``
        (what :meth:`save` writes, also used when a comparison saves a solution inside it).

        Returns
        -------
        meta : dict
            restitution, initial, resolution and options (as dicts), skewness, seconds,
            dimension, angular, angular_rule, angular_nodes, builtin_law.
        arrays : dict of str to numpy.ndarray
            ``tau``, ``G`` and ``deviation``.
        """
        meta = {
            "restitution": self.restitution,
            "initial": self.initial,
            "resolution": dataclasses.asdict(self.resolution),
            "skewness": self.skewness,
            "options": dataclasses.asdict(self.options),
            "seconds": self.seconds,
            "dimension": self.dimension,
            "angular": self.angular,
            "angular_rule": self.angular_rule,
            "angular_nodes": self.angular_nodes,
            "builtin_law": self.builtin_law,
        }
        return meta, {"tau": self.tau, "G": self.G, "deviation": self.deviation}

    @classmethod
    def from_record(cls, meta: dict, arrays: dict, path="solution") -> Solution:
        """Inverse of :meth:`to_record`; a malformed record raises
        :class:`particles.persistence.FileFormatError` naming ``path``.

        Parameters
        ----------
        meta : dict
            The parameters, as :meth:`to_record` writes them (``dimension``, ``angular``,
            ``angular_rule``, ``angular_nodes`` and ``builtin_law`` may be missing: older
            records; a missing ``angular_nodes`` reads as the default 16 in d >= 2, 1 in d = 1,
            a missing ``builtin_law`` as True, as those records were read).
        arrays : dict
            ``tau``, ``G`` and ``deviation``.
        path : str or os.PathLike, default "solution"
            Name of the source, for the error message.

        Returns
        -------
        Solution
            The rebuilt solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If a key is missing or a value has the wrong type.
        """
        try:
            return cls(
                float(meta["restitution"]),
                str(meta["initial"]),
                Resolution(**meta["resolution"]),
                np.asarray(arrays["tau"]),
                np.asarray(arrays["G"]),
                np.asarray(arrays["deviation"]),
                float(meta["skewness"]),
                SolverOptions(**meta["options"]),
                float(meta["seconds"]),
                int(meta.get("dimension", 1)),
                str(meta.get("angular", "uniform")),
                # files written before the rule existed used the 16-node ("accurate") rule
                str(meta.get("angular_rule", "accurate")),
                int(meta.get("angular_nodes", 16 if int(meta.get("dimension", 1)) > 1 else 1)),
                _record_flag(meta, "builtin_law", True),
            )
        except (KeyError, ValueError, TypeError) as exc:
            raise persistence.FileFormatError(
                path, f"{type(exc).__name__}: {exc}", "path", "a saved Solution"
            ) from None

    def save(self, path) -> None:
        """Save to ``path`` through :mod:`particles.persistence` (kind ``"solution"``: arrays
        ``tau``, ``G``, ``deviation`` and the parameters as JSON); reload with
        :meth:`Solution.load`.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        """
        meta, arrays = self.to_record()
        persistence.save(path, "solution", _SOLUTION_VERSION, arrays, meta)

    @classmethod
    def load(cls, path) -> Solution:
        """Read a file written by :meth:`save` (also of version 0.1.0); anything else raises
        :class:`particles.persistence.FileFormatError` naming ``path`` and the reason.

        Parameters
        ----------
        path : str or os.PathLike
            The file to read.

        Returns
        -------
        Solution
            The saved solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If the file is not a saved Solution of a known version.
        """
        loaded = persistence.load(path, "solution", (1, _SOLUTION_VERSION),
                                  expected="a saved Solution")
        return cls.from_record(loaded.meta, loaded.arrays, path)
