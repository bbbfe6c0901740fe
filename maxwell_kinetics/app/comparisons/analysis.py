"""Estimators on arrays shared by the comparisons (NumPy; no runs, no drawing): bin edges and
rescaled samples, velocity profiles and their coarse-grained increments, log-binned S(k) and its
Porod fit, the jackknife, and the late-stage estimators: the grid of the velocity tail and the
scaled cluster-mass law with its small-μ fits.
"""

from __future__ import annotations

import math

import numpy as np

from particles.observables import log_bin
from particles.validation import InvalidArgumentError

__all__ = [
    "bin_edges",
    "rescaled",
    "block_means",
    "velocity_on_grid",
    "coarse_increment_skewness",
    "profile_scales",
    "log_binned",
    "porod_fit",
    "binned_porod_fit",
    "porod_slope",
    "jackknife",
    "tail_grid",
    "mass_density",
    "small_mass_law",
    "paired_numbers",
    "MASS_MODELS",
    "PROFILE_EXPONENTS",
]


def bin_edges(spec) -> np.ndarray:
    """Edges ``lo, lo + step, …, hi`` of a preset's ``(lo, hi, step)`` (rounded to 12 digits).

    Parameters
    ----------
    spec : tuple of float
        ``(lo, hi, step)``.

    Returns
    -------
    numpy.ndarray
        The edges, ``hi`` included when it lies on the step grid.
    """
    lo, hi, step = spec
    return np.round(np.arange(lo, hi + 0.5 * step, step), 12)


def rescaled(v: np.ndarray) -> np.ndarray:
    """x = (v − ⟨v⟩) / √⟨(v − ⟨v⟩)²⟩ per run (rows).

    Every run starts with zero total momentum, and collisions conserve it up to round-off; but
    that round-off (~1e-16 of the initial velocities) does not decay while the velocities decay
    like e^{−λτ}, so the mean is subtracted.  Even so the fluctuations keep only ~16 − λτ/ln 10
    digits: the Ulam runs here stay at λτ ≤ 30 (measured: at r = 0.9, τ = 1200, λτ = 57, the
    raw velocities of N = 2·10⁴ particles were all equal to their round-off mean).

    Parameters
    ----------
    v : numpy.ndarray
        Velocities, one run per row (last axis: the particles).

    Returns
    -------
    numpy.ndarray
        The rescaled velocities, shape of ``v``.
    """
    v = v - v.mean(axis=-1, keepdims=True)
    return v / np.sqrt(np.mean(v * v, axis=-1, keepdims=True))


# ----------------------------------------------------------------------- profiles (Fig. 4)


def _increment_skewness(dv: np.ndarray) -> float:
    d = dv - dv.mean()
    return float(np.mean(d**3) / np.mean(d**2) ** 1.5)


def coarse_increment_skewness(profile, scale: int) -> float:
    """Skewness of the increments of a periodic profile coarse-grained over ``scale`` points.

    ``profile`` holds equally spaced samples of a field on a ring (v(i) against the label, or
    v(x) on a uniform grid).  It is cut into consecutive blocks of ``scale`` samples (a tail of
    ``len(profile) mod scale`` samples is dropped), each block is replaced by its mean, and the
    skewness γ₁ = ⟨(Δ − ⟨Δ⟩)³⟩ / ⟨(Δ − ⟨Δ⟩)²⟩^{3/2} of the increments between neighbouring
    blocks, the last to the first included, is returned.  ``scale = 1`` is the raw increment
    skewness.  Rare large negative increments (sharp drops after slow rises) give γ₁ < 0.

    Parameters
    ----------
    profile : array_like
        The 1-d periodic profile.
    scale : int
        Block length, ≥ 1, with at least 3 blocks in the profile.

    Returns
    -------
    float
        The skewness γ₁ of the block-mean increments.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``profile`` if it is not 1-d, or ``scale`` if it is not an integer ≥ 1 or
        leaves fewer than 3 blocks.
    """
    v = np.asarray(profile, dtype=float)
    if v.ndim != 1:
        raise InvalidArgumentError("profile", f"shape {v.shape}", "a 1-d array")
    if isinstance(scale, bool) or not isinstance(scale, (int, np.integer)) or scale < 1:
        raise InvalidArgumentError("scale", scale, "an integer >= 1")
    if v.size // scale < 3:
        raise InvalidArgumentError("scale", scale,
                                   f"at most {v.size // 3} for a profile of {v.size} points")
    means = block_means(v, scale)
    return _increment_skewness(np.diff(np.append(means, means[0])))


