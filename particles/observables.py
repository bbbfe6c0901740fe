"""Observables of a velocity field v(i) on N particles or sites (NumPy + pyfftw).

Every function takes a velocity array ``v`` whose last axis runs over the particles (for the
lattice and MD, over the site / particle label i = 0..N-1 on a ring).  Functions that accept a
two-dimensional array ``(runs, N)`` average over the runs, as stated in each docstring.

Conventions
-----------
* Energy is ⟨v²⟩ = (1/N) Σ_i v_i², per particle, *not* ½⟨v²⟩; it is 1 at τ = 0 for every run.
* Discrete Fourier transform (ring of N sites, lattice spacing 1):
  v̂(k) = Σ_{j=0}^{N-1} v_j e^{-i k j}, with k = 2π m / N.  Only m = 0 .. ⌊N/2⌋ is returned
  (``rfft`` ordering, increasing k) because v is real and S(−k) = S(k).
* The profile v(i) (:func:`velocity_profile`) is the velocity against the label i, in label
  order; what the label means depends on the model (ring site, rod order, or nothing: Ulam).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .validation import (
    InvalidArgumentError,
    check_count,
    check_edges,
    check_positive,
    check_real_array,
)

__all__ = [
    "Histogram",
    "NumericalErrorWarning",
    "energy",
    "momentum",
    "kurtosis",
    "rescaled_histogram",
    "histogram_from_counts",
    "structure_factor",
    "wavenumbers",
    "correlation",
    "velocity_profile",
    "log_bin",
    "DEFAULT_EDGES",
    "weighted_kurtosis",
    "mean_sem",
    "mean_sem_json",
]

#: Default bin edges for the rescaled velocity x = v / √E: 121 edges, width 0.1, on [-6, 6].
DEFAULT_EDGES = np.linspace(-6.0, 6.0, 121)



def _fftw():
    """pyfftw's NumPy-style interface, imported on first use: with dask installed,
    ``pyfftw.interfaces`` also imports ``dask.array.fft`` (about a second), which
    ``import particles`` should not pay."""
    import pyfftw.interfaces.numpy_fft as fft

    return fft

def _as_velocities(v, *, min_dims=1, max_dims=2) -> np.ndarray:
    """``v`` as a float array of finite real velocities, 1- or 2-dimensional and non-empty: the
    caller's array itself when it is float64 (the observables only read it; a copy would be
    one more array of N values at the peak of a run's last record)."""
    arr = check_real_array(v, "v", copy=False)
    if not min_dims <= arr.ndim <= max_dims or arr.shape[-1] < 1:
        raise InvalidArgumentError(
            "v",
            f"array of shape {arr.shape}",
            f"a {min_dims}..{max_dims}-dimensional velocity array",
        )
    return arr


def energy(v) -> np.ndarray | float:
    """Energy per particle ⟨v²⟩ = (1/N) Σ_i v_i² along the last axis (no factor ½).

    Parameters
    ----------
    v : array_like
        Velocities, particles along the last axis.

    Returns
    -------
    float or numpy.ndarray
        ⟨v²⟩, a float for one set of velocities.
    """
    arr = _as_velocities(v)
    with np.errstate(over="ignore"):  # |v| beyond ~1e154: ⟨v²⟩ is inf, as it should be
        out = np.mean(arr * arr, axis=-1)
    return float(out) if out.ndim == 0 else out


def kurtosis(v) -> float:
    """Kurtosis ⟨v⁴⟩/⟨v²⟩² of one run's velocities (raw moments, as the energy ⟨v²⟩: the
    engines keep the mean velocity at 0; 3 for a Gaussian).

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)``.

    Returns
    -------
    float
        The kurtosis; NaN when every velocity is 0 (undefined) or one is not finite.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``v`` when it is not an array of real numbers (a scalar, complex values,
        booleans, strings).
    """
    arr = check_real_array(v, "v", finite=False, copy=False)  # float64: no copy
    if arr.ndim == 0:
        raise InvalidArgumentError("v", v, "an array of velocities, not one number")
    if not arr.size:
        return math.nan
    # the largest |v| without an |v| temporary: max(max v, −min v) (negation is exact)
    scale = max(float(np.max(arr)), -float(np.min(arr)))
    if not (0.0 < scale < math.inf):  # every velocity 0, or beyond float64 (NaN included)
        return math.nan
    x = arr / scale  # |x| <= 1: no overflow of v⁴ whatever the velocities
    np.multiply(x, x, out=x)  # x², in place: one temporary of N values in all
    with np.errstate(under="ignore"):
        e2 = float(np.mean(x))
        np.multiply(x, x, out=x)  # x⁴
        return float(np.mean(x)) / (e2 * e2)


