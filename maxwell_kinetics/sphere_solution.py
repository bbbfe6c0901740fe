"""The result of :func:`maxwell_kinetics.sphere_spectral.solve_spheres`: the scaled distribution
F(c, t) of hard spheres or disks on the spectral grid at the saved times, with T(t), a₂(t),
a₃(t), the moments, the marginal of one component, histograms, its saved form, an ``xarray``
view and a plot (:class:`SphereSolution`, a
:class:`~maxwell_kinetics.kinetic_result.KineticResult`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from particles import persistence
from particles.validation import InvalidArgumentError, check_count, check_real_array

from .kinetic_result import pick_time, plot_densities, time_by_keyword
from .sphere_grid import SphereGrid

__all__ = ["SphereSolution", "sonine"]


def sonine(F, c, weight: float) -> tuple[float, float]:
    """a₂ and a₃ of a distribution on a grid (the formulas of
    :func:`particles.sphere_observables.sonine_coefficients`, with grid sums for the means).

    Parameters
    ----------
    F : numpy.ndarray
        Values at the nodes, shape (N,)*d.
    c : numpy.ndarray
        The nodes, shape (N,)*d + (d,).
    weight : float
        The volume of a cell, h^d.

    Returns
    -------
    a2, a3 : float
    """
    d = c.shape[-1]
    mass = F.sum() * weight
    mean = np.tensordot(F, c, axes=d) * weight / mass
    x = np.sum((c - mean) ** 2, axis=-1)
    m2, m4, m6 = (float(np.sum(F * x**k) * weight / mass) for k in (1, 2, 3))
    # the reduced velocity's |c|² = x/(2T) has moments m_k/(2T)^k: the ratios do not see 2T
    a2 = d / (d + 2.0) * m4 / m2**2 - 1.0
    a3 = 1.0 + 3.0 * a2 - d * d / ((d + 2.0) * (d + 4.0)) * m6 / m2**3
    return a2, a3


@dataclass(frozen=True)
class SphereSolution:
    """F(c, t) = s^d f(u + s c, t) on the grid of
    :func:`~maxwell_kinetics.sphere_spectral.solve_spheres` at the saved times (⟨|c|²⟩ = d:
    unit variance per component), with the contract of
    :class:`~maxwell_kinetics.kinetic_result.KineticResult` (time name ``"t"``, velocities in
    units of the initial temperature; ``density`` and ``histogram`` are of one component,
    x = (v_x − u_x)/√T).

    Attributes
    ----------
    kernel : str
        The kernel's name (``"hard_spheres"`` or ``"variable_hard_spheres"``).
    restitution, exponent, number_density : float
        α, γ and n.
    dimension : int
        d.
    initial : str
        The initial law's name (``"custom"`` for a density given as a function).
    grid : maxwell_kinetics.sphere_grid.SphereGrid
        The grid.
    t : numpy.ndarray
        The saved times, shape (T,).
    F : numpy.ndarray
        Shape (T,) + (N,)*d.
    log_scale : numpy.ndarray
        ln s(t), shape (T,).
    mean : numpy.ndarray
        u, shape (d,).
    cooling_rate : numpy.ndarray
        ζ(t) = −d ln T/dt of the discrete equation, shape (T,).
    steps : int
        Time steps taken.
    seconds : float
        Wall-clock time.
    """

    kernel: str
    restitution: float
    exponent: float
    dimension: int
    number_density: float
    initial: str
    grid: SphereGrid
    t: np.ndarray
    F: np.ndarray = field(repr=False)
    log_scale: np.ndarray = field(repr=False)
    mean: np.ndarray = field(repr=False)
    cooling_rate: np.ndarray = field(repr=False)
    steps: int = 0
    seconds: float = 0.0

    # -- times ----------------------------------------------------------------------------
    @property
    def times(self) -> np.ndarray:
        """The saved times ``t`` as a float array."""
        return np.asarray(self.t, dtype=float)

    @property
    def time_name(self) -> str:
        """``"t"``: physical time."""
        return "t"

    def time_index(self, t: float | None = None) -> int:
        """The index of a saved time (to a relative 1e-12); None: the last.

        Parameters
        ----------
        t : float, optional
            A saved time.

        Returns
        -------
        int

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``t`` when it is not a saved time.
        """
        if t is None:
            return len(self.t) - 1
        shown = ", ".join(f"{x:g}" for x in self.t)[:200]
        if (isinstance(t, (bool, np.bool_)) or not isinstance(t, (int, float, np.integer,
                                                                  np.floating))
                or not math.isfinite(float(t))):
            raise InvalidArgumentError("t", t, f"one of the saved times: {shown}")
        match = np.flatnonzero(np.abs(self.times - float(t)) <= 1e-12 * max(1.0, abs(float(t))))
        if match.size == 0:
            raise InvalidArgumentError("t", t, f"one of the saved times: {shown}")
        return int(match[0])

    # -- the grid and its sums -------------------------------------------------------------
    def nodes(self) -> np.ndarray:
        """c at the nodes, shape (N,)*d + (d,).

        Returns
        -------
        numpy.ndarray
        """
        c = self.grid.nodes()
        return np.stack(np.meshgrid(*([c] * self.dimension), indexing="ij"), axis=-1)

    def _sums(self, power) -> np.ndarray:
        """Σ F |c|^power h^d at each saved time."""
        r = np.sqrt(np.sum(self.nodes() ** 2, axis=-1))
        axes = tuple(range(1, self.dimension + 1))
        return np.sum(self.F * r**power, axis=axes) * self.grid.spacing**self.dimension

    @property
    def scale(self) -> np.ndarray:
        """s(t), shape (T,)."""
        return np.exp(self.log_scale)

    @property
    def temperature(self) -> np.ndarray:
        """T(t) = s² ⟨|c|²⟩/d (T(0) = 1 from the Maxwellian), shape (T,)."""
        return self.scale**2 * self._sums(2) / (self._sums(0) * self.dimension)

    @property
    def energy(self) -> np.ndarray:
        """⟨|v|²⟩ = |u|² + d T at each saved time."""
        return float(np.sum(self.mean**2)) + self.dimension * self.temperature

    @property
    def kurtosis(self) -> np.ndarray:
        """⟨|v − u|⁴⟩/⟨|v − u|²⟩² at each saved time."""
        return self._sums(4) * self._sums(0) / self._sums(2) ** 2

    def sonine(self) -> np.ndarray:
        """(a₂, a₃) at each saved time, shape (T, 2).

        Returns
        -------
        numpy.ndarray
        """
        c, w = self.nodes(), self.grid.spacing**self.dimension
        return np.array([sonine(row, c, w) for row in self.F])

    @property
    def a2(self) -> np.ndarray:
        """a₂(t), shape (T,)."""
        return self.sonine()[:, 0]

    @property
    def a3(self) -> np.ndarray:
        """a₃(t), shape (T,)."""
        return self.sonine()[:, 1]

    def moments(self, orders=(2, 4, 6)):
        """⟨|v − u|^n⟩/v₀^n (v₀² = T, the variance of one component; order 2 gives d) and one
        component's ⟨(v_x − u_x)^n⟩/v₀^n at every saved time, as a
        :class:`~maxwell_kinetics.moments.Moments` (``errors`` 0: grid sums).

        Parameters
        ----------
        orders : sequence of int
            The n ≥ 0.

        Returns
        -------
        maxwell_kinetics.moments.Moments

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``orders`` when it is not a sequence of integers ≥ 0.
        """
        from .moments import Moments

        if isinstance(orders, (str, bytes)) or np.ndim(orders) != 1:
            raise InvalidArgumentError("orders", orders, "a sequence of integers >= 0")
        orders = tuple(check_count(k, "orders", 0) for k in orders)
        mass, second = self._sums(0), self._sums(2)
        v0 = np.sqrt(second / (mass * self.dimension))
        cx = self.nodes()[..., 0]
        axes = tuple(range(1, self.dimension + 1))
        w = self.grid.spacing**self.dimension
        values = np.stack([self._sums(k) / mass / v0**k for k in orders], axis=1)
        component = np.stack([np.sum(self.F * cx**k, axis=axes) * w / mass / v0**k
                              for k in orders], axis=1)
        shape = values.shape
        return Moments(orders, self.times.copy(), self.dimension, values, component,
                       np.zeros(shape), np.full(shape + (2,), np.nan),
                       tuple(("",) * len(orders) for _ in range(shape[0])), "t",
                       self.scale * v0)

    # -- distributions ---------------------------------------------------------------------
    def distribution(self, *, time: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The scaled distribution F(c) on the grid at one saved time.

        Parameters
        ----------
        time : float, optional
            A saved time (default the last).

        Returns
        -------
        c, F : numpy.ndarray
            Shapes (N,)*d + (d,) and (N,)*d.
        """
        return self.nodes(), self.F[self.time_index(time)].copy()

    def marginal(self, *, time: float | None = None, axis: int = 0):
        """The law of one component x = c_a/v₀ (v₀ = √(⟨|c|²⟩/d)) at the grid's nodes.

        Parameters
        ----------
        time : float, optional
            A saved time (default the last).
        axis : int, default 0
            The component (0: v_x).

        Returns
        -------
        x, P : numpy.ndarray
            Shape (N,) each; Σ P Δx = 1.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``axis`` when it is not in 0 … d − 1.
        """
        if isinstance(axis, bool) or axis not in range(self.dimension):
            raise InvalidArgumentError("axis", axis, f"a component 0 ... {self.dimension - 1}")
        k = self.time_index(time)
        others = tuple(a for a in range(self.dimension) if a != axis)
        h = self.grid.spacing
        P = np.sum(self.F[k], axis=others) * h ** (self.dimension - 1)
        v0 = math.sqrt(self._sums(2)[k] / (self._sums(0)[k] * self.dimension))
        return self.grid.nodes() / v0, P * v0

    def _series(self, time, axis=0):
        """(v₀, the nodes, the Fourier coefficients of the marginal in c, the wavenumbers)."""
        x, P = self.marginal(time=time, axis=axis)
        c = self.grid.nodes()
        v0 = c[1] / x[1] if x[1] != 0 else c[-1] / x[-1]
        coefficients = np.fft.fft(P / v0) / P.size
        k = 2.0 * math.pi * np.fft.fftfreq(P.size, self.grid.spacing)
        coefficients[P.size // 2] = 0.0  # the Nyquist mode: no odd derivative, no shift
        return v0, c, coefficients, k

    def density(self, x=None, t: float | None = None, *, time: float | None = None):
        """P(x) of one component x = (v_x − u_x)/√T, by the Fourier series of the marginal
        (0 outside the box).

        Parameters
        ----------
        x : array_like, optional
            The x; None: the nodes.
        t : float, optional
            A saved time (default the last).
        time : float, optional
            The same as ``t``.

        Returns
        -------
        x, P : numpy.ndarray

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``x``, ``t``, or ``time`` with ``t``.
        """
        time = pick_time("t", t, time)
        if x is None:
            return self.marginal(time=time)
        x = check_real_array(x, "x")
        v0, c, coefficients, k = self._series(time)
        y = x * v0
        values = np.real(np.exp(1j * (y[..., None] - c[0]) * k) @ coefficients)
        inside = (y >= c[0]) & (y <= -c[0])
        return x, np.where(inside, values * v0, 0.0)

    @time_by_keyword("t={value} or time={value} (a saved time)")
    def histogram(self, edges, *, t: float | None = None, time: float | None = None):
        """The prediction on bins of x = (v_x − u_x)/√T as a
        :class:`particles.observables.Histogram` (bin probability / width from the exact
        integral of the marginal's Fourier series, zero errors, ``v0`` = √T).

        Parameters
        ----------
        edges : array_like
            Increasing finite edges in x.
        t : float, optional
            A saved time (default the last).
        time : float, optional
            The same as ``t``.

        Returns
        -------
        particles.observables.Histogram

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``edges``, ``t``, or ``time`` with ``t``.
        TypeError
            For a second positional argument (the time is keyword-only), naming ``t=``.
        """
        from particles.observables import Histogram

        from .kinetic_histogram import check_edges

        time = pick_time("t", t, time)
        edges = check_edges(edges)
        k_index = self.time_index(time)
        v0, c, coefficients, k = self._series(time)
        y = np.clip(edges * v0, c[0], -c[0]) - c[0]
        safe = np.where(k == 0.0, 1.0, k)
        antiderivative = np.where(k[None, :] == 0.0, y[:, None],
                                  (np.exp(1j * y[:, None] * k[None, :]) - 1.0) / (1j * safe))
        cumulative = np.real(antiderivative @ coefficients)
        width = np.diff(edges)
        return Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), np.diff(cumulative) / width,
                         np.zeros(width.size), np.zeros(width.size, dtype=np.int64), 0,
                         float(self.scale[k_index] * v0))

    def to_xarray(self):
        """The solution as an ``xarray.Dataset``: ``F`` over (``t``, ``c1`` … ``cd``),
        ``log_scale``, ``temperature``, ``a2``, ``a3``, ``cooling_rate`` over ``t``.

        Returns
        -------
        xarray.Dataset

        Raises
        ------
        ImportError
            When xarray is not installed.
        """
        import json

        from particles.driver.result import import_xarray

        xr = import_xarray("SphereSolution.to_xarray()")
        dims = tuple(f"c{a + 1}" for a in range(self.dimension))
        data = {"F": (("t",) + dims, np.asarray(self.F)), "log_scale": (("t",), self.log_scale),
                "temperature": (("t",), self.temperature), "a2": (("t",), self.a2),
                "a3": (("t",), self.a3), "cooling_rate": (("t",), self.cooling_rate)}
        coords = {"t": self.times, **{d: self.grid.nodes() for d in dims}}
        meta, _ = self.to_record()
        return xr.Dataset(data, coords=coords, attrs={key: json.dumps(value) if
                                                      isinstance(value, (dict, list))
                                                      else value for key, value in meta.items()})

    def plot(self, ax=None):
        """ln P(x) of one component at every saved t
        (:func:`maxwell_kinetics.kinetic_result.plot_densities`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            The panel.

        Returns
        -------
        matplotlib.axes.Axes
        """
        return plot_densities(self, ax)

    # -- persistence -------------------------------------------------------------------------
    def to_record(self) -> tuple[dict, dict]:
        """(meta, arrays): what :meth:`save` writes.

        Returns
        -------
        meta : dict
        arrays : dict of str to numpy.ndarray
        """
        meta = {"kernel": self.kernel, "restitution": float(self.restitution),
                "exponent": float(self.exponent), "dimension": int(self.dimension),
                "number_density": float(self.number_density), "initial": str(self.initial),
                "grid": self.grid.to_dict(), "steps": int(self.steps),
                "seconds": float(self.seconds)}
        arrays = {"t": np.asarray(self.t), "F": np.asarray(self.F),
                  "log_scale": np.asarray(self.log_scale), "mean": np.asarray(self.mean),
                  "cooling_rate": np.asarray(self.cooling_rate)}
        return meta, arrays

    @classmethod
    def from_record(cls, meta: dict, arrays: dict, path="solution") -> SphereSolution:
        """Inverse of :meth:`to_record`.

        Parameters
        ----------
        meta : dict
            The parameters.
        arrays : dict
            The arrays.
        path : str or os.PathLike, optional
            The source's name, for errors.

        Returns
        -------
        SphereSolution

        Raises
        ------
        particles.persistence.FileFormatError
            When a key is missing or a value is of the wrong type.
        """
        try:
            grid = SphereGrid(**meta["grid"])
            return cls(str(meta["kernel"]), float(meta["restitution"]), float(meta["exponent"]),
                       int(meta["dimension"]), float(meta["number_density"]),
                       str(meta["initial"]), grid, np.asarray(arrays["t"]),
                       np.asarray(arrays["F"]), np.asarray(arrays["log_scale"]),
                       np.asarray(arrays["mean"]), np.asarray(arrays["cooling_rate"]),
                       int(meta["steps"]), float(meta["seconds"]))
        except (KeyError, ValueError, TypeError, InvalidArgumentError) as exc:
            raise persistence.FileFormatError(path, f"{type(exc).__name__}: {exc}", "path",
                                              "a saved SphereSolution") from None

    def save(self, path) -> None:
        """Save to ``path`` (:mod:`particles.persistence`, kind ``"sphere_solution"``);
        :meth:`load` reads it back bit for bit.

        Parameters
        ----------
        path : str or os.PathLike
            The file.
        """
        meta, arrays = self.to_record()
        persistence.save(path, "sphere_solution", _SAVED_VERSION, arrays, meta)

    @classmethod
    def load(cls, path) -> SphereSolution:
        """Read a file written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            The file.

        Returns
        -------
        SphereSolution

        Raises
        ------
        particles.persistence.FileFormatError
            When the file is not a saved SphereSolution.
        """
        loaded = persistence.load(path, "sphere_solution", (_SAVED_VERSION,),
                                  expected="a saved SphereSolution")
        return cls.from_record(loaded.meta, loaded.arrays, path)


#: Version of the saved SphereSolution format.
_SAVED_VERSION = 1