def block_means(values, m: int) -> np.ndarray:
    """Means of consecutive blocks of ``m`` values (a tail of ``len(values) mod m`` dropped).

    Parameters
    ----------
    values : array_like
        The values (flattened order).
    m : int
        Block length, ≥ 1.

    Returns
    -------
    numpy.ndarray
        The ``len(values) // m`` block means.
    """
    values = np.asarray(values, dtype=float)
    blocks = values.size // m
    return values[: blocks * m].reshape(blocks, m).mean(axis=1)


def velocity_on_grid(positions, velocities, length: float) -> np.ndarray:
    """MD v(x): the rods' velocities interpolated linearly in x (periodic, rods sorted by
    position) at the N grid points x_m = m L / N, m = 0 … N − 1.

    Parameters
    ----------
    positions : numpy.ndarray
        Positions of the N rods in [0, ``length``).
    velocities : numpy.ndarray
        Their velocities, shape (N,).
    length : float
        The ring's length L.

    Returns
    -------
    numpy.ndarray
        v at the N grid points, shape (N,).
    """
    n = len(velocities)
    order = np.argsort(positions, kind="stable")
    grid = np.arange(n) * (length / n)
    return np.interp(grid, positions[order], velocities[order], period=length)


def profile_scales(n: int) -> tuple[int, ...]:
    """Coarse-graining scales of comparison 7: 1, 4, 16, … up to N/64 (at least 64 blocks).

    Parameters
    ----------
    n : int
        Number of points N of the profile.

    Returns
    -------
    tuple of int
        The scales, increasing.
    """
    scales = [1]
    while scales[-1] * 4 * 64 <= n:
        scales.append(scales[-1] * 4)
    return tuple(scales)


# ----------------------------------------------------------------------- S(k) (Fig. 3)


def log_binned(k, s):
    """Log-binned S(k), 10 bins per decade: (bin centres, mean S)
    (:func:`particles.observables.log_bin`).

    Parameters
    ----------
    k, s : numpy.ndarray
        Wavenumbers and S(k), same shape.

    Returns
    -------
    tuple of numpy.ndarray
        ``(kb, sb)``: bin centres and mean S per bin.
    """
    kb, sb, _ = log_bin(k, s, 10)
    return kb, sb


def porod_fit(k, s, t, z, x_window, k_max):
    """Least-squares line ln S = a + b ln k over the log bins with k·t^z in ``x_window`` and
    k ≤ ``k_max``: (b, a, k of the bins used), or None with fewer than 3 bins.

    Parameters
    ----------
    k, s : numpy.ndarray
        Wavenumbers and S(k), same shape (log-binned here by :func:`log_binned`).
    t : float
        The time (τ or t) of the spectrum.
    z : float
        Dynamic exponent of the rescaling x = k t^z.
    x_window : tuple of float
        (lowest, highest) x = k t^z of the bins fitted.
    k_max : float
        Largest k fitted.

    Returns
    -------
    tuple or None
        ``(b, a, kb)``: slope, intercept and the bin centres used; None with fewer than 3
        bins in the window.
    """
    return binned_porod_fit(*log_binned(k, s), t, z, x_window, k_max)


