"""The overpopulated high-energy tail of the homogeneous cooling state (HCS) of inelastic hard
spheres (d = 3) and disks (d = 2): the predicted exponential rate A (:func:`tail_rate`) and its
measurement on the spectral solver's grid (:func:`radial_profile`, :func:`fit_tail`,
:func:`measure_tail`).

Prediction (the conventions of :mod:`maxwell_kinetics.sphere_spectral`).  The grid's c is the
scaled velocity of unit variance per component, c = (v − u)/√T with T = ⟨|v − u|²⟩/d, and the
scaled time is dτ = n s^γ dt (s = √T; γ = 1 for hard spheres).  The scaled equation is
∂F/∂τ = Q(F, F) + σ′ ∇·(cF), the cooling rate ζ* = −2σ′ = −d ln T/dτ, so the cooling state
(∂F/∂τ = 0) of an isotropic F(c), c = |c| here, obeys

    Q(F, F) = (ζ*/2) ∇·(cF) = (ζ*/2) (d F + c dF/dc).

Write Q = G − ν F.  The loss rate of a particle at c is
ν(c) = ∫dw F(w) ∫dn |(c − w)·n| = K ⟨|c − w|⟩ with K = ∫_{S^{d−1}} |ĝ·n| dn over the WHOLE
unit sphere (:meth:`particles.sphere_kernels.HardSpheres.sphere_factor`: 2π in d = 3, 4 in
d = 2, twice the hemisphere's π and 2), and for c ≫ 1, with ⟨w⟩ = 0 and ⟨|w|²⟩ = d,
ν(c) = K [c + (d − 1)/(2c) + O(c⁻³)]: a fast particle's collision frequency grows like c.
The gain at c is of order F(c) (grazing collisions of particles barely faster than c; not
of order cF), so dividing the balance by (ζ*/2) c F,

    d ln F/dc = −2K/ζ* − (d − 2g/ζ*)/c + O(c⁻²),    g = lim G/F,

i.e. F(c) ∝ c^μ exp(−A c) at large c with

    A = 2K/ζ*        (unit-variance c, τ = ∫ n √T dt),

and μ = −d + 2g/ζ*, which this module does not predict (the fit leaves it free).  A is the
exponential tail of Esipov and Pöschel (1997) and van Noije and Ernst (1998).  In the Sonine
variable c̃ = (v − u)/√(2T) = c/√2 the tail is exp(−√2 A c̃); with the Maxwellian's cooling
rate ζ* = (1 − α²) ν₀/d (ν₀ = 8√π in d = 3, a₂ = 0) that is exp(−3√(2π) c̃/(2(1 − α²))).
For variable hard spheres of rate |g| (γ = 1, isotropic scattering) K = 1 (the rate itself);
for γ < 1 the same balance gives exp(−2K c^γ/(γ ζ*)) (γ = 0: no exponential at all, the Maxwell
model's tail is the power law c^(−d−2s*) of :mod:`maxwell_kinetics.tails`), so
:func:`tail_rate` accepts γ = 1 kernels only.

The exponential is reached only where exp(−A c) beats the Gaussian core exp(−c²/2), c ≳ 2A
(d = 2, α = 0.5: A ≈ 3, c ≳ 6); on the grid the tail is resolved only where F is above the
round-off of the FFTs, well inside the kernel's cutoff R (a particle at c collides with
partners at |c − w| ≤ R only: the loss is exact for c ≲ R − 4) and inside the box L.

Measurement.  :func:`radial_profile` averages ln F over shells of |c| at the grid's nodes
(each shell kept only when every node in it is above the round-off floor and the shell lies
inside the kernel's cutoff R < L, beyond which the truncated kernel and the absorbing layer at
the box's faces make F unphysical); :func:`fit_tail` fits ln F = a + μ ln c − A c to the nodes
of the shells whose mean |c| lies in a window, by least squares with every shell weighted once
(exact for an F of that form), with the standard errors of the fit (from the scatter about it,
n − 3 degrees of freedom for n shells) and a window systematic: the largest change of A when
the window moves by ± ``shift``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from particles.validation import InvalidArgumentError, check_positive

from .sphere_grid import SphereGrid, sphere_grid

__all__ = ["tail_rate", "node_speeds", "RadialProfile", "radial_profile", "TailFit",
           "fit_tail", "measure_tail", "MIN_SHELLS"]

#: The fewest shells a fit takes (three parameters: at least two degrees of freedom).
MIN_SHELLS = 5


def tail_rate(kernel, dimension: int, cooling_rate: float) -> float:
    """The predicted rate A of the cooling state's exponential tail F ∝ c^μ exp(−A c):
    A = 2K/ζ* (module docstring), c of unit variance per component.

    Parameters
    ----------
    kernel : particles.kernels.Kernel
        A kernel of rate K |g| (homogeneity γ = 1): :class:`particles.sphere_kernels.HardSpheres`
        (K = β_d = 2π in d = 3, 4 in d = 2) or
        :class:`~particles.sphere_kernels.VariableHardSpheres` at γ = 1 (K = 1).
    dimension : int
        d, 2 or 3.
    cooling_rate : float
        ζ* = −d ln T/dτ of the cooling state
        (:attr:`maxwell_kinetics.sphere_spectral.CoolingState.cooling_rate`), > 0.

    Returns
    -------
    float
        A.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``dimension`` (not 2 or 3), ``kernel`` (no ``rate``, or not homogeneous of
        degree 1: for γ < 1 the tail is not exponential) or ``cooling_rate`` (not > 0).
    """
    if dimension not in (2, 3) or isinstance(dimension, bool):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    gamma = getattr(kernel, "homogeneity", None)
    if not hasattr(kernel, "rate") or gamma is None or float(gamma) != 1.0:
        raise InvalidArgumentError(
            "kernel", kernel, "a kernel of rate K|v − w| (γ = 1); for γ < 1 the tail is "
            "exp(−A c^γ), and the Maxwell model's (γ = 0) a power law")
    zeta = check_positive(cooling_rate, "cooling_rate")
    v = np.zeros((1, dimension))
    v[0, 0] = 1.0
    k = float(np.asarray(kernel.rate(v, np.zeros_like(v), np))[0])  # the rate at |g| = 1
    return 2.0 * k / zeta


def node_speeds(grid, dimension: int, axis_gap: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """|c| at the grid's nodes, and which nodes lie at least ``axis_gap`` degrees from every
    coordinate axis (the angle to the nearest axis has cos = max_a |c_a| / |c|; the origin
    counts as off the axes).

    Parameters
    ----------
    grid : str or SphereGrid
        The grid (:func:`maxwell_kinetics.sphere_grid.sphere_grid`).
    dimension : int
        d, 2 or 3.
    axis_gap : float, default 0
        The angle in degrees (0: every node is kept).

    Returns
    -------
    speed : numpy.ndarray
        |c|, shape (N,)*d.
    keep : numpy.ndarray of bool
        The nodes off the axes, shape (N,)*d.
    """
    g = sphere_grid(grid, dimension)
    axes = np.meshgrid(*([g.nodes()] * dimension), indexing="ij")
    r = np.sqrt(sum(x**2 for x in axes))
    largest = np.max(np.abs(np.stack(axes)), axis=0)
    keep = (largest <= math.cos(math.radians(axis_gap)) * r) | (r == 0)
    return r, keep


@dataclass(frozen=True)
class RadialProfile:
    """ln F averaged over shells of |c| (:func:`radial_profile`).

    Attributes
    ----------
    speed : numpy.ndarray
        The mean |c| of the nodes of each kept shell.
    log_density : numpy.ndarray
        The mean ln F of each shell.
    spread : numpy.ndarray
        The rms of ln F about a straight line in |c| within each shell (the grid's anisotropy;
        about its mean where the shell's nodes lie at one radius to 1e-9 of the width; 0 for
        shells of fewer than three nodes).
    counts : numpy.ndarray
        Nodes per shell.
    width : float
        The shells' width.
    threshold : float
        The floor F had to exceed at every node of a kept shell.
    resolved : float
        The outer edge of the last shell before the first one dropped (by the floor or the
        cutoff R): the profile is complete on [0, resolved).
    node_speed, node_log_density : numpy.ndarray
        |c| and ln F at every node of the kept shells.
    node_shell : numpy.ndarray
        The index (into ``speed``) of each node's shell.
    """

    speed: np.ndarray
    log_density: np.ndarray
    spread: np.ndarray
    counts: np.ndarray
    width: float
    threshold: float
    resolved: float
    node_speed: np.ndarray = field(repr=False, default=None)
    node_log_density: np.ndarray = field(repr=False, default=None)
    node_shell: np.ndarray = field(repr=False, default=None)

    def local_slope(self) -> tuple[np.ndarray, np.ndarray]:
        """−d ln F/d|c| between neighbouring shells (at their mean |c|).

        Returns
        -------
        speed, slope : numpy.ndarray
        """
        dc = np.diff(self.speed)
        return 0.5 * (self.speed[1:] + self.speed[:-1]), -np.diff(self.log_density) / dc


def radial_profile(F, grid, *, width: float | None = None, floor: float = 1e-12,
                   noise_factor: float = 100.0, axis_gap: float = 0.0) -> RadialProfile:
    """The shell average of ln F on a spectral grid.

    The shells are [k w, (k + 1) w) in |c|; a shell is kept when it lies inside the kernel's
    cutoff ((k + 1) w ≤ R) and F exceeds the floor at every one of its nodes; the floor is the
    larger of ``floor`` × max F and ``noise_factor`` × the largest negative excursion of F at
    |c| < R (the round-off and Gibbs level of the FFTs; beyond R, in the absorbing layer at
    the box's faces, F is not the solution's).  With ``axis_gap`` > 0 the nodes within that
    angle of a coordinate axis are left out, the noise included: the ringing of the Fourier
    cutoff (a cube in k) gathers along the axes (measured, d = 2, α = 0.5, h = 0.4375: ±1.5e-8
    of the peak along the axes from |c| ≈ 7 on; 20° off them the profile is resolved to
    |c| = 8.3 on the grid (96, 21, 12), to 5.7 with every node).

    Parameters
    ----------
    F : array_like
        F at the nodes, shape (N,)*d, d = 2 or 3.
    grid : str or SphereGrid
        Its grid (:func:`maxwell_kinetics.sphere_grid.sphere_grid`).
    width : float, optional
        The shells' width (default the grid spacing h).
    floor : float, default 1e-12
        The floor relative to max F, > 0.
    noise_factor : float, default 100
        The floor's multiple of max(0, −min F) over |c| < R, ≥ 0.
    axis_gap : float, default 0
        Leave out the nodes within this angle (degrees, in [0, 45)) of a coordinate axis.

    Returns
    -------
    RadialProfile

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``F`` (not of shape (N,)*d on the grid, d = 2 or 3, not positive anywhere, or
        below the floor in the first shell),
        ``grid``, ``width``, ``floor``, ``noise_factor`` or ``axis_gap``.
    """
    F = np.asarray(F, dtype=float)
    d = F.ndim
    if d not in (2, 3):
        raise InvalidArgumentError("F", f"an array of shape {F.shape}", "F on a grid in d = 2, 3")
    g = sphere_grid(grid, d)
    if F.shape != (g.points,) * d or not np.all(np.isfinite(F)) or not np.max(F) > 0:
        raise InvalidArgumentError("F", f"an array of shape {F.shape}",
                                   f"finite values on the grid, shape {(g.points,) * d}, "
                                   f"positive somewhere")
    w = g.spacing if width is None else check_positive(width, "width")
    floor = check_positive(floor, "floor")
    if not (math.isfinite(noise_factor) and noise_factor >= 0):
        raise InvalidArgumentError("noise_factor", noise_factor, "a finite number >= 0")
    if not (math.isfinite(axis_gap) and 0 <= axis_gap < 45):
        raise InvalidArgumentError("axis_gap", axis_gap, "an angle in degrees in [0, 45)")
    r, keep = (a.ravel() for a in node_speeds(g, d, axis_gap))
    values = F.ravel()
    if axis_gap > 0:
        r, values = r[keep], values[keep]
    noise = max(0.0, -float(np.min(values[r < g.cutoff])))
    threshold = max(floor * float(np.max(F)), noise_factor * noise)
    shell = np.floor(r / w).astype(int)
    rows, nodes, resolved = [], [], 0.0
    for k in range(int(g.cutoff // w)):
        pick = shell == k
        if not np.any(pick):
            continue
        if np.any(values[pick] <= threshold):
            break
        x, y = r[pick], np.log(values[pick])
        spread = 0.0
        if x.size >= 3 and np.ptp(x) > 1e-9 * w:
            residual = y - np.polyval(np.polyfit(x, y, 1), x)
            spread = float(np.sqrt(np.mean(residual**2)))
        elif x.size >= 3:  # one radius, to round-off (a spacing that is no binary fraction)
            spread = float(np.std(y))
        nodes.append((x, y, np.full(x.size, len(rows))))
        rows.append((x.mean(), y.mean(), spread, x.size))
        resolved = (k + 1) * w
    if not rows:
        raise InvalidArgumentError("F", "a law below its floor at the origin",
                                   "F above the floor near c = 0")
    speed, log_density, spread, counts = (np.array(col) for col in zip(*rows, strict=True))
    x, y, index = (np.concatenate(col) for col in zip(*nodes, strict=True))
    return RadialProfile(speed, log_density, spread, counts.astype(int), float(w), threshold,
                         float(resolved), x, y, index)


@dataclass(frozen=True)
class TailFit:
    """The fit ln F = a + μ ln c − A c of a cooling state's tail (:func:`fit_tail`).

    Attributes
    ----------
    window : tuple of float
        (c_lo, c_hi): the shells whose mean |c| lies in it were fitted.
    rate, rate_error : float
        A and its standard error from the fit.
    power, power_error : float
        μ and its standard error.
    amplitude : float
        a.
    window_systematic : float
        The largest |change of A| when the window moves by ± ``shift``.
    moved_rates : tuple of float
        A on the windows moved by −shift and +shift.
    shift : float
        The window's move.
    shells : int
        Shells fitted.
    rms : float
        The rms residual of the fit (in ln F, each shell weighted once).
    predicted : float or None
        The prediction 2K/ζ* (:func:`tail_rate`; None when not given).
    """

    window: tuple
    rate: float
    rate_error: float
    power: float
    power_error: float
    amplitude: float
    window_systematic: float
    moved_rates: tuple
    shift: float
    shells: int
    rms: float
    predicted: float | None = None

    def to_dict(self) -> dict:
        """The fields as a JSON-able dict.

        Returns
        -------
        dict
        """
        return {"window": list(self.window), "rate": self.rate, "rate_error": self.rate_error,
                "power": self.power, "power_error": self.power_error,
                "amplitude": self.amplitude, "window_systematic": self.window_systematic,
                "moved_rates": list(self.moved_rates), "shift": self.shift,
                "shells": self.shells, "rms": self.rms, "predicted": self.predicted}


def _least_squares(profile: RadialProfile, lo: float, hi: float) -> tuple:
    """(a, μ, A), their standard errors, the shells and the rms residual on [lo, hi]: least
    squares over the nodes of the shells whose mean |c| lies in [lo, hi], each node weighted by
    1/(its shell's nodes), so that every shell counts once (n shells, n − 3 degrees of
    freedom); exact for an F of the fitted form."""
    shells = np.flatnonzero((profile.speed >= lo) & (profile.speed <= hi))
    n = int(shells.size)
    if n < MIN_SHELLS:
        raise InvalidArgumentError("window", (lo, hi), f"a window holding at least "
                                   f"{MIN_SHELLS} resolved shells (this one: {n})")
    pick = np.isin(profile.node_shell, shells)
    c, y = profile.node_speed[pick], profile.node_log_density[pick]
    weight = 1.0 / profile.counts[profile.node_shell[pick]]
    X = np.column_stack([np.ones_like(c), np.log(c), -c])
    root = np.sqrt(weight)
    coef, *_ = np.linalg.lstsq(X * root[:, None], y * root, rcond=None)
    residual = y - X @ coef
    s2 = float(np.sum(weight * residual**2)) / (n - 3)
    cov = s2 * np.linalg.inv(X.T @ (X * weight[:, None]))
    return coef, np.sqrt(np.diag(cov)), n, float(np.sqrt(np.sum(weight * residual**2) / n))


def fit_tail(profile: RadialProfile, window, *, shift: float | None = None,
             predicted: float | None = None) -> TailFit:
    """Fit ln F = a + μ ln c − A c to the shells of ``profile`` in ``window``, and move the
    window by ± ``shift`` for the window systematic.

    Parameters
    ----------
    profile : RadialProfile
        The shells (:func:`radial_profile`).
    window : tuple of float
        (c_lo, c_hi), 0 < c_lo < c_hi; the moved windows (c_lo − shift, c_hi + shift) must lie
        in (0, ``profile.resolved``].
    shift : float, optional
        The window's move (default a quarter of its width).
    predicted : float, optional
        The predicted A, recorded with the fit.

    Returns
    -------
    TailFit

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``window`` (not two increasing positive numbers, a moved window beyond the
        resolved profile, or fewer than :data:`MIN_SHELLS` shells in one of the three) or
        ``shift`` (not > 0).
    """
    try:
        lo, hi = (float(x) for x in window)
    except (TypeError, ValueError):
        raise InvalidArgumentError("window", window, "two numbers (c_lo, c_hi)") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise InvalidArgumentError("window", window, "0 < c_lo < c_hi")
    shift = 0.25 * (hi - lo) if shift is None else check_positive(shift, "shift")
    if lo - shift <= 0 or hi + shift > profile.resolved:
        raise InvalidArgumentError(
            "window", window, f"a window that moved by ±{shift:g} stays in (0, "
            f"{profile.resolved:g}], where the profile is resolved")
    coef, err, n, rms = _least_squares(profile, lo, hi)
    moved = tuple(float(_least_squares(profile, lo + s, hi + s)[0][2]) for s in (-shift, shift))
    systematic = max(abs(m - coef[2]) for m in moved)
    return TailFit((lo, hi), float(coef[2]), float(err[2]), float(coef[1]), float(err[1]),
                   float(coef[0]), float(systematic), moved, float(shift), n, rms,
                   None if predicted is None else float(predicted))


def measure_tail(state, window, *, kernel=None, shift: float | None = None,
                 width: float | None = None, floor: float = 1e-12,
                 margin: float = 0.0) -> TailFit:
    """The tail of a cooling state (:func:`maxwell_kinetics.sphere_spectral.cooling_state`):
    :func:`radial_profile` and :func:`fit_tail`, with the prediction of :func:`tail_rate`
    when ``kernel`` is given and homogeneous of degree 1.

    Parameters
    ----------
    state : maxwell_kinetics.sphere_spectral.CoolingState
        The cooling state (``F``, ``grid``, ``dimension``, ``cooling_rate``).
    window : tuple of float
        (c_lo, c_hi) (:func:`fit_tail`); c_hi + shift must not exceed the cutoff R − ``margin``.
    kernel : particles.kernels.Kernel, optional
        The state's kernel, for the prediction (None, or γ ≠ 1: no prediction).
    shift : float, optional
        The window's move (:func:`fit_tail`).
    width : float, optional
        The shells' width (:func:`radial_profile`).
    floor : float, default 1e-12
        The floor relative to max F (:func:`radial_profile`).
    margin : float, default 0
        How far inside the cutoff the moved window must end (the partners' spread: the loss is
        exact only for c ≲ R − 4).

    Returns
    -------
    TailFit

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``window`` when a moved window reaches past R − ``margin``; as
        :func:`radial_profile` and :func:`fit_tail`.
    """
    grid: SphereGrid = state.grid
    profile = radial_profile(state.F, grid, width=width, floor=floor)
    lo, hi = (float(x) for x in window)
    move = 0.25 * (hi - lo) if shift is None else float(shift)
    if hi + move > grid.cutoff - margin:
        raise InvalidArgumentError(
            "window", window, f"a window ending (moved by {move:g}) at most at the cutoff "
            f"R = {grid.cutoff:g} less the margin {margin:g}")
    predicted = None
    if kernel is not None and float(getattr(kernel, "homogeneity", 0.0)) == 1.0:
        predicted = tail_rate(kernel, state.dimension, state.cooling_rate)
    return fit_tail(profile, (lo, hi), shift=shift, predicted=predicted)