def weighted_kurtosis(values, counts) -> float:
    """Kurtosis ⟨v⁴⟩/⟨v²⟩² of velocities given as distinct ``values``, value ``values[c]``
    held by ``counts[c]`` particles: the :func:`kurtosis` of the expanded array, to round-off,
    at a cost of one pass over the values (the sticky gas's clusters, for one).

    Parameters
    ----------
    values : numpy.ndarray
        Velocities, shape ``(C,)``.
    counts : numpy.ndarray
        How many particles hold each value, shape ``(C,)``, ≥ 0, not all 0.

    Returns
    -------
    float
        The kurtosis; NaN when every velocity is 0 or one is not finite.

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``values`` or ``counts`` when it is not a one-dimensional array of real numbers,
        or when the two differ in length; ``counts`` when one is negative or all are 0.
    """
    values = check_real_array(values, "values", ndim=1, finite=False, copy=False)
    counts = check_real_array(counts, "counts", ndim=1, copy=False)
    if counts.shape != values.shape:
        raise InvalidArgumentError("counts", f"array of shape {counts.shape}",
                                   f"one count per value (shape {values.shape})")
    if values.size and not (np.all(counts >= 0.0) and np.any(counts > 0.0)):
        raise InvalidArgumentError("counts", counts.tolist()[:50], "counts >= 0, not all 0")
    if not values.size:
        return math.nan
    scale = max(float(np.max(values)), -float(np.min(values)))
    if not (0.0 < scale < math.inf):
        return math.nan
    x = values / scale
    np.multiply(x, x, out=x)
    n = float(np.sum(counts))
    with np.errstate(under="ignore"):
        e2 = float(np.dot(counts, x)) / n
        np.multiply(x, x, out=x)
        return float(np.dot(counts, x)) / n / (e2 * e2)


def momentum(v) -> np.ndarray | float:
    """Mean velocity (1/N) Σ_i v_i (momentum per particle, unit masses) along the last axis.

    Parameters
    ----------
    v : array_like
        Velocities, particles along the last axis (one run ``(N,)`` or runs ``(R, N)``).

    Returns
    -------
    float or numpy.ndarray
        ⟨v⟩, a float for one set of velocities, one value per run otherwise.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``v``) if ``v`` is not a 1- or 2-dimensional non-empty array.
    """
    arr = _as_velocities(v)
    out = np.mean(arr, axis=-1)
    return float(out) if out.ndim == 0 else out


class NumericalErrorWarning(UserWarning):
    """A prediction's numerical error exceeds the sampling error of the histogram it is compared
    with (:meth:`Histogram.distance`): the comparison stays valid, but it tests the numerics
    more than the sample; a finer solve removes it."""


