"""The distance between two histograms on the same bins: the one home of the χ² and the
Kolmogorov–Smirnov distance of :meth:`particles.observables.Histogram.distance`.

Conventions.  A histogram here is a density on bins (``density[b]`` = mass in bin b / its
width) with a standard error per bin; a prediction (e.g. the kinetic theory's
:meth:`maxwell_kinetics.solution.Solution.histogram`) is a histogram with zero error.

* χ² = Σ_b (ρ₁[b] − ρ₂[b])² / (σ₁[b]² + σ₂[b]²) over the bins where the summed variance is
  positive and each sampled side (``samples > 0``) has at least ``min_count`` counts;
  ``dof`` is the number of those bins, minus one when every bin is used and both sides hold
  all their mass inside the edges (Σ ρ·width = 1 to 1e-9: the normalisation then ties the bins
  together, as in Pearson's test against a law, :func:`scipy.stats.chisquare`).  Under the
  hypothesis that both sides describe the same law with independent samples, χ²/dof has mean 1
  and standard deviation √(2/dof).  Correlated samples (one particle run) inflate it by the
  overdispersion φ of the bins.
* ``ks`` = sup over the edges of |F₁ − F₂|, F the cumulative mass from the first edge
  (Σ ρ·width over the bins to the left).  Mass below the first edge is not known to a histogram
  and counts as 0 on both sides, so with edges that hold (nearly) all the mass it is the
  two-sample Kolmogorov–Smirnov statistic restricted to the edges (exactly
  :func:`scipy.stats.ks_2samp`'s for samples that only take values between the edges, one per
  bin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .validation import InvalidArgumentError

__all__ = ["HistogramDistance", "histogram_distance"]


@dataclass(frozen=True)
class HistogramDistance:
    """The distance between two histograms on the same bins (:func:`histogram_distance`).

    Attributes
    ----------
    chi2 : float
        Σ (ρ₁ − ρ₂)² / (σ₁² + σ₂²) over the bins used.
    dof : int
        Degrees of freedom (bins used, minus one when normalisation ties them).
    chi2_dof : float
        χ²/dof (NaN when dof is 0).
    chi2_dof_expected : tuple of float
        (1, √(2/dof)): the mean and standard deviation of χ²/dof for independent samples of the
        same law.
    ks : float
        The Kolmogorov–Smirnov distance on the edges (module docstring).
    bins : numpy.ndarray
        Boolean mask of the bins used in χ², shape ``(B,)``.
    """

    chi2: float
    dof: int
    chi2_dof: float
    chi2_dof_expected: tuple
    ks: float
    bins: np.ndarray

    def to_dict(self) -> dict:
        """The distance as JSON-ready numbers.

        Returns
        -------
        dict
            ``chi2``, ``dof``, ``chi2_dof``, ``chi2_dof_expected`` (a list) and ``ks``.
        """
        return {"chi2": self.chi2, "dof": self.dof, "chi2_dof": self.chi2_dof,
                "chi2_dof_expected": list(self.chi2_dof_expected), "ks": self.ks}


def _mass_is_inside(h) -> bool:
    return abs(float(np.sum(h.density * np.diff(h.edges))) - 1.0) <= 1e-9


def _check_values(name: str, h, bins: int) -> None:
    """Refuse a histogram whose densities or errors are not ``bins`` finite values, or whose
    errors (or, for a sample, densities) are negative."""
    for field_name in ("density", "error"):
        try:
            values = np.asarray(getattr(h, field_name), dtype=float)
        except (TypeError, ValueError):
            values = None
        # a prediction's density may carry round-off below 0 far out; a sample's cannot
        negative = field_name == "error" or int(getattr(h, "samples", 0) or 0) > 0
        if values is None or values.shape != (bins,) or not np.all(np.isfinite(values)) \
                or (negative and np.any(values < 0)):
            raise InvalidArgumentError(
                name, getattr(h, field_name),
                f"a histogram with {bins} finite {field_name} values (one per bin), >= 0 for an "
                f"error or a sample's density (this is its {field_name})")


def histogram_distance(first, second, *, min_count: int = 5) -> HistogramDistance:
    """χ², its degrees of freedom and χ²/dof with the errors of both sides, and the
    Kolmogorov–Smirnov distance, between two histograms on the same edges (module docstring).

    Parameters
    ----------
    first, second : particles.observables.Histogram
        The two histograms (a prediction has zero ``error`` and ``samples`` 0).
    min_count : int, optional
        Bins where a sampled side counts fewer samples are left out of χ² (default 5; 0 keeps
        every bin with a positive variance).

    Returns
    -------
    HistogramDistance
        The distance.

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``other`` if it is not a histogram or has other edges than this one,
        ``histogram`` (``first``) or ``other`` when a density or an error is not finite or has
        not one value per bin, or when an error or a sampled histogram's density is negative,
        and ``min_count`` if it is not an integer ≥ 0.
    """
    for name in ("edges", "density", "error", "count", "samples"):
        if not hasattr(second, name):
            raise InvalidArgumentError("other", type(second).__name__, "a Histogram")
    if isinstance(min_count, bool) or not isinstance(min_count, (int, np.integer)) \
            or min_count < 0:
        raise InvalidArgumentError("min_count", min_count, "an integer ≥ 0")
    a, b = np.asarray(first.edges, float), np.asarray(second.edges, float)
    if a.shape != b.shape or not np.array_equal(a, b):
        raise InvalidArgumentError(
            "other", f"a histogram on {b.size} edges [{b[0]:g} … {b[-1]:g}]",
            f"a histogram on the same {a.size} edges [{a[0]:g} … {a[-1]:g}] as this one")
    for name, h in (("histogram", first), ("other", second)):
        _check_values(name, h, a.size - 1)
    variance = np.asarray(first.error, float) ** 2 + np.asarray(second.error, float) ** 2
    use = variance > 0
    for h in (first, second):
        if int(h.samples) > 0:
            use &= np.asarray(h.count) >= min_count
    diff = np.asarray(first.density, float) - np.asarray(second.density, float)
    chi2 = float(np.sum(diff[use] ** 2 / variance[use]))
    dof = int(use.sum())
    if dof and use.all() and _mass_is_inside(first) and _mass_is_inside(second):
        dof -= 1
    width = np.diff(a)
    cdf = np.concatenate([[0.0], np.cumsum(diff * width)])
    return HistogramDistance(
        chi2=chi2, dof=dof, chi2_dof=chi2 / dof if dof else float("nan"),
        chi2_dof_expected=(1.0, math.sqrt(2.0 / dof) if dof else float("nan")),
        ks=float(np.max(np.abs(cdf))), bins=use)
