"""The result of :func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`: F(c, t) on the
velocity grid at the saved times, with f(v, t), the moments, P(x, t), histograms, its saved form,
an ``xarray`` view and a plot (:class:`BoltzmannSolution`, a
:class:`~maxwell_kinetics.kinetic_result.KineticResult`).  Moved here from
:mod:`maxwell_kinetics.inelastic_boltzmann`, which still imports it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from particles import persistence
from particles.validation import InvalidArgumentError, check_count, check_real_array

from . import velocity_grid as _grid
from .kinetic_result import pick_time, plot_densities, time_by_keyword
from .model import RelativeVelocityModel

__all__ = ["BoltzmannSolution", "interpolate_nodes", "moment_order"]


@dataclass(frozen=True)
class BoltzmannSolution:
    """The solution of :func:`~maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`:
    F(c, t) = s f(u + s c, t) on the grid of c at the saved times, with f(v, t), ⟨v²⟩, the
    kurtosis, the moments and histograms, saved with :meth:`save` and read with :meth:`load`.
    It meets the contract of :class:`~maxwell_kinetics.kinetic_result.KineticResult` (time
    name ``"t"``, velocities in units of the initial ⟨v²⟩ = 1).

    Attributes
    ----------
    restitution, exponent, number_density : float
        r, γ and n (particles per unit length) of the solve.
    initial : str
        The initial law's name.
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid of c.
    t : numpy.ndarray
        The saved physical times, shape (T,).
    F : numpy.ndarray
        Shape (T, N): F(c_i, t_k).
    log_scale : numpy.ndarray
        ln s(t_k), shape (T,) (s(0) = 1: the standard deviation of v).
    mean : float
        u, the conserved mean velocity.
    energy_rate : numpy.ndarray
        d⟨v²⟩/dt of the discrete equation at each saved time, shape (T,).
    edge_mass : numpy.ndarray
        Largest ω|F| (ω = h, or the local spacing of a
        :class:`maxwell_kinetics.velocity_grid.MappedGrid`) among the two outermost nodes on each
        side at each time, shape (T,): a tail that reaches the grid's end shows here.
    steps : int
        Time steps taken.
    seconds : float
        Wall-clock time of the solve.
    """

    restitution: float
    exponent: float
    number_density: float
    initial: str
    grid: _grid.VelocityGrid
    t: np.ndarray
    F: np.ndarray = field(repr=False)
    log_scale: np.ndarray = field(repr=False)
    mean: float = 0.0
    energy_rate: np.ndarray = field(repr=False, default=None)
    edge_mass: np.ndarray = field(repr=False, default=None)
    steps: int = 0
    seconds: float = 0.0

    @property
    def times(self) -> np.ndarray:
        """The saved physical times ``t`` as a float array."""
        return np.asarray(self.t, dtype=float)

    @property
    def time_name(self) -> str:
        """``"t"``: the times are physical times."""
        return "t"

    @property
    def model(self) -> RelativeVelocityModel:
        """The :class:`~maxwell_kinetics.model.RelativeVelocityModel` of the solve."""
        return RelativeVelocityModel(self.restitution, exponent=self.exponent)

    def time_index(self, t: float | None = None) -> int:
        """The index of a saved time (to a relative 1e-12); None: the last.

        Parameters
        ----------
        t : float, optional
            One of the saved times (a real number: not a bool, not a string).

        Returns
        -------
        int
            Its index.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``t`` when it is not a saved time, or not a finite real number (a bool, a
            string such as ``'2'``, NaN).
        """
        if t is None:
            return len(self.t) - 1
        shown = ", ".join(f"{x:g}" for x in self.t)[:200]
        if (isinstance(t, (bool, np.bool_))
                or not isinstance(t, (int, float, np.integer, np.floating))
                or not math.isfinite(float(t))):
            raise InvalidArgumentError("t", t, f"one of the saved times: {shown}")
        match = np.flatnonzero(np.abs(self.t - float(t)) <= 1e-12 * max(1.0, abs(float(t))))
        if match.size == 0:
            raise InvalidArgumentError("t", t, f"one of the saved times: {shown}")
        return int(match[0])

    @property
    def scale(self) -> np.ndarray:
        """s(t_k), the velocity scale of the grid (shape (T,))."""
        return np.exp(self.log_scale)

    def velocity_density(self, t: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """f(v, t) on the grid's velocities v_i = u + s c_i.

        Parameters
        ----------
        t : float, optional
            A saved time (default the last).

        Returns
        -------
        v, f : numpy.ndarray
            The velocities and the density there (∫ f dv = 1).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``t`` (:meth:`time_index`).
        """
        k = self.time_index(t)
        s = self.scale[k]
        return self.mean + s * self.grid.c, self.F[k] / s

    def _raw_moments(self, orders) -> np.ndarray:
        """⟨(v − u)^k⟩ for k in ``orders`` (checked), shape (T, len(orders))."""
        orders = _check_orders(orders, "orders", self.grid)
        c = self.grid.c
        out = np.array([[_grid.grid_sum(self.grid, row, c**k) for k in orders] for row in self.F])
        return out * self.scale[:, None] ** np.asarray(orders)

    def moments(self, orders=(2, 4, 6)):
        """Central moments at every saved time, as a :class:`~maxwell_kinetics.moments.Moments`
        rescaled by v₀(t) = √⟨(v − u)²⟩: ``values[k, j]`` = ⟨(v − u)^n⟩/v₀^n (order 2: 1),
        ``raw()`` = ⟨(v − u)^n⟩ (the array this method returned before, to round-off),
        ``errors`` 0 (grid sums, exact for the discrete law; the discretisation error is not
        estimated), ``windows`` NaN, ``scale`` = v₀, ``time_name`` ``"t"``.

        Parameters
        ----------
        orders : sequence of int
            The n, integers >= 0.

        Returns
        -------
        maxwell_kinetics.moments.Moments
            One row per saved time.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``orders`` when it is not a sequence, or holds an order that is not an
            integer >= 0 (2.5, a bool, a string, NaN: c^2.5 is not real for c < 0) or whose
            power overflows on the grid (:func:`moment_order`).
        """
        from .moments import Moments

        orders = tuple(_check_orders(orders, "orders", self.grid))
        c = self.grid.c
        sums = np.array([[_grid.grid_sum(self.grid, row, c**k) for k in orders]
                         for row in self.F])
        second = np.array([_grid.grid_sum(self.grid, row, c * c) for row in self.F])
        values = sums / second[:, None] ** (0.5 * np.asarray(orders, dtype=float))
        shape = values.shape
        return Moments(orders, self.times.copy(), 1, values, values.copy(), np.zeros(shape),
                       np.full(shape + (2,), np.nan),
                       tuple(("",) * len(orders) for _ in range(shape[0])), "t",
                       self.scale * np.sqrt(second))

    @property
    def temperature(self) -> np.ndarray:
        """⟨(v − u)²⟩ at each saved time."""
        return self._raw_moments((2,))[:, 0]

    @property
    def energy(self) -> np.ndarray:
        """⟨v²⟩ = u² + ⟨(v − u)²⟩ at each saved time (1 at t = 0 for the built-in laws)."""
        return self.mean**2 + self.temperature

    @property
    def kurtosis(self) -> np.ndarray:
        """⟨(v − u)⁴⟩/⟨(v − u)²⟩² at each saved time."""
        m = self._raw_moments((2, 4))
        return m[:, 1] / m[:, 0] ** 2

    def collisions_per_particle(self) -> np.ndarray:
        """Collisions per particle τ(t) = ∫₀ᵗ n⟨|v − w|^γ⟩ dt′ at each saved time, by the
        trapezoid rule over the saved times (which must start at t = 0 and be dense enough for
        the rule: the rate changes by little between two of them).

        Each particle collides at rate n⟨|v − w|^γ⟩ (γ = 1, hard rods: 2n√(T/π) for a
        Gaussian of temperature T; γ = 0, the Maxwell model: n, so that τ = n t), with
        ⟨|v − w|^γ⟩ = s^γ Σᵢⱼ ωᵢ ωⱼ F_i F_j |c_i − c_j|^γ on the solution's grid (v = u + s c,
        ω the grid's trapezoid weights; the rate is the model's,
        :meth:`~maxwell_kinetics.model.RelativeVelocityModel.rate`).

        Returns
        -------
        numpy.ndarray
            τ at each saved time, shape (T,), starting at 0 and increasing.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``t`` if the first saved time is not 0.
        """
        if self.t[0] != 0.0:
            raise InvalidArgumentError("t", float(self.t[0]),
                                       "saved times starting at t = 0 (the count starts there)")
        c, model = self.grid.c, self.model
        pair_rates = model.rate(c[:, None], c[None, :])  # of the rescaled velocities c
        weighted = self.F * self.grid.weights
        mean_rate = np.einsum("ti,ij,tj->t", weighted, pair_rates, weighted)
        # the rate is homogeneous of degree γ in the velocities: v − w = s (c_i − c_j)
        rate = self.number_density * self.scale ** model.kernel.homogeneity * mean_rate
        steps = 0.5 * (rate[1:] + rate[:-1]) * np.diff(self.times)
        return np.concatenate([[0.0], np.cumsum(steps)])

    def density(self, x=None, t: float | None = None, *, time: float | None = None):
        """P(x, t) of x = (v − u)/√T(t), T = ⟨(v − u)²⟩, by sixth-order Lagrange interpolation
        of the nodes (zero outside the grid): returns ``(x, P)`` as
        :meth:`maxwell_kinetics.solution.Solution.density` does (it returned P alone before).

        Parameters
        ----------
        x : array_like, optional
            Rescaled velocities (finite real numbers); None: the grid's nodes, c_i/√⟨c²⟩.
        t : float, optional
            A saved time (default the last).
        time : float, optional
            The same as ``t`` (the keyword every kinetic result takes).

        Returns
        -------
        x, P : numpy.ndarray
            The velocities (as a float array) and P there, of the shape of ``x``.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``x`` when it is not an array of finite real numbers (NaN, ±inf, booleans,
            strings), ``t`` (:meth:`time_index`), ``time`` when ``t`` is given too.
        """
        if x is not None:
            x = check_real_array(x, "x")
        k = self.time_index(pick_time("t", t, time))
        c = self.grid.c
        scale = math.sqrt(_grid.grid_sum(self.grid, self.F[k], c * c))
        if x is None:
            return c / scale, scale * self.F[k]
        return x, scale * interpolate_nodes(self.F[k], self.grid, x * scale)

    @time_by_keyword("t={value} or time={value} (a saved time)")
    def histogram(self, edges, *, t: float | None = None, time: float | None = None):
        """The solution's prediction on bins of x = (v − u)/√T as the
        :class:`particles.observables.Histogram` particle runs return (``density`` = bin
        probability / width, ``error`` and ``count`` 0, ``samples`` 0, ``v0`` = √T).

        Parameters
        ----------
        edges : array_like
            Increasing finite bin edges in x.
        t : float, optional
            A saved time (default the last).
        time : float, optional
            The same as ``t``.

        Returns
        -------
        particles.observables.Histogram
            The predicted histogram.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``edges``, ``t``, or ``time`` when ``t`` is given too.
        TypeError
            For a second positional argument (the time is keyword-only), naming ``t=``.
        """
        from particles.observables import Histogram

        from .kinetic_histogram import check_edges

        t = pick_time("t", t, time)
        edges = check_edges(edges)
        k = self.time_index(t)
        c = self.grid.c
        scale = math.sqrt(_grid.grid_sum(self.grid, self.F[k], c * c))
        prob = np.diff(_cumulative(self.F[k], self.grid, edges * scale))
        width = np.diff(edges)
        return Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), prob / width,
                         np.zeros(width.size), np.zeros(width.size, dtype=np.int64), 0,
                         float(self.scale[k] * scale))

    def to_xarray(self):
        """The solution as an ``xarray.Dataset`` (needs the optional ``xarray`` extra): ``F``
        over (``t``, ``c``), ``log_scale``, ``energy``, ``kurtosis`` and, when recorded,
        ``energy_rate`` and ``edge_mass`` over ``t``; attributes ``restitution``,
        ``exponent``, ``number_density``, ``initial``, ``mean`` and ``grid`` (JSON).

        Returns
        -------
        xarray.Dataset
            The labelled arrays, the time coordinate named :attr:`time_name`.

        Raises
        ------
        ImportError
            When xarray is not installed, naming the extra to install.
        """
        import json

        from particles.driver.result import import_xarray

        xr = import_xarray("BoltzmannSolution.to_xarray()")
        name = self.time_name
        data = {"F": ((name, "c"), np.asarray(self.F)),
                "log_scale": ((name,), np.asarray(self.log_scale)),
                "energy": ((name,), self.energy), "kurtosis": ((name,), self.kurtosis)}
        for key in ("energy_rate", "edge_mass"):
            if getattr(self, key) is not None:
                data[key] = ((name,), np.asarray(getattr(self, key)))
        attrs = {"restitution": float(self.restitution), "exponent": float(self.exponent),
                 "number_density": float(self.number_density), "initial": str(self.initial),
                 "mean": float(self.mean), "grid": json.dumps(_grid_record(self.grid))}
        return xr.Dataset(data, coords={name: self.times, "c": np.asarray(self.grid.c)},
                          attrs=attrs)

    def plot(self, ax=None):
        """P(x, t) on a log scale at every saved t on the grid's nodes
        (:func:`maxwell_kinetics.kinetic_result.plot_densities`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            The panel; default the one panel of a new figure (made without pyplot).

        Returns
        -------
        matplotlib.axes.Axes
            The panel, one line per saved t.
        """
        return plot_densities(self, ax)

    # -- persistence --------------------------------------------------------------------
    def to_record(self) -> tuple[dict, dict[str, np.ndarray]]:
        """(meta, arrays): the JSON-able parameters and the arrays (what :meth:`save` writes).

        Returns
        -------
        meta : dict
            restitution, exponent, number_density, initial, grid (kind, points, half_width,
            core_spacing), mean, steps, seconds.
        arrays : dict of str to numpy.ndarray
            ``t``, ``F``, ``log_scale`` and, when recorded, ``energy_rate`` and ``edge_mass``.
        """
        meta = {"restitution": float(self.restitution), "exponent": float(self.exponent),
                "number_density": float(self.number_density), "initial": str(self.initial),
                "grid": _grid_record(self.grid), "mean": float(self.mean),
                "steps": int(self.steps), "seconds": float(self.seconds)}
        arrays = {"t": np.asarray(self.t), "F": np.asarray(self.F),
                  "log_scale": np.asarray(self.log_scale)}
        for key in ("energy_rate", "edge_mass"):
            if getattr(self, key) is not None:
                arrays[key] = np.asarray(getattr(self, key))
        return meta, arrays

    @classmethod
    def from_record(cls, meta: dict, arrays: dict, path="solution") -> BoltzmannSolution:
        """Inverse of :meth:`to_record`.

        Parameters
        ----------
        meta : dict
            The parameters, as :meth:`to_record` writes them.
        arrays : dict
            ``t``, ``F``, ``log_scale`` and optionally ``energy_rate`` and ``edge_mass``.
        path : str or os.PathLike, default "solution"
            Name of the source, for the error message.

        Returns
        -------
        BoltzmannSolution
            The rebuilt solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If a key is missing or a value has the wrong type, naming ``path``.
        """
        try:
            grid = dict(meta["grid"])
            kind = grid.pop("kind")
            if kind == "uniform":
                grid = _grid.VelocityGrid(int(grid["points"]), float(grid["half_width"]))
            elif kind == "mapped":
                grid = _grid.MappedGrid(int(grid["points"]), float(grid["half_width"]),
                                        float(grid["core_spacing"]))
            else:
                raise ValueError(f"unknown grid kind {kind!r}")
            optional = {key: np.asarray(arrays[key]) if key in arrays else None
                        for key in ("energy_rate", "edge_mass")}
            return cls(float(meta["restitution"]), float(meta["exponent"]),
                       float(meta["number_density"]), str(meta["initial"]), grid,
                       np.asarray(arrays["t"]), np.asarray(arrays["F"]),
                       np.asarray(arrays["log_scale"]), float(meta["mean"]),
                       optional["energy_rate"], optional["edge_mass"], int(meta["steps"]),
                       float(meta["seconds"]))
        except (KeyError, ValueError, TypeError, InvalidArgumentError) as exc:
            raise persistence.FileFormatError(
                path, f"{type(exc).__name__}: {exc}", "path", "a saved BoltzmannSolution"
            ) from None

    def save(self, path) -> None:
        """Save to ``path`` through :mod:`particles.persistence` (kind
        ``"boltzmann_solution"``, hashed); :meth:`load` reads it back bit for bit, the grid
        included.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        """
        meta, arrays = self.to_record()
        persistence.save(path, "boltzmann_solution", _SAVED_VERSION, arrays, meta)

    @classmethod
    def load(cls, path) -> BoltzmannSolution:
        """Read a file written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            The file to read.

        Returns
        -------
        BoltzmannSolution
            The saved solution.

        Raises
        ------
        particles.persistence.FileFormatError
            If the file is not a saved BoltzmannSolution of a known version.
        """
        loaded = persistence.load(path, "boltzmann_solution", (_SAVED_VERSION,),
                                  expected="a saved BoltzmannSolution")
        return cls.from_record(loaded.meta, loaded.arrays, path)


#: Version of the saved BoltzmannSolution format.
_SAVED_VERSION = 1


def _grid_record(grid) -> dict:
    """The JSON-able parameters of a VelocityGrid or MappedGrid."""
    if isinstance(grid, _grid.MappedGrid):
        return {"kind": "mapped", "points": int(grid.points),
                "half_width": float(grid.half_width), "core_spacing": float(grid.core_spacing)}
    return {"kind": "uniform", "points": int(grid.points), "half_width": float(grid.half_width)}


def _check_orders(orders, name: str, grid=None) -> list[int]:
    """The moment orders as ints >= 0 (:func:`particles.validation.check_count` each), naming
    ``name`` for a value that is not a sequence of them (:func:`moment_order`)."""
    if isinstance(orders, (str, bytes)) or np.ndim(orders) != 1:
        raise InvalidArgumentError(name, orders, "a sequence of integers >= 0")
    out = []
    for k in orders:
        try:
            out.append(check_count(k, name, 0))
        except InvalidArgumentError:
            raise InvalidArgumentError(name, orders, "a sequence of integers >= 0") from None
        if grid is not None:
            moment_order(out[-1], name, grid)
    return out


def moment_order(order, name: str, grid) -> int:
    """A moment order k: an integer >= 0 for which c^k stays finite on the whole grid (k ln
    max|c| below 700: up to 189 on ±40, 58 on ±2·10⁵).

    Parameters
    ----------
    order : int
        k.
    name : str
        The argument's name in errors.
    grid : VelocityGrid or MappedGrid (:mod:`maxwell_kinetics.velocity_grid`)
        The grid.

    Returns
    -------
    int
        ``order``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``name`` when ``order`` is not an integer >= 0, or c^k overflows on the grid.
    """
    k = check_count(order, name, 0)
    top = math.log(max(float(grid.half_width), 1.0))
    if not k * top < 700.0:
        raise InvalidArgumentError(name, order, f"an order <= {int(700.0 / top)} (c^k "
                                   f"overflows beyond on a grid of half-width "
                                   f"{grid.half_width:g})")
    return k


def interpolate_nodes(values: np.ndarray, grid, x: np.ndarray, order: int = 6):
    """Lagrange interpolation of order ``order`` of grid ``values`` at ``x`` (0 outside), in
    c on the uniform grid, in s on a mapped one.

    Parameters
    ----------
    values : numpy.ndarray
        The values at the grid's nodes, shape (N,).
    grid : VelocityGrid or MappedGrid
        The grid (:mod:`maxwell_kinetics.velocity_grid`).
    x : numpy.ndarray
        Where to interpolate (values of c).
    order : int
        Points of the Lagrange stencil.

    Returns
    -------
    numpy.ndarray
        The interpolated values, of the shape of ``x`` (0 outside the grid).
    """
    c = grid.c
    n = c.size
    if isinstance(grid, _grid.MappedGrid):
        pos = grid.position(x)
    else:
        pos = (x - c[0]) / (c[1] - c[0])
    first = np.clip(np.floor(pos) - order // 2 + 1, 0, n - order).astype(int)
    u = pos - first
    out = np.zeros(x.shape)
    for m in range(order):
        w = np.ones(x.shape)
        for k in range(order):
            if k != m:
                w *= (u - k) / (m - k)
        out += w * values[np.clip(first + m, 0, n - 1)]
    return np.where((pos >= 0) & (pos <= n - 1), out, 0.0)


def _cumulative(values: np.ndarray, grid, x: np.ndarray) -> np.ndarray:
    """∫_{−L}^{x} of the cubic spline through the nodes (0 below the grid, the total above);
    on a mapped grid the spline of F g′(s) in s, integrated in s."""
    from scipy.interpolate import CubicSpline

    c = grid.c
    if isinstance(grid, _grid.MappedGrid):
        spline = CubicSpline(grid.s, values * grid.weights / grid.step)
        s = np.clip(np.arcsinh(np.asarray(x, dtype=float) / grid.scale), grid.s[0], grid.s[-1])
        return np.array([spline.integrate(grid.s[0], b) for b in s])
    spline = CubicSpline(c, values)
    x = np.clip(x, c[0], c[-1])
    return np.array([spline.integrate(c[0], b) for b in x])