@dataclass(frozen=True)
class Histogram:
    """A density estimate of x = v / v0 on fixed bins, with its statistical error.

    ``density[b] = count[b] / (n · width[b])`` integrates to the fraction of samples inside the
    edges.  ``error[b] = sqrt(n p (1 − p)) / (n · width[b])`` with ``p = count[b] / n`` is the
    binomial (≈ Poisson for small p) standard error of one bin for n independent samples.  For a
    correlated field (lattice, MD late times) the velocities are not independent and the true
    error is larger; averaging over independent runs is then the honest estimate.  A prediction
    (``samples`` 0) has no sampling error: its ``error`` is its numerical error (0 for an exact
    law; the solver's estimate for a kinetic solution,
    :meth:`maxwell_kinetics.solution.Solution.histogram`).

    Attributes
    ----------
    edges : numpy.ndarray
        Bin edges in x, shape ``(B + 1,)``, increasing.
    centres : numpy.ndarray
        Bin centres, shape ``(B,)``.
    density : numpy.ndarray
        Estimated probability density of x in each bin, shape ``(B,)``.
    error : numpy.ndarray
        Binomial standard error of ``density``, shape ``(B,)``.
    count : numpy.ndarray
        Number of samples in each bin, shape ``(B,)``.
    samples : int
        Total number of samples n, those outside the edges included.
    v0 : float
        The velocity scale x is measured in (mean of the per-run √E when pooled).
    """

    edges: np.ndarray
    centres: np.ndarray
    density: np.ndarray
    error: np.ndarray
    count: np.ndarray
    samples: int
    v0: float

    def __repr__(self) -> str:
        """One line: the bins, the samples and v0 (the arrays are attributes)."""
        edges = np.asarray(self.edges)
        return (f"Histogram({edges.size - 1} bins on [{edges[0]:g}, {edges[-1]:g}], "
                f"samples={self.samples}, v0={self.v0:.6g})")

    def to_dict(self) -> dict:
        """The histogram as JSON-ready lists.

        Returns
        -------
        dict
            ``{"centres", "density", "error"}``, each a list of floats.
        """
        return {
            "centres": self.centres.tolist(),
            "density": self.density.tolist(),
            "error": self.error.tolist(),
        }

    def distance(self, other, *, min_count: int = 5):
        """χ², degrees of freedom and χ²/dof (with the errors of both histograms) and the
        Kolmogorov–Smirnov distance to ``other``, a histogram on the same edges (a particle run's,
        or a prediction such as :meth:`maxwell_kinetics.solution.Solution.histogram`); conventions
        in :mod:`particles.distance`.  The errors of the two sides add in quadrature, so a
        prediction's numerical error (its ``error``; ``samples`` 0) widens each bin's tolerance
        together with the sample's statistical error.  Where, in a bin used in χ², the
        prediction's numerical error exceeds the sample's statistical error, a
        :class:`NumericalErrorWarning` says so (the χ² is still right, but it tests the numerics
        rather than the sample: solve on a finer grid).  A warning rather than a refusal: the
        result stays valid and scripts that compare many runs keep going.

        Parameters
        ----------
        other : Histogram
            The histogram compared with this one, on the same edges.
        min_count : int, optional
            Bins where a sampled side counts fewer samples are left out of χ² (default 5).

        Returns
        -------
        particles.distance.HistogramDistance
            ``chi2``, ``dof``, ``chi2_dof``, ``chi2_dof_expected`` = (1, √(2/dof)), ``ks``.

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``other`` if it is not a histogram on the same edges.

        Warns
        -----
        NumericalErrorWarning
            When one side is a prediction whose numerical error exceeds the other side's
            sampling error in a bin used in χ².
        """
        from .distance import histogram_distance

        result = histogram_distance(self, other, min_count=min_count)
        _warn_numerical_error(self, other, result.bins)
        return result


def _warn_numerical_error(first, second, bins: np.ndarray) -> None:
    """Warn (:class:`NumericalErrorWarning`) when one of the two histograms is a prediction
    (``samples`` 0) whose error exceeds the other's sampling error in a bin of ``bins``."""
    prediction, sample = sorted((first, second), key=lambda h: int(h.samples) > 0)
    if int(prediction.samples) > 0 or int(sample.samples) == 0 or not np.any(bins):
        return
    numeric = np.asarray(prediction.error, dtype=float)[bins]
    sampling = np.asarray(sample.error, dtype=float)[bins]
    over = numeric > sampling
    if np.any(over):
        worst = float(np.max(numeric[over] / np.maximum(sampling[over], np.finfo(float).tiny)))
        warnings.warn(NumericalErrorWarning(
            f"the prediction's numerical error exceeds the sampling error in {int(over.sum())} "
            f"of {int(bins.sum())} bins (up to {worst:.3g} times): chi2 includes it in "
            "quadrature, so this comparison tests the numerics more than the sample of "
            f"{int(sample.samples)}; raise the resolution of the solve (e.g. "
            "resolution='fine') to compare at the sample's precision"), stacklevel=3)


def _rms(rows: np.ndarray) -> np.ndarray:
    """√⟨v²⟩ of each row.  A row whose ⟨v²⟩ underflows below the smallest normal float (every
    |v| below ~1e-154, e.g. a long run at r = 0) or overflows is first divided by its largest |v|,
    so v0 stays exact to round-off whenever some velocity is non-zero; an all-zero row gives 0."""
    with np.errstate(over="ignore"):
        e = np.mean(rows * rows, axis=1)
    rms = np.sqrt(e)
    for i in np.flatnonzero(~((e >= np.finfo(float).tiny) & np.isfinite(e))):
        scale = np.max(np.abs(rows[i]))
        if 0.0 < scale < np.inf:
            rms[i] = scale * np.sqrt(np.mean((rows[i] / scale) ** 2))
    return rms


