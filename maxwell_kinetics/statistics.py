"""Statistics for comparing particle samples with a predicted law (NumPy/SciPy only).

Conventions.  A predicted law is given either by its rescaled characteristic function G(q)
(P̂(k) = ∫ e^{ikv} P(v) dv, x = v / v0; G(−q) = conj G(q)) or directly by bin probabilities.
The probability of a bin [a, b] is

    Pr(a ≤ x < b) = (1/π) Re ∫_0^∞ G(q) · 2 sin(q h)/q · e^{−iqm} dq,   m = (a+b)/2, h = (b−a)/2,

computed by composite Gauss–Legendre quadrature on [0, q_max] (the integrand is smooth at
q = 0).  Unlike a density evaluated at points, a bin probability converges even for laws with a
jump (G ~ 1/q): the integrand then decays like 1/q², so the cut at q_max costs O(1/q_max²).

Distances, all with their expectation under the null hypothesis "the samples were drawn from the
predicted law".  They are computed by :meth:`particles.observables.Histogram.distance` (module
:mod:`particles.distance`), the one home of χ² and KS; :func:`compare_histograms` adds what a
comparison of several runs needs around them:

* ``ks``: the Kolmogorov–Smirnov distance sup |F_emp − F| on the bin edges, counting from the
  first edge.  For M independent samples its mean is ≈ 0.8687/√M (the mean of Kolmogorov's law,
  √(π/2) ln 2, slightly less when restricted to the edges), so √M · D_KS ≈ 0.87 and D_KS falls
  like 1/√M.
* ``chi2``: Pearson's χ² (the variance of each bin from the predicted probability) over the bins
  with at least 5 expected counts, divided by its degrees of freedom (the bins used);
  expectation 1, standard deviation √(2/dof), for independent samples.  Velocities of one
  particle run are *not* independent (collisions correlate them), which inflates the bin
  variances by an overdispersion factor φ.  φ is measured from the scatter of the counts
  between independent runs (seeds), without using the prediction, and the pooled χ²/dof is
  compared with φ.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from particles.observables import Histogram, histogram_from_counts, mean_sem
from particles.validation import (
    InvalidArgumentError,
    check_count,
    check_edges,
    check_fit_points,
    check_nonnegative,
    check_positive,
    check_real_array,
)

__all__ = [
    "interval_probabilities",
    "interval_bound",
    "f_cdf",
    "f_interval_probabilities",
    "bin_counts",
    "HistogramComparison",
    "compare_histograms",
    "law_histogram",
    "KS_MEAN",
    "weighted_slope",
    "seed_slope",
]

#: Mean of Kolmogorov's distribution: E[√M · D_KS] → √(π/2) ln 2 for M independent samples.
KS_MEAN = math.sqrt(math.pi / 2.0) * math.log(2.0)


def _gauss_nodes(q_max: float, width: float, nodes_per_panel: int = 16):
    panels = max(1, math.ceil(q_max / width))
    t, w = np.polynomial.legendre.leggauss(nodes_per_panel)
    edges = np.linspace(0.0, q_max, panels + 1)
    half = 0.5 * np.diff(edges)
    q = (edges[:-1, None] + half[:, None] * (t[None, :] + 1.0)).ravel()
    return q, (half[:, None] * w[None, :]).ravel()


#: Most kernel elements (bins × nodes) of :func:`interval_probabilities` built at once.
_KERNEL_ELEMENTS = 2**18
#: The most kernel elements (bins × q nodes, summed over the node sets) that one call of
#: :func:`interval_probabilities` computes.  Each costs a sine and a complex exponential:
#: 200–430 ns measured on 2 cores under a load of 6–9 (10⁶ bins on [−6, 6], 1.1·10⁹
#: elements, took 280 s), so this is one to four minutes.
MAX_KERNEL_WORK = 5e8
#: Seconds per kernel element that the refusal quotes (the measurement above, loaded).
SECONDS_PER_KERNEL_ELEMENT = 2.5e-7


def interval_probabilities(G: Callable, edges, q_max: float) -> np.ndarray:
    """Pr(edges[i] ≤ x < edges[i+1]) for the law with rescaled characteristic function ``G``.

    ``G`` is a callable of an array of q ≥ 0 (it is only evaluated on [0, q_max]).  Finite edges
    only; the panels are narrow enough that each sees at most half an oscillation of the
    integrand (width ≤ π / (|m| + h)).  The formula (module docstring) follows from
    P̂(k) = ∫ e^{ikv} P(v) dv, so the inverse transform carries e^{−iqx}.

    Parameters
    ----------
    G : callable
        The rescaled characteristic function, G(q) for an array of q ≥ 0 (real or complex).
    edges : array_like
        Increasing finite bin edges in the rescaled velocity x = v / v0.
    q_max : float
        Cut of the q integral (composite 16-point Gauss–Legendre panels on [0, q_max]).

    Returns
    -------
    numpy.ndarray
        Shape (len(edges) − 1,): the bin probabilities.

    Raises
    ------
    particles.InvalidArgumentError
        If ``G`` is not callable, ``edges`` are not finite and strictly increasing,
        ``q_max`` is not a finite number > 0, or an edge is so far out that the node set of
        its bin would exceed :data:`maxwell_kinetics.velocity.MAX_QUADRATURE_NODES` or the
        memory available, or the bins × nodes exceed :data:`MAX_KERNEL_WORK` (naming
        ``edges``, before any work).
    """
    if not callable(G):
        raise InvalidArgumentError("G", G, "a callable G(q)")
    edges = check_edges(edges, "edges")
    q_max = check_positive(q_max, "q_max")
    from .velocity import check_quadrature

    a, b = edges[:-1], edges[1:]
    m, h = 0.5 * (a + b), 0.5 * (b - a)
    out = np.empty(a.size)
    reach = np.abs(m) + h  # the largest |x| of each bin
    check_quadrature(q_max, reach, "edges")  # the widest bin's node set, before any work
    # Ordinary bins (reach <= 64) share one node set; wider ones share one per factor 2 of reach
    # (panels at least as narrow as each bin needs).  The kernel is built a block of bins at a
    # time, so that memory stays bounded whatever the number of bins.
    level = np.where(reach <= 64.0, 0.0, np.ceil(np.log2(np.maximum(reach, 64.0) / 64.0)))
    work = sum(np.count_nonzero(level == lv) * 16 * max(1, math.ceil(
        q_max / min(0.5, math.pi / max(float(reach[level == lv].max()), 1.0))))
        for lv in np.unique(level))
    if not work <= MAX_KERNEL_WORK:
        raise InvalidArgumentError(
            "edges", f"{a.size} bins on [{edges[0]:g}, {edges[-1]:g}]",
            f"at most {MAX_KERNEL_WORK:.0e} bins × quadrature nodes (this: {work:.3g}, "
            f"about {work * SECONDS_PER_KERNEL_ELEMENT:.0f} s); fewer bins")
    for lv in np.unique(level):
        sel = np.flatnonzero(level == lv)
        r = float(reach[sel].max())
        q, w = _gauss_nodes(q_max, min(0.5, math.pi / max(r, 1.0)))
        wg = w * np.asarray(G(q), dtype=complex)
        rows = max(1, _KERNEL_ELEMENTS // q.size)
        for start in range(0, sel.size, rows):
            part = sel[start:start + rows]
            kernel = (2.0 * np.sin(np.outer(h[part], q)) / q[None, :]
                      * np.exp(-1j * np.outer(m[part], q)))
            out[part] = (kernel @ wg).real / math.pi
    return out


def interval_bound(A: Callable, edges, q_low: float, q_high: float) -> np.ndarray:
    """(1/π) ∫_{q_low}^{q_high} A(q) · 2 |sin(q h)|/q dq for each bin (h its half-width): the
    largest change of the bin probabilities of :func:`interval_probabilities` that an error of
    modulus at most A(q) in G(q) on [q_low, q_high] can cause (the absolute value of the
    integrand, whatever the phase of the error).

    Parameters
    ----------
    A : callable
        A(q) ≥ 0 for an array of q in [q_low, q_high]: a bound on the modulus of the error.
    edges : array_like
        Increasing finite bin edges in x (only the widths matter).
    q_low, q_high : float
        The q interval, 0 ≤ q_low < q_high (composite 16-point Gauss–Legendre panels of width at
        most 0.5 and π / max(h, 1)).

    Returns
    -------
    numpy.ndarray
        Shape (len(edges) − 1,): the bound for each bin (0 when q_low ≥ q_high).

    Raises
    ------
    particles.InvalidArgumentError
        If ``edges`` are not finite and strictly increasing.
    """
    edges = check_edges(edges, "edges")
    h = 0.5 * np.diff(edges)
    if not q_high > q_low:
        return np.zeros(h.size)
    width = min(0.5, math.pi / max(float(h.max()), 1.0))
    q, w = _gauss_nodes(q_high - q_low, width)
    q = q + q_low
    weights = w * np.abs(np.asarray(A(q), dtype=float))
    out = np.empty(h.size)
    rows = max(1, _KERNEL_ELEMENTS // q.size)
    for start in range(0, h.size, rows):
        part = slice(start, start + rows)
        out[part] = (2.0 * np.abs(np.sin(np.outer(h[part], q))) / q[None, :]) @ weights / math.pi
    return out


def f_cdf(x) -> np.ndarray:
    """CDF of the scaling solution f(x) = 2/(π(1+x²)²): 1/2 + (arctan x + x/(1+x²))/π.

    Parameters
    ----------
    x : array_like
        Rescaled velocities x = v / v0 (±inf allowed).

    Returns
    -------
    numpy.ndarray
        F(x), of the shape of ``x``.
    """
    x = np.asarray(x, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        ratio = np.where(np.isfinite(x), x / (1.0 + x * x), 0.0)
    return 0.5 + (np.arctan(x) + ratio) / math.pi


def f_interval_probabilities(edges) -> np.ndarray:
    """Exact bin probabilities of the scaling solution f (edges may include ±inf).

    Parameters
    ----------
    edges : array_like
        Increasing bin edges in x = v / v0.

    Returns
    -------
    numpy.ndarray
        Shape (len(edges) − 1,): differences of :func:`f_cdf`.

    Raises
    ------
    particles.InvalidArgumentError
        If ``edges`` are not real, at least two, strictly increasing and free of NaN.
    """
    arr = check_real_array(edges, "edges", ndim=1, min_size=2, finite=False)
    if np.any(np.isnan(arr)) or np.any(np.diff(arr) <= 0):
        raise InvalidArgumentError("edges", arr.tolist()[:50], "strictly increasing edges "
                                   "(±inf allowed, no NaN)")
    return np.diff(f_cdf(arr))


def bin_counts(samples, edges) -> np.ndarray:
    """Counts per bin for each run: ``samples`` (R, M) → (R, len(edges) − 1).

    Parameters
    ----------
    samples : array_like
        Shape (R, M), or (M,) for one run.
    edges : array_like
        Increasing bin edges (as for :func:`numpy.histogram`).

    Returns
    -------
    numpy.ndarray
        Float counts of shape (R, len(edges) − 1); samples outside the edges are not counted.

    Raises
    ------
    particles.InvalidArgumentError
        If ``samples`` are not finite reals of one or two dimensions, or ``edges`` are not
        finite and strictly increasing.
    """
    rows = np.atleast_2d(check_real_array(samples, "samples"))
    if rows.ndim != 2:
        raise InvalidArgumentError("samples", f"shape {rows.shape}", "shape (R, M) or (M,)")
    edges = check_edges(edges, "edges")
    return np.stack([np.histogram(r, bins=edges)[0] for r in rows]).astype(float)


@dataclass(frozen=True)
class HistogramComparison:
    """Pooled histogram of R runs against predicted bin probabilities.

    Returned by :func:`compare_histograms`.  The property ``ks_scaled`` = √M · ks (≈ 0.87 √φ
    under the null hypothesis) and ``chi2_over_phi`` = χ²/dof / φ (≈ 1 ± √(2/dof)).

    Attributes
    ----------
    centres : numpy.ndarray
        Bin centres.
    density : numpy.ndarray
        Pooled density (counts / (R M width)).
    error : numpy.ndarray
        Its standard error, from the scatter between runs (Poisson when R = 1).
    predicted : numpy.ndarray
        Predicted density (probability / width).
    chi2_dof : float
        Pearson χ²/dof of the pooled counts (binomial variances of the predicted
        probabilities), :meth:`particles.observables.Histogram.distance`'s.
    dof : int
        Degrees of freedom of χ² (the bins with at least ``min_expected`` expected counts).
    overdispersion : float
        φ, the mean over bins of (between-run variance of the counts) / (binomial variance);
        φ = 1 for independent samples, NaN when R < 2.
    overdispersion_error : float
        Standard error of φ.
    ks : float
        Mean Kolmogorov–Smirnov distance of the single runs on the edges
        (:meth:`particles.observables.Histogram.distance`'s).
    ks_error : float
        Its standard error.
    samples : int
        M, the samples per run.
    runs : int
        R, the number of runs.
    """

    centres: np.ndarray
    density: np.ndarray
    error: np.ndarray
    predicted: np.ndarray
    chi2_dof: float
    dof: int
    overdispersion: float
    overdispersion_error: float
    ks: float
    ks_error: float
    samples: int
    runs: int

    @property
    def ks_scaled(self) -> float:
        """√M · ks: ≈ 0.87 √φ under the null hypothesis (``KS_MEAN`` for independent samples)."""
        return self.ks * math.sqrt(self.samples)

    @property
    def chi2_over_phi(self) -> float:
        """χ²/dof divided by φ: ≈ 1 ± √(2/dof) when the prediction is right."""
        return self.chi2_dof / self.overdispersion

    def summary(self) -> dict:
        """The comparison's numbers with their expectations under the null hypothesis.

        Returns
        -------
        dict
            JSON-able: ``chi2_dof``, ``dof``, ``chi2_dof_expected`` ([1, √(2/dof)]),
            ``overdispersion`` ([φ, error]), ``chi2_over_overdispersion``, ``ks`` ([mean,
            error]), ``ks_sqrt_M``, ``ks_sqrt_M_expected_iid`` (``KS_MEAN``),
            ``samples_per_run`` and ``runs``.
        """
        return {
            "chi2_dof": self.chi2_dof,
            "dof": self.dof,
            "chi2_dof_expected": [1.0, math.sqrt(2.0 / self.dof)],
            "overdispersion": [self.overdispersion, self.overdispersion_error],
            "chi2_over_overdispersion": self.chi2_over_phi,
            "ks": [self.ks, self.ks_error],
            "ks_sqrt_M": self.ks * math.sqrt(self.samples),
            "ks_sqrt_M_expected_iid": KS_MEAN,
            "samples_per_run": self.samples,
            "runs": self.runs,
        }


def law_histogram(edges, probabilities):
    """A predicted law on ``edges`` as the :class:`particles.observables.Histogram` a particle
    run returns: density = probability / width, zero ``error``, ``count`` 0, ``samples`` 0 (what
    :meth:`particles.observables.Histogram.distance` takes for a prediction).

    Parameters
    ----------
    edges : array_like
        Increasing finite bin edges in x.
    probabilities : array_like
        Predicted probabilities of the len(edges) − 1 bins.

    Returns
    -------
    particles.observables.Histogram
        The prediction (``v0`` 1: x is the only variable here).

    Raises
    ------
    particles.InvalidArgumentError
        If ``edges`` are not finite and strictly increasing, or ``probabilities`` are not one
        finite value per bin.
    """
    edges = check_edges(edges, "edges")
    prob = check_real_array(probabilities, "probabilities", ndim=1)
    if prob.size != edges.size - 1:  # quadrature may leave -1e-17: no sign check
        raise InvalidArgumentError("probabilities", prob.tolist()[:50],
                                   f"{edges.size - 1} probabilities, one per bin")
    width = np.diff(edges)
    return Histogram(edges, 0.5 * (edges[1:] + edges[:-1]), prob / width, np.zeros(width.size),
                     np.zeros(width.size, dtype=np.int64), 0, 1.0)


def compare_histograms(samples, edges, probabilities, *,
                       min_expected: float = 5.0) -> HistogramComparison:
    """Compare R runs of M samples (array (R, M)) with the predicted ``probabilities`` of the bins
    ``edges`` (finite edges; the mass outside them is not compared).

    The distances are :meth:`particles.observables.Histogram.distance`'s (module
    :mod:`particles.distance`), the one home of χ² and KS:

    * χ²/dof: the pooled histogram of the R·M samples against the law, with Pearson's variance,
      the binomial variance T p (1 − p) of the *predicted* bin probability p (T = R·M), over the
      bins with at least ``min_expected`` expected counts (the others get no variance and are
      left out).  Each term then has mean 1 under the null hypothesis, so χ²/dof ≈ 1 for
      independent samples, φ with correlated ones.  (A variance from the observed counts,
      Neyman's, is biased: E[(O − E)²/O] ≈ 1 + 2/E per bin.)
    * ks: the mean over the runs of each run's Kolmogorov–Smirnov distance to the law on the
      edges (the mass below the first edge counts 0 on both sides).

    φ is measured from the scatter between runs over the bins with at least ``min_expected``
    expected counts per run, the mass outside the edges as one more bin (module docstring).

    Parameters
    ----------
    samples : array_like
        Shape (R, M): R independent runs of M samples each (x = v / v0).
    edges : array_like
        Increasing finite bin edges.
    probabilities : array_like
        Predicted probabilities of the len(edges) − 1 bins.
    min_expected : float, default 5.0
        Smallest expected count of a bin kept in χ² (pooled) and in φ (per run).

    Returns
    -------
    HistogramComparison
        The pooled histogram, χ²/dof, φ and the KS distances.

    Raises
    ------
    particles.InvalidArgumentError
        If ``samples`` are not finite reals of shape (R, M) with M ≥ 1, ``edges`` are not finite
        and strictly increasing, ``probabilities`` are not one finite value per bin, or
        ``min_expected`` is not a finite number >= 0.
    """
    rows = np.atleast_2d(check_real_array(samples, "samples", min_size=1))
    if rows.ndim != 2:
        raise InvalidArgumentError("samples", f"shape {rows.shape}", "shape (R, M) or (M,)")
    runs, m = rows.shape
    law = law_histogram(edges, probabilities)
    edges = law.edges
    width = np.diff(edges)
    prob = law.density * width
    min_expected = check_nonnegative(min_expected, "min_expected")
    counts = bin_counts(rows, edges)
    pooled = counts.sum(axis=0)
    total = runs * m
    # The particle side of χ²: the pooled histogram with the law's binomial error (Pearson).
    # (the binomial error of the expected counts; quadrature may leave a probability of −1e-17)
    expected = histogram_from_counts(edges, total * np.clip(prob, 0.0, 1.0), total, 1.0)
    error = np.where(total * prob >= min_expected, expected.error, 0.0)
    particles = histogram_from_counts(edges, pooled, total, 1.0)
    particles = Histogram(edges, law.centres, particles.density, error, particles.count, total,
                          1.0)
    distance = particles.distance(law, min_count=0)
    ks = np.array([histogram_from_counts(edges, c, m, 1.0).distance(law, min_count=0).ks
                   for c in counts])
    # Overdispersion from the scatter between runs (needs R ≥ 2), over bins with ≥ 5 expected
    # counts per run; the prediction only sets the binomial reference variance.
    counts = np.column_stack([counts, m - counts.sum(axis=1)])
    prob_all = np.append(prob, max(0.0, 1.0 - prob.sum()))
    per_run = m * prob_all
    good = per_run >= min_expected
    if runs >= 2 and np.any(good):
        ratio = counts[:, good].var(axis=0, ddof=1) / (per_run[good] * (1.0 - prob_all[good]))
        phi = float(ratio.mean())
        # Each ratio has ≈ 2/(R − 1) relative variance; bins are nearly independent.
        phi_err = float(phi * math.sqrt(2.0 / ((runs - 1) * good.sum())))
    else:
        phi, phi_err = float("nan"), float("nan")
    if runs >= 2:
        err = mean_sem(counts[:, :-1], axis=0)[1] / (m * width)
    else:
        err = np.sqrt(pooled) / (total * width)
    return HistogramComparison(
        law.centres, particles.density, err, law.density, distance.chi2_dof, distance.dof,
        phi, phi_err, float(ks.mean()), mean_sem(ks)[1], m, runs,
    )


def weighted_slope(x, y, sigma=None) -> tuple[float, float, float]:
    """Least-squares line y = a + b x with standard errors ``sigma`` (None: unweighted, error
    from the residuals).

    Parameters
    ----------
    x, y : array_like
        The points.
    sigma : array_like, optional
        Standard errors of ``y`` (weights 1/σ²); None for an unweighted fit.

    Returns
    -------
    tuple of float
        (slope, slope standard error, intercept).  Unweighted with at most 3 points the
        standard error is NaN.

    Raises
    ------
    particles.InvalidArgumentError
        If ``x`` and ``y`` are not finite one-dimensional arrays of one length with at least two
        distinct x (a line through one abscissa is not determined), or ``sigma`` is not one
        finite value > 0 per point.
    """
    x, y = check_fit_points(x, y, fewest=2)
    if y.ndim != 1:
        raise InvalidArgumentError("y", f"shape {y.shape}", "a one-dimensional array")
    if sigma is not None:
        sigma = check_real_array(sigma, "sigma", ndim=1)
        if sigma.size != x.size or np.any(sigma <= 0):
            raise InvalidArgumentError("sigma", sigma.tolist()[:50],
                                       f"{x.size} standard errors > 0, one per point")
    if sigma is None:
        coef, cov = np.polyfit(x, y, 1, cov=True) if x.size > 3 else (np.polyfit(x, y, 1), None)
        err = math.sqrt(cov[0, 0]) if cov is not None else float("nan")
        return float(coef[0]), err, float(coef[1])
    w = 1.0 / np.asarray(sigma, dtype=float) ** 2
    sw, sx, sy = w.sum(), (w * x).sum(), (w * y).sum()
    sxx, sxy = (w * x * x).sum(), (w * x * y).sum()
    det = sw * sxx - sx * sx
    slope = (sw * sxy - sx * sy) / det
    return float(slope), float(math.sqrt(sw / det)), float((sxx * sy - sx * sxy) / det)


def seed_slope(x, ys, degree: int = 1) -> tuple[float, float, np.ndarray]:
    """Fit a polynomial of ``degree`` to each run's ``ys[i]`` against ``x`` and return (mean
    slope, its standard error from the scatter between runs, the per-run slopes); the slope is
    the linear coefficient, i.e. dy/dx at x = 0.

    Parameters
    ----------
    x : array_like
        Abscissae, shared by the runs.
    ys : array_like
        Shape (R, len(x)): one row per run (seed).
    degree : int, default 1
        Degree of the polynomial.

    Returns
    -------
    mean : float
        Mean slope over the runs.
    error : float
        Its standard error from the scatter between runs.
    slopes : numpy.ndarray
        Shape (R,): the per-run slopes.

    Raises
    ------
    particles.InvalidArgumentError
        If ``degree`` is not an integer >= 1, or ``x`` and ``ys`` are not finite arrays with
        one value per x in each row and at least ``degree`` + 1 distinct x (fewer leave the
        polynomial undetermined).
    """
    degree = check_count(degree, "degree", 1)
    x, ys = check_fit_points(x, ys, fewest=degree + 1, name_y="ys")
    ys = np.atleast_2d(ys)
    slopes = np.array([np.polyfit(x, y, degree)[-2] for y in ys])
    mean, err = mean_sem(slopes)
    return mean, err, slopes


def __getattr__(name: str):
    if name == "ks_distance":
        raise ImportError("maxwell_kinetics.statistics.ks_distance was removed: the "
                          "Kolmogorov–Smirnov distance is the ks of "
                          "particles.observables.Histogram.distance")
    raise AttributeError(f"module 'maxwell_kinetics.statistics' has no attribute {name!r}")
