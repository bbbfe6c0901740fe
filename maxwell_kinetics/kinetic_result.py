"""The one contract of a kinetic solve's result: :class:`KineticResult`, met by
:class:`maxwell_kinetics.solution.Solution` (the Fourier scheme of
:func:`maxwell_kinetics.solver.solve`) and by
:class:`maxwell_kinetics.boltzmann_solution.BoltzmannSolution` (the velocity grid of
:func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`).

Conventions.

* Time.  ``times`` holds the saved times and ``time_name`` names them: ``"tau"``, collisions per
  particle τ (``Solution``, whose ``tau`` attribute is the same array), or ``"t"``, the physical
  time (``BoltzmannSolution``, whose ``t`` attribute is the same array).  A method that reads one
  time takes it by value as the keyword ``time=`` on both (a saved time, to a relative 1e-12;
  default the last); each result also keeps its own keyword (``tau=``, ``tau_index`` for
  ``Solution``; ``t`` for ``BoltzmannSolution``), and giving both is refused.
* Velocity units.  Both start from a unit initial variance per component (⟨v²⟩ = 1 in d = 1).
  ``density`` and ``histogram`` are in the rescaled velocity x = (v − u)/v₀ with v₀ the standard
  deviation of one component at that time: ``Solution``: v₀(τ) = e^{−Λτ/2} (u = 0; Λ = 2λ in
  d = 1); ``BoltzmannSolution``: v₀(t) = √⟨(v − u)²⟩(t), u the conserved mean.
* Moments.  ``moments(orders)`` returns a :class:`maxwell_kinetics.moments.Moments` with one row
  per saved time: ``values`` rescaled by v₀ (order 2 gives d), ``raw()`` = ``values`` × v₀^k in
  the units of the initial law (for ``BoltzmannSolution`` the central moments ⟨(v − u)^k⟩,
  the array its ``moments`` returned before), ``errors`` (the window estimate of the Fourier
  read-out; 0 on the velocity grid, whose sums are exact for its discrete law).  ``Solution``
  takes even orders only, ``BoltzmannSolution`` any integer order ≥ 0.
* ``energy`` is ⟨|v|²⟩ at each saved time (``Solution``: d e^{−Λτ}; ``BoltzmannSolution``:
  u² + ⟨(v − u)²⟩), ``kurtosis`` ⟨|v − u|⁴⟩/⟨|v − u|²⟩² (arrays of shape (T,), properties).
* ``density(x=None, *, time=None)`` returns ``(x, P)``: P(x) at the given x, or on the result's
  own grid when x is None (``Solution``: the FFT grid; ``BoltzmannSolution``: its nodes).
* ``histogram(edges, *, time=None)`` returns a :class:`particles.observables.Histogram` with
  ``v0`` = v₀ of that time; its ``error`` is the prediction's numerical error, estimated by the
  result itself where it can (``Solution``: grid and cut at q_max,
  :func:`maxwell_kinetics.kinetic_histogram.bin_errors`), else 0 (``BoltzmannSolution``).
* ``save(path)`` and the class method ``load(path)`` round-trip every array bit for bit
  (:mod:`particles.persistence`); ``to_xarray()`` labels the time coordinate ``time_name``;
  ``plot(ax=None)`` draws the density at every saved time (:func:`plot_densities`) and returns
  the Axes.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from particles.validation import InvalidArgumentError

__all__ = ["KineticResult", "pick_time", "plot_densities", "time_by_keyword"]


@runtime_checkable
class KineticResult(Protocol):
    """What every kinetic result offers (conventions: the module docstring).

    Attributes
    ----------
    times : numpy.ndarray
        The saved times, shape (T,).
    time_name : str
        ``"tau"`` or ``"t"``.
    energy : numpy.ndarray
        ⟨|v|²⟩ at each saved time, shape (T,).
    kurtosis : numpy.ndarray
        ⟨|v − u|⁴⟩/⟨|v − u|²⟩² at each saved time, shape (T,).
    """

    @property
    def times(self) -> np.ndarray: ...

    @property
    def time_name(self) -> str: ...

    @property
    def energy(self) -> np.ndarray: ...

    @property
    def kurtosis(self) -> np.ndarray: ...

    def moments(self, orders=(2, 4, 6)):
        """The moments at every saved time.

        Parameters
        ----------
        orders : sequence of int
            The orders.

        Returns
        -------
        maxwell_kinetics.moments.Moments
            One row per saved time.
        """

    def density(self, x=None, *, time=None):
        """P(x) of the rescaled velocity at one saved time.

        Parameters
        ----------
        x : array_like, optional
            Rescaled velocities; None for the result's own grid.
        time : float, optional
            A saved time (default the last).

        Returns
        -------
        x, P : numpy.ndarray
            The velocities and the density there.
        """

    def histogram(self, edges, *, time=None):
        """The predicted histogram on ``edges`` at one saved time.

        Parameters
        ----------
        edges : array_like
            Increasing bin edges in the rescaled velocity.
        time : float, optional
            A saved time (default the last).

        Returns
        -------
        particles.observables.Histogram
            Bin probabilities / width; ``error``: the numerical error (module docstring).
        """

    def save(self, path) -> None:
        """Write the result to ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        """

    def to_xarray(self):
        """The result as an ``xarray.Dataset``, its time coordinate named ``time_name``.

        Returns
        -------
        xarray.Dataset
            The labelled arrays.
        """

    def plot(self, ax=None):
        """Draw the density at the saved times.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            The panel; default a new figure's.

        Returns
        -------
        matplotlib.axes.Axes
            The panel drawn in.
        """


def pick_time(own_name: str, own, time):
    """The time a method was given, by its own keyword (``own_name``, value ``own``) or by the
    shared keyword ``time``.

    Parameters
    ----------
    own_name : str
        The result's own keyword (``"tau"`` or ``"t"``), for the error.
    own : float or None
        Its value.
    time : float or None
        The value of ``time=``.

    Returns
    -------
    float or None
        The one given, or None.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``time`` when both are given.
    """
    if time is None:
        return own
    if own is not None:
        raise InvalidArgumentError("time", time, f"either time or {own_name}, not both "
                                   f"({own_name}={own!r} was given too)")
    return time


def plot_densities(result, ax=None, limit: float = 8.0):
    """ln P(x) against the rescaled velocity x, one line per saved time of a
    :class:`KineticResult` (``result.density(time=...)`` on its own grid, |x| ≤ ``limit``).
    matplotlib is imported here, on first use, never when this module is imported; a new
    figure is made without :mod:`matplotlib.pyplot` (on its own Agg canvas).

    Parameters
    ----------
    result : KineticResult
        The result.
    ax : matplotlib.axes.Axes, optional
        The panel to draw in; default the one panel of a new figure.
    limit : float, optional
        Largest |x| drawn.

    Returns
    -------
    matplotlib.axes.Axes
        The panel, with one line per saved time.
    """
    from matplotlib import colormaps

    if ax is None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        figure = Figure(figsize=(5.0, 4.0))
        FigureCanvasAgg(figure)
        ax = figure.add_subplot()
    name = result.time_name
    symbol = "τ" if name == "tau" else name
    colors = colormaps["viridis"](np.linspace(0.0, 0.9, len(result.times)))
    for color, time in zip(colors, result.times, strict=True):
        x, P = result.density(time=float(time))
        x, P = np.asarray(x, dtype=float), np.asarray(P, dtype=float)
        keep = (np.abs(x) <= limit) & (P > 1e-300)
        ax.semilogy(x[keep], P[keep], color=color, label=f"{symbol} = {time:g}")
    ax.set(xlabel="x = (v − u) / v0", ylabel="P(x)")
    ax.legend(fontsize=7)
    return ax


def time_by_keyword(keywords: str):
    """Decorator of a method ``method(self, first, *, ...)`` whose time is keyword-only: a
    second positional argument, which reads differently on different results (an index into
    ``tau`` for :meth:`maxwell_kinetics.solution.Solution.histogram`, a time ``t`` for
    :meth:`maxwell_kinetics.boltzmann_solution.BoltzmannSolution.histogram`), is refused with a
    TypeError naming the keywords to use, instead of Python's bare count of arguments.

    Parameters
    ----------
    keywords : str
        The keywords to use, with ``{value}`` standing for the value received, e.g.
        ``"tau_index={value} (an index into tau) or tau={value} (a saved time)"``.

    Returns
    -------
    callable
        The decorator (the method keeps its name, docstring and signature).
    """
    import functools

    def decorate(method):
        @functools.wraps(method)
        def keyword_time(self, *args, **kwargs):
            if len(args) > 1:
                value = args[1]
                raise TypeError(f"{type(self).__name__}.{method.__name__}() takes its time by "
                                f"keyword only: {keywords.format(value=repr(value))}; got "
                                f"{value!r} as a second positional argument")
            return method(self, *args, **kwargs)

        return keyword_time

    return decorate