def rescaled_histogram(v, bins=None, v0=None) -> Histogram:
    """Histogram of the rescaled velocity x = v / v0, v0 = √E, E = ⟨v²⟩ of the same array.

    ``v`` may be one run ``(N,)`` or several runs ``(R, N)``; each run is rescaled by its own v0
    and all R·N values are pooled (the reported ``v0`` is the mean over runs).  ``bins`` is an
    array of increasing edges in x, or an integer number of equal bins on [-6, 6]; the default is
    :data:`DEFAULT_EDGES`.  The density is normalised by the total number of samples (including
    those outside the edges), so it estimates the probability density of x directly.

    x is undefined for a run whose velocities are all 0 (E = 0): that raises
    ``InvalidArgumentError`` (argument ``v``).  A run whose ⟨v²⟩ merely underflows in float64
    (velocities ~1e-160) still has a well-defined x: v0 is then computed without underflow.

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)`` or ``(R, N)``.
    bins : int or array_like, optional
        Number of equal bins on [-6, 6], or increasing edges in x; default :data:`DEFAULT_EDGES`.
    v0 : float, optional
        A fixed positive velocity scale used for every run instead of each run's own √E.

    Returns
    -------
    Histogram
        The density of x with its binomial error.

    Raises
    ------
    particles.InvalidArgumentError
        ``v`` of a wrong shape, not real, with a non-finite value, or with zero energy;
        ``bins`` not an integer in [1, 10⁶] nor at least two finite, strictly increasing edges;
        ``v0`` not a finite number > 0 (booleans and complex numbers refused).
    """
    arr = _as_velocities(v)
    if bins is None:
        edges = DEFAULT_EDGES
    elif np.isscalar(bins):
        if (isinstance(bins, bool) or not isinstance(bins, (int, float, np.integer, np.floating))
                or not np.isfinite(bins) or int(bins) != bins or not 1 <= int(bins) <= 10**6):
            raise InvalidArgumentError("bins", bins, "an integer in [1, 1e6] or an array of edges")
        edges = np.linspace(-6.0, 6.0, int(bins) + 1)
    else:
        edges = check_edges(bins, "bins")
    rows = arr.reshape(-1, arr.shape[-1])
    if v0 is None:
        v0 = _rms(rows)
    else:
        v0 = np.full(rows.shape[0], check_positive(v0, "v0"))
    if np.any(v0 <= 0) or not np.all(np.isfinite(v0)):
        raise InvalidArgumentError("v", f"energy {v0**2}", "a finite, non-zero energy per run")
    x = (rows / v0[:, None]).ravel()
    count, _ = np.histogram(x, bins=edges)
    return histogram_from_counts(edges, count, x.size, float(np.mean(v0)))


def histogram_from_counts(edges, count, n: int, v0: float) -> Histogram:
    """The :class:`Histogram` of ``count`` samples per bin of ``edges`` out of ``n`` in all
    (those outside the edges included), rescaled by ``v0``: density count/(n·width) and the
    binomial error (see :class:`Histogram`).

    Parameters
    ----------
    edges : array_like
        Bin edges in x, shape ``(B + 1,)``.
    count : array_like
        Samples per bin, shape ``(B,)``.
    n : int
        Total number of samples, those outside the edges included.
    v0 : float
        The velocity scale x = v / v0 was measured in.

    Returns
    -------
    Histogram
        The normalised density and its error.

    Raises
    ------
    particles.InvalidArgumentError
        If ``edges`` are not finite and strictly increasing, ``count`` is not one non-negative
        finite number per bin or one is more than ``n``, ``n`` is not a count >= 1, or
        ``v0`` is not a finite number > 0.
    """
    edges = check_edges(edges, "edges")
    count = check_real_array(count, "count", ndim=1)
    if count.size != edges.size - 1 or np.any(count < 0):
        raise InvalidArgumentError("count", count.tolist()[:50], f"{edges.size - 1} "
                                   "non-negative counts, one per bin")
    n = check_count(n, "n", 1)
    # per bin, not in all: expected counts n·p of a prediction may add up to a little more
    # than n (a kinetic prediction cut at q_max; a wrong law under test)
    if np.any(count > n):
        raise InvalidArgumentError("count", count.tolist()[:50], f"at most n = {n} samples in "
                                   "each bin")
    v0 = check_positive(v0, "v0")
    width = np.diff(edges)
    prob = count / n
    density = prob / width
    error = np.sqrt(n * prob * (1.0 - prob)) / (n * width)
    centres = 0.5 * (edges[1:] + edges[:-1])
    return Histogram(edges, centres, density, error, count, int(n), float(v0))


