"""The velocity grids of :mod:`maxwell_kinetics.inelastic_boltzmann` and the initial law on them.

A grid is a set of nodes c_i of the rescaled velocity c = (v − u)/s with trapezoid weights
ω_i:

* :class:`VelocityGrid`: uniform, c_i = (i − (N − 1)/2) h on [−L, L], ω_i = h (the default);
* :class:`MappedGrid`: c = a sinh(s) on a uniform grid of s, ω_i = g′(s_i) h_s, for the
  |c|⁻⁴ tail of the Maxwell model (γ = 0 only).

:func:`initial_values` samples an initial law at the nodes (the derivative of its CDF, sixth
order) and multiplies it by 1 + a + b c + d c² with the three numbers that make the discrete
mass 1, mean 0 and ⟨c²⟩ 1.  A grid whose extent leaves more than :data:`EXTENT_TOLERANCE` of the
law's mass outside, or whose raw moments are off by more than :data:`RESOLUTION_TOLERANCE`, is
refused with the size needed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from particles.initial import InitialLaw, get_law
from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_positive,
)

__all__ = ["VelocityGrid", "MappedGrid", "check_grid", "default_grid", "initial_values", "grid_sum",
           "EXTENT_TOLERANCE", "RESOLUTION_TOLERANCE", "MAX_SPACING", "MAX_POINTS",
           "MAX_MAPPED_HALF_WIDTH"]

#: Largest mass fraction of the initial law that may lie outside the grid (its moments of order
#: ≤ 6 then change by less than ~1e-6; the nodes inside are renormalised).
EXTENT_TOLERANCE = 1e-8
#: Largest relative error of the grid's raw mass and variance of the initial law (before the
#: correction that makes them exact): a larger one means the spacing does not resolve the law.
RESOLUTION_TOLERANCE = 1e-3
#: Largest grid spacing h, in units of the initial standard deviation (hard rods, r = 0.99,
#: t = 400: h = 0.2 errs by 3.6e-4 in the kurtosis, benchmarks/README.md).
MAX_SPACING = 0.25
#: Most grid points (the collision tables hold N² M numbers).
MAX_POINTS = 1601
#: Largest half-width of a :class:`MappedGrid` (c⁶ and the weights a h_s cosh s stay finite
#: with a wide margin; the widest measured grid is ±2·10⁵).
MAX_MAPPED_HALF_WIDTH = 1e30


@dataclass(frozen=True)
class VelocityGrid:
    """A uniform grid of the rescaled velocity c = (v − u)/s on [−half_width, half_width].

    Attributes
    ----------
    points : int
        Number N of nodes (odd N puts a node at c = 0), 8 ≤ N ≤ ``MAX_POINTS``.
    half_width : float
        L > 0: the nodes are c_i = −L + i h, h = 2L/(N − 1), in units of the standard deviation.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``points`` or ``half_width`` for a value out of range.
    """

    points: int
    half_width: float

    def __post_init__(self):
        n = check_count(self.points, "points", 8)
        if n > MAX_POINTS:
            raise InvalidArgumentError("points", self.points,
                                       f"at most {MAX_POINTS} grid points (the collision "
                                       "tables grow as points squared)")
        object.__setattr__(self, "points", n)
        object.__setattr__(self, "half_width", check_positive(self.half_width, "half_width"))

    @property
    def c(self) -> np.ndarray:
        """The nodes c_i, shape (N,)."""
        return np.linspace(-self.half_width, self.half_width, self.points)

    @property
    def h(self) -> float:
        """The spacing 2L/(N − 1)."""
        return 2.0 * self.half_width / (self.points - 1)

    @property
    def step(self) -> float:
        """The spacing h (the step of the uniform variable of the scheme)."""
        return self.h

    @property
    def weights(self) -> np.ndarray:
        """The trapezoid weights: h at every node, shape (N,)."""
        return np.full(self.points, self.h)


@dataclass(frozen=True)
class MappedGrid:
    """A non-uniform grid of the rescaled velocity, fine in the core and wide in the tails:
    c = a sinh(s) on the uniform grid s_i = −S + i h_s, i = 0 … N − 1, h_s = 2S/(N − 1).

    The map's two numbers follow from the requested extent and core spacing:
    a sinh(S) = half_width and a h_s = core_spacing (the spacing at c = 0), i.e.
    sinh(S)/S = 2 half_width/(core_spacing (N − 1)).  The local spacing is
    ω(c) = h_s √(a² + c²): ≈ core_spacing for |c| ≪ a, ≈ h_s |c| (a fixed relative spacing h_s)
    for |c| ≫ a, the shape an algebraic tail such as the |x|⁻⁴ of the Maxwell model needs.
    Integrals are the trapezoid rule in s (weights ω_i = ω(c_i), :attr:`weights`); the
    solver interpolates in s (:mod:`maxwell_kinetics._boltzmann_scheme`).  All velocities are
    in units of the standard deviation of c (the grid's ⟨c²⟩ = 1).

    For γ = 0 only (:func:`solve_boltzmann` refuses it otherwise, naming ``grid``): every
    integrand is then smooth in s, the trapezoid rule spectral, the interpolation (10 points)
    O(h_s¹⁰) and the dilation O(h_s⁸).  Measured (benchmarks/README.md, ``hard_rods.py
    mapped``): r = 0.5, 561 points on ±2·10⁵, core spacing 0.07: the kurtosis at τ = 10 and 50
    within 1.2e-8 and 5.5e-8 (relative) of −3 + 6e^{9τ/128}, P(x) within 1.1e-7 of the Fourier
    solver.  For hard rods (γ = 1; the kink at v = w corrected with the local spacing) the
    mapped grid converged on some sizes (r = 0.8, t = 2, ±12: the kurtosis within 4.5e-7 at 81
    points, 2.3e-8 at 161 of a fine uniform grid) but grew a grid-scale oscillation at the
    grid's ends on others (41 and 121 points: kurtosis 3.16 and 98.8 instead of 2.85); until
    that is understood, γ > 0 keeps the uniform grid.  At γ = 0 on the same map (r = 0.8,
    t = 2) the kurtosis errs by 0.063, 1.7e-5, 2.9e-8, −3.5e-9 and −4.0e-10 at 41, 61, 81, 121
    and 161 points; the 41-point grid, too coarse in its tails, shows it in
    :attr:`BoltzmannSolution.edge_mass`.

    Attributes
    ----------
    points : int
        N, odd or even, 8 ≤ N ≤ ``MAX_POINTS``.
    half_width : float
        L > 0: the outermost nodes are ±L.
    core_spacing : float
        The spacing at c = 0, > 0 and below the uniform spacing 2L/(N − 1) (else the uniform
        :class:`VelocityGrid` is the right grid).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``points``, ``half_width`` or ``core_spacing`` for a value out of range
        (``half_width`` above :data:`MAX_MAPPED_HALF_WIDTH` too).
    """

    points: int
    half_width: float
    core_spacing: float
    scale: float = field(init=False, repr=False)
    s_max: float = field(init=False, repr=False)

    def __post_init__(self):
        n = VelocityGrid(self.points, self.half_width).points  # the same checks
        object.__setattr__(self, "points", n)
        L = check_positive(self.half_width, "half_width")
        if L > MAX_MAPPED_HALF_WIDTH:
            raise InvalidArgumentError("half_width", self.half_width, f"a half-width <= "
                                       f"{MAX_MAPPED_HALF_WIDTH:g} (beyond, the powers of c the "
                                       "solver forms overflow)")
        object.__setattr__(self, "half_width", L)
        h0 = check_positive(self.core_spacing, "core_spacing")
        object.__setattr__(self, "core_spacing", h0)
        ratio = 2.0 * L / (h0 * (n - 1))
        if not ratio > 1.0 + 1e-9:
            raise InvalidArgumentError(
                "core_spacing", self.core_spacing,
                f"a core spacing below the uniform spacing 2 half_width/(points - 1) = "
                f"{2.0 * L / (n - 1):.6g} (else use the uniform VelocityGrid)")
        lo, hi = 0.0, max(1.0, math.log(4.0 * ratio) + math.log(math.log(4.0 * ratio) + 1.0))
        while math.sinh(hi) / hi < ratio:
            hi *= 2.0
        for _ in range(200):  # bisection on sinh(S)/S = ratio (increasing in S)
            mid = 0.5 * (lo + hi)
            if mid == 0.0 or math.sinh(mid) / mid < ratio:
                lo = mid
            else:
                hi = mid
        S = 0.5 * (lo + hi)
        object.__setattr__(self, "s_max", S)
        object.__setattr__(self, "scale", L / math.sinh(S))

    @property
    def step(self) -> float:
        """h_s = 2S/(N − 1), the step of the uniform variable s."""
        return 2.0 * self.s_max / (self.points - 1)

    @property
    def s(self) -> np.ndarray:
        """The uniform nodes s_i, shape (N,)."""
        return np.linspace(-self.s_max, self.s_max, self.points)

    @property
    def c(self) -> np.ndarray:
        """The nodes c_i = a sinh(s_i), shape (N,)."""
        return self.scale * np.sinh(self.s)

    def spacing(self, x) -> np.ndarray:
        """The local spacing ω(x) = g′(s(x)) h_s = h_s √(a² + x²).

        Parameters
        ----------
        x : array_like
            Velocities c (units of the standard deviation).

        Returns
        -------
        numpy.ndarray
            ω(x), of the shape of ``x``.
        """
        x = np.asarray(x, dtype=float)
        return self.step * np.sqrt(self.scale**2 + x * x)

    def position(self, x) -> np.ndarray:
        """Velocities in units of node index: (asinh(x/a) + S)/h_s (node i at i).

        Parameters
        ----------
        x : array_like
            Velocities c.

        Returns
        -------
        numpy.ndarray
            The fractional index, of the shape of ``x``.
        """
        return (np.arcsinh(np.asarray(x, dtype=float) / self.scale) + self.s_max) / self.step

    @property
    def weights(self) -> np.ndarray:
        """The trapezoid weights ω_i = g′(s_i) h_s, shape (N,)."""
        return self.spacing(self.c)


def grid_sum(grid, values: np.ndarray, g: np.ndarray):
    """The trapezoid rule Σ_i ω_i values_i g_i on ``grid`` (h (values @ g) on the uniform grid).

    Parameters
    ----------
    grid : VelocityGrid or MappedGrid
        The grid, whose weights ω_i are used.
    values : numpy.ndarray
        Shape (..., N): values at the nodes (e.g. F, or rows of F at several times).
    g : numpy.ndarray
        Shape (N,): the function weighed against them (e.g. c**k).

    Returns
    -------
    numpy.ndarray or float
        Shape ``values.shape[:-1]``.
    """
    if isinstance(grid, MappedGrid):
        return (values * grid.weights) @ g
    return grid.h * (values @ g)


def check_grid(grid) -> VelocityGrid | MappedGrid:
    """``grid`` if it is a :class:`VelocityGrid` or a :class:`MappedGrid`.

    Parameters
    ----------
    grid : object
        The grid given.

    Returns
    -------
    VelocityGrid or MappedGrid
        ``grid``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``grid`` otherwise.
    """
    if not isinstance(grid, (VelocityGrid, MappedGrid)):
        raise InvalidArgumentError("grid", grid, "a VelocityGrid(points, half_width), a "
                                   "MappedGrid(points, half_width, core_spacing) or None")
    return grid


def default_grid(exponent: float) -> VelocityGrid:
    """The grid used when none is given: 201 points on [−6, 6] for γ > 0 (hard rods: the
    kurtosis at t = 400, r = 0.99 converged to ~1e-6, benchmarks/README.md); 401 points on
    [−40, 40] for γ = 0, whose |x|⁻⁴ tail needs a wide grid.

    Parameters
    ----------
    exponent : float
        γ of the rate.

    Returns
    -------
    VelocityGrid
        The grid.
    """
    if exponent == 0.0:
        return VelocityGrid(401, 40.0)
    return VelocityGrid(201, 6.0)


def _density_at(law: InitialLaw, v: np.ndarray) -> np.ndarray:
    """The law's density at ``v``: the sixth-order central difference of its CDF, step 0.01."""
    d = 0.01
    F = law.cdf
    diff = [F(v + k * d) - F(v - k * d) for k in (1, 2, 3)]
    return (45.0 * diff[0] - 9.0 * diff[1] + diff[2]) / (60.0 * d)


def _raw_moments(values: np.ndarray, c: np.ndarray, h: float) -> np.ndarray:
    return np.array([h * np.sum(values * c**k) for k in range(3)])


def initial_values(law, grid: VelocityGrid) -> np.ndarray:
    """The initial law on the grid: unit mass, zero mean and unit ⟨c²⟩ exactly (module
    docstring).

    Parameters
    ----------
    law : str or particles.initial.InitialLaw
        A built-in law's name or a law with a CDF (zero mean, unit variance).
    grid : VelocityGrid or MappedGrid
        The grid.

    Returns
    -------
    numpy.ndarray
        F(c_i, 0), shape (N,).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``initial`` for a law without a CDF; ``half_width`` when more than
        :data:`EXTENT_TOLERANCE` of the mass lies outside the grid, ``points`` when the spacing
        exceeds :data:`MAX_SPACING` or does not resolve the law (:data:`RESOLUTION_TOLERANCE`);
        both with the size needed; ``half_width`` again when no grid of at most
        :data:`MAX_POINTS` points has a spacing below :data:`MAX_SPACING` on it.  On a
        :class:`MappedGrid`: ``core_spacing`` above
        :data:`MAX_SPACING`, ``points`` when the mapped weights do not resolve the law.
    """
    law = get_law(law)
    if law.distribution is None:
        raise InvalidArgumentError("initial", law.name, "a law with a known CDF (the velocity-"
                                   "space solver samples its density)")
    L = grid.half_width
    outside = float(law.cdf(np.array([-L]))[0] + 1.0 - law.cdf(np.array([L]))[0])
    if not outside <= EXTENT_TOLERANCE:
        needed = L
        while needed < 1e6 and not (law.cdf(np.array([-needed]))[0]
                                    + 1.0 - law.cdf(np.array([needed]))[0]) <= EXTENT_TOLERANCE:
            needed *= 1.25
        raise InvalidArgumentError(
            "half_width", L, f"a grid that holds the initial law {law.name!r} (a fraction "
            f"{outside:.3g} of its mass lies outside [-{L:g}, {L:g}]; at most "
            f"{EXTENT_TOLERANCE:g}: half_width >= {needed:.3g})")

    if isinstance(grid, MappedGrid):
        return _mapped_initial_values(law, grid)

    def defect(points: int) -> float:
        g = VelocityGrid(points, L) if points <= MAX_POINTS else None
        c = g.c if g else np.linspace(-L, L, points)
        h = 2.0 * L / (points - 1)
        m = _raw_moments(_density_at(law, c), c, h)
        return max(abs(m[0] - 1.0), abs(m[1]), abs(m[2] - 1.0))

    if grid.h > MAX_SPACING:
        needed = math.ceil(2.0 * L / MAX_SPACING) + 1
        if needed > MAX_POINTS:  # no grid of points can do it: the half-width is too large
            widest = MAX_SPACING * (MAX_POINTS - 1) / 2.0
            raise InvalidArgumentError(
                "half_width", L, f"a half-width <= {widest:g} (a spacing 2 half_width/(points - 1)"
                f" <= {MAX_SPACING:g} with at most {MAX_POINTS} points)")
        raise InvalidArgumentError(
            "points", grid.points, f"a spacing 2 half_width/(points - 1) <= {MAX_SPACING:g} "
            f"(it is {grid.h:.3g} on [-{L:g}, {L:g}]): at least {needed} points")
    found = defect(grid.points)
    if not found <= RESOLUTION_TOLERANCE:
        needed = grid.points
        while needed < 10**6 and not defect(needed) <= RESOLUTION_TOLERANCE:
            needed = 2 * needed - 1
        raise InvalidArgumentError(
            "points", grid.points, f"a grid fine enough for the initial law {law.name!r} (its "
            f"mass, mean or variance on {grid.points} points on [-{L:g}, {L:g}] is off by "
            f"{found:.3g}; at most {RESOLUTION_TOLERANCE:g}: about {needed} points)")
    c, h = grid.c, grid.h
    values = _density_at(law, c)
    # F (1 + a + b c + d c²) with unit mass, zero mean and unit second moment
    basis = np.array([values * c**k for k in range(3)])
    matrix = h * np.array([[np.sum(basis[j] * c**k) for j in range(3)] for k in range(3)])
    coefficients = np.linalg.solve(matrix, np.array([1.0, 0.0, 1.0]))
    return values * (coefficients[0] + coefficients[1] * c + coefficients[2] * c * c)


def _mapped_initial_values(law: InitialLaw, grid: MappedGrid) -> np.ndarray:
    """:func:`initial_values` on a mapped grid (the extent already checked)."""
    if grid.core_spacing > MAX_SPACING:
        raise InvalidArgumentError(
            "core_spacing", grid.core_spacing, f"a core spacing <= {MAX_SPACING:g}")

    def raw(g: MappedGrid) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c, w = g.c, g.weights
        values = _density_at(law, c)
        return values, c, np.array([(values * w) @ c**k for k in range(3)])

    values, c, m = raw(grid)
    found = max(abs(m[0] - 1.0), abs(m[1]), abs(m[2] - 1.0))
    if not found <= RESOLUTION_TOLERANCE:
        needed = grid.points
        while needed <= MAX_POINTS:
            needed = 2 * needed - 1
            try:
                finer = MappedGrid(needed, grid.half_width, grid.core_spacing)
            except InvalidArgumentError:
                break
            m2 = raw(finer)[2]
            if max(abs(m2[0] - 1.0), abs(m2[1]), abs(m2[2] - 1.0)) <= RESOLUTION_TOLERANCE:
                break
        raise InvalidArgumentError(
            "points", grid.points, f"a grid fine enough for the initial law {law.name!r} (its "
            f"mass, mean or variance on the mapped grid of {grid.points} points on "
            f"[-{grid.half_width:g}, {grid.half_width:g}], core spacing "
            f"{grid.core_spacing:g}, is off by {found:.3g}; at most {RESOLUTION_TOLERANCE:g}: "
            f"about {needed} points)")
    w = grid.weights
    basis = np.array([values * c**k for k in range(3)])
    matrix = np.array([[np.sum(w * basis[j] * c**k) for j in range(3)] for k in range(3)])
    coefficients = np.linalg.solve(matrix, np.array([1.0, 0.0, 1.0]))
    return values * (coefficients[0] + coefficients[1] * c + coefficients[2] * c * c)