def binned_porod_fit(kb, sb, t, z, x_window, k_max):
    """:func:`porod_fit` on a spectrum already log-binned (``kb``, ``sb``).

    Parameters
    ----------
    kb, sb : numpy.ndarray
        Bin centres and mean S of a log-binned spectrum.
    t : float
        The time (τ or t) of the spectrum.
    z : float
        Dynamic exponent of the rescaling x = k t^z.
    x_window : tuple of float
        (lowest, highest) x = k t^z of the bins fitted.
    k_max : float
        Largest k fitted.

    Returns
    -------
    tuple or None
        As :func:`porod_fit`.
    """
    x = kb * t**z
    sel = (x >= x_window[0]) & (x <= x_window[1]) & (kb <= k_max)
    if sel.sum() < 3:
        return None
    b, a = np.polyfit(np.log(kb[sel]), np.log(sb[sel]), 1)
    return float(b), float(a), kb[sel]


def porod_slope(k, s, t, z, x_window, k_max):
    """Slope of ln S against ln k over k·t^z in ``x_window`` and k ≤ ``k_max`` (None with
    fewer than 3 log bins there).

    Parameters
    ----------
    k, s : numpy.ndarray
        Wavenumbers and S(k), same shape.
    t : float
        The time (τ or t) of the spectrum.
    z : float
        Dynamic exponent of the rescaling x = k t^z.
    x_window : tuple of float
        (lowest, highest) x = k t^z of the bins fitted.
    k_max : float
        Largest k fitted.

    Returns
    -------
    float or None
        The slope b of :func:`porod_fit` (expected −2 in a Porod range).
    """
    fit = porod_fit(k, s, t, z, x_window, k_max)
    return None if fit is None else fit[0]


def jackknife(values) -> float | None:
    """Jackknife standard error from the leave-one-out estimates ``values`` (None below 3 of
    them: two replicas give one difference, not a spread).

    Parameters
    ----------
    values : sequence of float or None
        The leave-one-out estimates; a None among them gives None.

    Returns
    -------
    float or None
        √((n − 1)/n · Σ (vᵢ − v̄)²).
    """
    v = np.asarray([x for x in values if x is not None], dtype=float)
    if v.size < 3 or v.size < len(values):
        return None
    return float(np.sqrt((v.size - 1) / v.size * np.sum((v - v.mean()) ** 2)))


# Late-stage estimators (the sticky gas and late MD): the tail grid and the cluster-mass law


def tail_grid(first: float, last: float, per_octave: int) -> np.ndarray:
    """The velocities w_k = first · 2^{k/per_octave} ≤ last at which the tail survival
    P(|w| > w_k) is counted (geometric, so that the chord exponents sit at even steps of ln w).

    Parameters
    ----------
    first, last : float
        The first velocity and the bound of the last.
    per_octave : int
        Points per doubling of w.

    Returns
    -------
    numpy.ndarray
        The increasing velocities w_k.
    """
    count = int(math.floor(per_octave * math.log2(last / first) + 1e-9)) + 1
    return first * 2.0 ** (np.arange(count) / per_octave)