def _spectrum(arr: np.ndarray) -> tuple[np.ndarray, float]:
    """(P, c) with |v̂(k)|² = P · c² for k = 2πm/N, m = 0..⌊N/2⌋, for every row (pyfftw, one
    thread).  c = 1 unless some |v| ≥ 2²⁵⁶; below that |v̂|² ≤ (N max|v|)² < N² 2⁵¹² and the
    inverse transform's sums of N such terms cannot overflow for any N < 2¹⁶⁰.  Above it the
    velocities are divided by a power of two c first (exact: the transform of v/c is v̂/c to
    the last bit), and the caller multiplies its result by c twice, which overflows to ±inf only
    where the true value does."""
    # max |v| without a temporary of N values (|v| would be one more array at a run's peak)
    top = max(float(arr.max()), -float(arr.min())) if arr.size else 0.0
    scale = 2.0 ** (math.frexp(top)[1] - 1) if top >= 2.0**256 else 1.0
    vhat = _fftw().rfft(arr / scale if scale != 1.0 else arr, axis=-1, threads=1,
                        auto_align_input=False)  # no aligned copy of N values
    return vhat.real**2 + vhat.imag**2, scale


def _unscale(values: np.ndarray, scale: float) -> np.ndarray:
    if scale == 1.0:
        return values
    with np.errstate(over="ignore"):
        return values * scale * scale  # left to right: 0 stays 0, never inf * 0


def structure_factor(v) -> tuple[np.ndarray, np.ndarray]:
    """Structure factor S(k) = |v̂(k)|² / N of a ring of N sites, averaged over runs.

    Sign and normalisation: v̂(k) = Σ_j v_j e^{−ikj} (forward FFT, no 1/N), S(k) = |v̂(k)|²/N.
    Returns ``(k, S)`` with k = 2πm/N for m = 0, 1, …, ⌊N/2⌋, increasing.

    * k = 0: S(0) = (Σ_j v_j)²/N = N ⟨v⟩², zero up to round-off at zero total momentum; it is
      returned but is not part of any scaling range (:func:`log_bin` drops it).
    * Nyquist (even N only, m = N/2, k = π): v̂ = Σ_j (−1)^j v_j is real; it is returned once.
    * Parseval: averaging S over the full circle of N modes (each m ≠ 0, N/2 counted twice) gives
      ⟨v²⟩; uncorrelated velocities of energy E have S(k) = E for every k ≠ 0.

    ``v`` of shape ``(R, N)`` gives the average of S over the R runs (all of the same N).

    Parameters
    ----------
    v : array_like
        Velocities on the ring, shape ``(N,)`` or ``(R, N)``.

    Returns
    -------
    k : numpy.ndarray
        Wavenumbers 2πm/N, shape ``(⌊N/2⌋ + 1,)``.
    S : numpy.ndarray
        S(k), same shape (run-averaged for 2-D input).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``v``) if ``v`` is not a 1- or 2-dimensional non-empty array.
    """
    arr = _as_velocities(v)
    n = arr.shape[-1]
    power, scale = _spectrum(arr)
    power = power / n
    if power.ndim == 2:
        power = power.mean(axis=0)
    return wavenumbers(n), _unscale(power, scale)