def mass_density(masses_counts, times, length, mu_edges, m_min=1, *, errors=False):
    """Scaled cluster-mass density Φ(μ) = M² n(m, t) with μ = m/M, M = t^{2/3} (density 1),
    pooled over ``times``: ``masses_counts`` is a list (one per time) of ``(m, count)`` from
    :func:`particles.sticky_observables.cluster_mass_distribution`, n(m, t) = count(m)/L the number
    of clusters of mass m per unit length.  In each bin [a, b) of ``mu_edges``, with C_t the
    clusters and k_t the integers m ≥ ``m_min`` with a M ≤ m < b M at time t,
    Φ = Σ_t M² C_t / (L Σ_t k_t) (bins with no integer are NaN).  Σ_m m n(m) = n = 1 makes
    ∫ μ Φ dμ time-independent in the scaling state; the sticky gas has Φ → F(μ)
    (:func:`particles.sticky_exact.exact_mass_density`), ~ μ^{−1/2}/√(2π) at small μ.

    With ``errors=True`` it returns ``(Φ, σ, clusters)``: σ is the standard error of Φ with the
    cluster counts taken as independent Poisson numbers (var Σ_t M² C_t / L = Σ_t M⁴ C_t / L²),
    and ``clusters`` the number of clusters counted per bin.  Several runs (seeds) are pooled
    by passing one table per run and time.

    Parameters
    ----------
    masses_counts : list of tuple of numpy.ndarray
        One ``(m, count)`` table per (run and) time.
    times : sequence of float
        The time t of each table.
    length : float
        The ring's length L (= N at density 1).
    mu_edges : array_like
        Increasing bin edges in μ.
    m_min : int, optional
        Smallest mass counted (default 1).
    errors : bool, optional
        Also return the Poisson standard errors and the counts (default false).

    Returns
    -------
    numpy.ndarray or tuple of numpy.ndarray
        Φ per bin, or ``(Φ, σ, clusters)`` with ``errors=True``.
    """
    mu_edges = np.asarray(mu_edges, dtype=float)
    num = np.zeros(mu_edges.size - 1)
    var = np.zeros(mu_edges.size - 1)
    counted = np.zeros(mu_edges.size - 1)
    den = np.zeros(mu_edges.size - 1)
    for (m, c), t in zip(masses_counts, times, strict=True):
        big_m = float(t) ** (2.0 / 3.0)
        lo = np.maximum(np.ceil(mu_edges[:-1] * big_m), m_min)
        hi = np.ceil(mu_edges[1:] * big_m)  # integers in [a M, b M)
        k = np.maximum(hi - lo, 0.0)
        idx = np.searchsorted(mu_edges * big_m, m, side="right") - 1
        ok = (idx >= 0) & (idx < num.size) & (m >= m_min)
        clusters = np.bincount(idx[ok], weights=c[ok], minlength=num.size)
        num += big_m**2 * clusters / length
        var += big_m**4 * clusters / length**2
        counted += clusters
        den += k
    with np.errstate(invalid="ignore", divide="ignore"):
        phi = np.where(den > 0, num / den, np.nan)
        if not errors:
            return phi
        return phi, np.where(den > 0, np.sqrt(var) / den, np.nan), counted


#: The models fitted to the small-μ cluster-mass density (:func:`small_mass_law`): a pure power
#: law, and the power law with its first corrections (a constant and μ^{1/2}).
MASS_MODELS = {
    "power": (lambda mu, a_, amp: amp * mu**a_, (-0.5, 0.4)),
    "corrected": (lambda mu, a_, amp, b, c: amp * mu**a_ + b + c * np.sqrt(mu),
                  (-0.5, 0.4, 0.1, 0.1)),
}


def small_mass_law(mu, phi, err, counted, mu_max, mu_min=0.0, min_count=50,
                   models=tuple(MASS_MODELS)) -> dict:
    """Weighted least-squares fits of the scaled cluster-mass density Φ(μ) on the bins with
    ``mu_min`` ≤ μ ≤ ``mu_max`` and at least ``min_count`` clusters (so that the Poisson error
    is close to Gaussian), weights 1/σ² (:func:`mass_density` with ``errors=True``).  For each
    model of :data:`MASS_MODELS` it returns the exponent ``a`` ± its standard error (from the
    covariance with σ taken as absolute), χ²/dof and the parameters.  χ²/dof ≈ 1 says that a
    model and the Poisson errors describe the data.  Measured with this function (N = 10⁷, 16 seeds
    1000…1015, t = 10⁴, 3·10⁴, 10⁵ pooled, m ≥ 10, μ ∈ [0.0045, 0.28], 19 bins): "power"
    a = −0.453 ± 0.004 with χ²/dof = 2.58 (rejected), "corrected" a = −0.465 ± 0.050 with
    χ²/dof = 1.03.  A fit that does not converge is None.  ``profile``: χ² of the corrected
    model with a held at −1/3, −1/2, −2/3 (B, C free), to show which exponents the data
    exclude; on those data 22.5, 15.9, 33.3 for 16 degrees of freedom.

    Parameters
    ----------
    mu, phi, err, counted : numpy.ndarray
        Bin centres μ, Φ, its standard error and the clusters counted per bin (from
        :func:`mass_density` with ``errors=True``).
    mu_max : float
        Largest μ fitted.
    mu_min : float, optional
        Smallest μ fitted (default 0).
    min_count : int, optional
        Fewest clusters of a bin fitted (default 50).
    models : sequence of str, optional
        Names among :data:`MASS_MODELS` to fit (default all).

    Returns
    -------
    dict
        ``mu_range`` and ``bins`` used, one entry per model (``a``, ``chi2_dof``,
        ``parameters``, or None) and, with ``"corrected"``, ``profile``.
    """
    from scipy.optimize import curve_fit

    ok = np.isfinite(phi) & (counted >= min_count) & (mu >= mu_min) & (mu <= mu_max) & (err > 0)
    out = {"mu_range": [float(mu[ok].min()), float(mu[ok].max())] if ok.any() else None,
           "bins": int(ok.sum())}
    for name in models:
        f, p0 = MASS_MODELS[name]
        out[name] = None
        if ok.sum() <= len(p0) + 1:
            continue
        x, y, e = mu[ok], phi[ok], err[ok]
        try:
            p, cov = curve_fit(f, x, y, p0=p0, sigma=e, absolute_sigma=True, maxfev=20000)
        except RuntimeError:  # no convergence
            continue
        chi2 = float(np.sum(((f(x, *p) - y) / e) ** 2)) / (x.size - len(p))
        out[name] = {"a": [float(p[0]), float(np.sqrt(cov[0, 0]))], "chi2_dof": chi2,
                     "parameters": [float(v) for v in p]}
    if "corrected" in models and ok.sum() > 4:
        out["profile"] = {"dof": int(ok.sum()) - 3,
                          "chi2": {label: _corrected_chi2(mu[ok], phi[ok], err[ok], a_)
                                   for label, a_ in PROFILE_EXPONENTS.items()}}
    return out


#: Exponents at which the corrected model is refitted with a held fixed (:func:`small_mass_law`).
PROFILE_EXPONENTS = {"-1/3": -1.0 / 3.0, "-1/2": -0.5, "-2/3": -2.0 / 3.0}


def _corrected_chi2(mu, phi, err, a_) -> float:
    """χ² of A μ^a + B + C μ^{1/2} with ``a_`` held fixed (linear least squares in A, B, C)."""
    design = np.stack([mu**a_, np.ones_like(mu), np.sqrt(mu)], axis=1) / err[:, None]
    coef = np.linalg.lstsq(design, phi / err, rcond=None)[0]
    return float(np.sum((design @ coef - phi / err) ** 2))


def paired_numbers(e_md, e_sticky):
    """Relative differences of MD and sticky-gas energies from the same and from independent
    initial states.

    Parameters
    ----------
    e_md, e_sticky : array_like
        Energies, shape (R, T): R seeds, T times; row i of both from seed i.

    Returns
    -------
    paired : numpy.ndarray
        (R, T): E_MD,i / E_sticky,i − 1.
    unpaired : numpy.ndarray
        (R(R − 1), T): E_MD,i / E_sticky,j − 1 for every i ≠ j, in the order (i, j) row by row.
    """
    e_md, e_sticky = np.asarray(e_md, float), np.asarray(e_sticky, float)
    r = e_md.shape[0]
    paired = e_md / e_sticky - 1.0
    unpaired = np.array([e_md[i] / e_sticky[j] - 1.0 for i in range(r) for j in range(r)
                         if i != j]).reshape(-1, e_md.shape[1])
    return paired, unpaired