def wavenumbers(n: int) -> np.ndarray:
    """The k of :func:`structure_factor` for a ring of ``n`` sites: 2πm/n, m = 0..⌊n/2⌋.

    Parameters
    ----------
    n : int
        Number of sites on the ring (lattice spacing 1).

    Returns
    -------
    numpy.ndarray
        The ⌊n/2⌋ + 1 wavenumbers, increasing from 0.

    Raises
    ------
    particles.InvalidArgumentError
        If ``n`` is not an integer >= 1 (booleans refused).
    """
    n = check_count(n, "n", 1)
    return 2.0 * np.pi * np.arange(n // 2 + 1) / n


def correlation(v) -> np.ndarray:
    """Velocity correlation C(r) = (1/N) Σ_i v_i v_{i+r} on the ring (indices mod N), averaged
    over runs.

    Returns C(r) for r = 0..N−1 (C(N − r) = C(r)); C(0) = ⟨v²⟩.  Computed through the FFT as
    C(r) = (1/N²) Σ_m |v̂(k_m)|² e^{+i k_m r} (Wiener–Khinchin), i.e. the inverse transform of S(k)
    divided by N; it is not normalised by C(0).

    Parameters
    ----------
    v : array_like
        Velocities on the ring, shape ``(N,)`` or ``(R, N)``.

    Returns
    -------
    numpy.ndarray
        C(r) for r = 0..N−1, shape ``(N,)`` (run-averaged for 2-D input).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``v``) if ``v`` is not a 1- or 2-dimensional non-empty array.
    """
    arr = _as_velocities(v)
    n = arr.shape[-1]
    power, scale = _spectrum(arr)
    c = _fftw().irfft(power, n=n, axis=-1, threads=1) / n
    if c.ndim == 2:
        c = c.mean(axis=0)
    return _unscale(c, scale)


def velocity_profile(v) -> tuple[np.ndarray, np.ndarray]:
    """The profile v(i): labels ``i = 0..N-1`` and the velocity of each, ``(i, v(i))``.

    No normalisation: v(i) is the velocity itself (not rescaled by √E), returned as a float
    copy.  ``v`` of shape ``(R, N)`` gives one profile per run (rows), not an average: profiles
    of independent runs do not average to anything meaningful.

    Label order:

    * lattice: i is the site, and label order is ring order (site i's neighbours are i ± 1 mod
      N, bond i joins i and i + 1), so v(i) is a spatial profile (shocks, smooth patches);
    * MD (hard rods on a ring): rods never pass each other, so label order is the rods' order
      along the ring: v(i) is the profile against the particle label (v(x) needs the positions);
    * Ulam: the model is mean-field, any particle collides with any other, so the label order
      carries no spatial meaning: v(i) is a list of velocities in arbitrary order, and
      neighbouring labels are uncorrelated (its C(r) and S(k) are flat, r, k ≠ 0).

    Parameters
    ----------
    v : array_like
        Velocities, shape ``(N,)`` or ``(R, N)``.

    Returns
    -------
    i : numpy.ndarray
        The labels 0..N−1.
    v : numpy.ndarray
        A float copy of the velocities, same shape as the input.

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``v``) if ``v`` is not a 1- or 2-dimensional non-empty array.
    """
    arr = np.array(_as_velocities(v), dtype=float)  # a copy
    return np.arange(arr.shape[-1]), arr


def log_bin(k, s, bins_per_decade: int = 10) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Average ``s(k)`` in logarithmically spaced bins of k > 0 (k = 0 is dropped).

    Bin edges are 10^(j / bins_per_decade).  Returns ``(k_mean, s_mean, count)`` for the non-empty
    bins: the arithmetic means of k and of s over the modes in each bin and the number of modes.

    Parameters
    ----------
    k : array_like
        Wavenumbers, 1-D.
    s : array_like
        Values at ``k`` (e.g. S(k)), same shape as ``k``.
    bins_per_decade : int, optional
        Number of logarithmic bins per factor 10 in k (default 10).

    Returns
    -------
    k_mean, s_mean : numpy.ndarray
        Mean k and mean s of each non-empty bin.
    count : numpy.ndarray
        Number of modes in each non-empty bin (int).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``k`` or ``s``) if they are not 1-D arrays of finite real numbers of one
        shape; (argument ``bins_per_decade``) if it is not an integer >= 1.
    """
    k = check_real_array(k, "k", ndim=1)
    s = check_real_array(s, "s", ndim=1)
    if k.shape != s.shape:
        raise InvalidArgumentError("s", f"shape {s.shape}", f"the shape of k, {k.shape}")
    bins_per_decade = check_count(bins_per_decade, "bins_per_decade", 1)
    keep = k > 0
    k, s = k[keep], s[keep]
    if k.size == 0:
        return np.empty(0), np.empty(0), np.empty(0, dtype=int)
    b = int(bins_per_decade)
    lo = np.floor(np.log10(k.min()) * b)
    hi = np.ceil(np.log10(k.max()) * b) + 1
    edges = 10.0 ** (np.arange(lo, hi + 1) / b)
    index = np.clip(np.searchsorted(edges, k, side="right") - 1, 0, edges.size - 2)
    count = np.bincount(index, minlength=edges.size - 1)
    ksum = np.bincount(index, weights=k, minlength=edges.size - 1)
    ssum = np.bincount(index, weights=s, minlength=edges.size - 1)
    full = count > 0
    return ksum[full] / count[full], ssum[full] / count[full], count[full]


def _is_bool(value) -> bool:
    return isinstance(value, (bool, np.bool_))


def mean_sem(values, axis: int = 0):
    """Mean and standard error of the mean over ``axis`` (e.g. over seeds): ``s / √m`` with
    ``s`` the sample standard deviation (ddof = 1) of the ``m`` values; NaN where m < 2.
    Returns ``(mean, sem)``, floats for a 1-D input, arrays otherwise.

    Parameters
    ----------
    values : array_like
        The values, e.g. one per seed along ``axis``.
    axis : int, optional
        Axis to average over (default 0).

    Returns
    -------
    mean, sem : float or numpy.ndarray
        The mean and its standard error (NaN where fewer than two values).

    Values beyond 2²⁵⁶ are summed in units of a power of two near the largest |value| along
    ``axis`` (exact), so values near the float limit (1e308) give their finite mean and error
    instead of an overflow to inf or NaN; below 2²⁵⁶ no sum of squares can overflow (m < 2⁶³
    values of |deviation| < 2²⁵⁷ sum to less than 2⁵⁷⁷).

    Raises
    ------
    particles.InvalidArgumentError
        (argument ``values``) if they are not real numbers or there is no value along
        ``axis``; (argument ``axis``) if it is not an axis of ``values``.
    """
    a = check_real_array(values, "values", finite=False)
    if a.ndim == 0:
        a = a.reshape(1)
    if _is_bool(axis) or not isinstance(axis, (int, np.integer)) or not -a.ndim <= axis < a.ndim:
        raise InvalidArgumentError("axis", axis, f"an axis of the {a.ndim}-dimensional values")
    m = a.shape[axis]
    if m == 0:
        raise InvalidArgumentError("values", a.shape, "at least one value along the axis")
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # large values are summed in units of a power of two (exact); below 2²⁵⁶ nothing is
        # rescaled, so ordinary values give NumPy's own mean and std
        top = np.max(np.abs(a), axis=axis, keepdims=True)
        big = np.isfinite(top) & (top >= 2.0**256)
        scale = np.where(big, np.exp2(np.frexp(np.where(big, top, 1.0))[1] - 1.0), 1.0)
        unit = a / scale
        mean = np.squeeze(scale * unit.mean(axis=axis, keepdims=True), axis=axis)
        if m < 2:
            sem = np.full_like(mean, np.nan, dtype=float)
        else:
            # divided by √m before the scale is put back: sem ≤ max|value|, so it stays finite
            # where the standard deviation itself (up to √2 max|value|) would overflow
            sem = unit.std(axis=axis, ddof=1, keepdims=True) / np.sqrt(m)
            sem = np.squeeze(scale * sem, axis=axis)
    if np.ndim(mean) == 0:
        return float(mean), float(sem)
    return mean, sem


def mean_sem_json(values) -> list:
    """``[mean, sem]`` of 1-D ``values`` (:func:`mean_sem`) as JSON numbers, the error ``None``
    for a single value; ``[None, None]`` for none.

    Parameters
    ----------
    values : array_like
        The values (flattened).

    Returns
    -------
    list
        ``[mean, sem]`` as floats, or ``None`` where one is not finite (a NaN kurtosis).
    """
    a = np.asarray(values, dtype=float).ravel()
    if a.size == 0:
        return [None, None]
    mean, sem = mean_sem(a)
    # NaN and ±inf are not JSON numbers (json.dumps would write the non-standard NaN)
    return [mean if math.isfinite(mean) else None,
            sem if a.size > 1 and math.isfinite(sem) else None]
