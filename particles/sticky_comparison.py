"""The sticky gas against its exact late-time laws: histograms of runs pooled at one time
(:class:`ExactLawComparison`) and the unit of work of a large ensemble (:func:`exact_law_runs`).
The laws themselves are in :mod:`particles.sticky_exact`, the engine in :mod:`particles.sticky`.
"""

from __future__ import annotations

import math

import numpy as np

from .sticky import StickyGas, StickyParams, StickyState, check_state
from .sticky_exact import (
    exact_mass_density,
    exact_moments,
    exact_velocity_density,
    exact_velocity_survival,
)
from .validation import InvalidArgumentError, check_count, check_positive

__all__ = [
    "EXACT_W_EDGES",
    "ExactLawComparison",
    "exact_law_runs",
]


# ---------------------------------------------------------------------------------------------
# The engine against the exact laws

#: The scaled-velocity bins of :class:`ExactLawComparison`: 24 bins of width 0.25 on w ∈ [−3, 3]
#: (the two open bins beyond ±3 are added to the outermost ones).
EXACT_W_EDGES = np.linspace(-3.0, 3.0, 25)

_EXACT_CACHE: dict = {}  # exact bin integrals and survivals on fixed grids, computed once


def _bin_integrals(density, edges, nodes: int = 12) -> np.ndarray:
    """∫ ``density`` over each [edges[i], edges[i + 1]] by Gauss–Legendre with ``nodes`` nodes."""
    from scipy.special import roots_legendre

    edges = np.asarray(edges, dtype=float)
    x, weight = roots_legendre(int(nodes))
    lo, hi = edges[:-1, None], edges[1:, None]
    pts = 0.5 * (hi - lo) * (x[None, :] + 1.0) + lo
    return (density(pts) * weight[None, :]).sum(axis=1) * 0.5 * (hi - lo)[:, 0]


def _cached(key, compute):
    if key not in _EXACT_CACHE:
        _EXACT_CACHE[key] = compute()
    return _EXACT_CACHE[key]


def _two_sided_survival(w) -> np.ndarray:
    """2 :func:`~particles.sticky_exact.exact_velocity_survival` at the positive ``w``, each
    value computed once."""
    w = np.atleast_1d(np.asarray(w, dtype=float))
    new = [x for x in np.unique(w).tolist() if ("S", x) not in _EXACT_CACHE]
    if new:
        for x, value in zip(new, 2.0 * exact_velocity_survival(np.array(new)), strict=True):
            _EXACT_CACHE[("S", x)] = float(value)
    return np.array([_EXACT_CACHE[("S", x)] for x in w.tolist()])


def _merge_outer(clusters_per_bin, minimum: float) -> np.ndarray:
    """Start indices of groups of adjacent bins: the outer bins are merged inwards (from each
    end) until each end group holds at least ``minimum`` clusters."""
    k = clusters_per_bin.size
    lo, acc = 0, 0.0
    while lo < k // 2 and acc + clusters_per_bin[lo] < minimum:
        acc += clusters_per_bin[lo]
        lo += 1
    hi, acc = k, 0.0
    while hi > k // 2 and acc + clusters_per_bin[hi - 1] < minimum:
        acc += clusters_per_bin[hi - 1]
        hi -= 1
    return np.concatenate([[0], np.arange(lo + 1, min(hi, k))]) if hi > lo + 1 else np.array([0])


class ExactLawComparison:
    """Sticky-gas states at one time t, pooled over runs (:meth:`add`), against the exact
    late-time laws: the mass-weighted velocity histogram in w = v (n t/T₀)^{1/3}
    (:meth:`velocity`), the cluster-mass histogram in μ = m/(n² T₀ t²)^{1/3} (:meth:`mass`) and
    the two-sided survival P(|w| > w_k) with its local exponent β on the grid ``tail_w``
    (:meth:`tail`).  ``variance`` is T₀, the variance of the initial velocities (the engine
    draws 1); the density n is read from each state (N/L).  Only histograms are kept, so states
    of any size can be added one at a time.

    Variance models (χ² = Σ (observed − expected)²/variance over the bins):

    * velocity: a cluster's particles share one velocity, so a bin's particle count is a sum of
      cluster masses; clusters are taken as independent, and the variance of the count is
      Σ m² over the clusters in the bin.  Bins of width 0.25 on [−3, 3], the open bins beyond
      added to the outermost ones, and the outer bins merged inwards until each end holds at
      least ``min_clusters`` clusters.  Expected: N ∫ P(w) dw over the bin
      (:func:`~particles.sticky_exact.exact_velocity_density`, Gauss–Legendre with 8 nodes;
      beyond ±3 :func:`~particles.sticky_exact.exact_velocity_survival`).  dof = number of bins
      (nothing is fitted).
    * mass: integer masses grouped in bins [m_a, m_b] (half-integer edges, about 12 per decade
      from m = 1 to 8 M, M = (n² T₀ t²)^{1/3}; masses beyond go to the last bin), cluster counts
      taken as independent Poisson numbers (variance = expected count, checked against the
      scatter of independent runs in the comparison's tests); expected N/M ∫ F(μ) dμ over
      [m_a − ½, m_b + ½]/M (:func:`~particles.sticky_exact.exact_mass_density`, 8 nodes); bins
      with fewer than ``min_clusters`` expected clusters are merged with their neighbours.
      dof = bins.
    * tail: S_k = (mass of the clusters with |w| > w_k)/N, variance Σ m²/N² over those
      clusters; the chord exponent between neighbours β_k = Δ ln(−ln S)/Δ ln w, its error by the
      delta method with the clusters above w_{k+1} and those between w_k and w_{k+1} as two
      independent sums; only grid points with at least ``min_clusters`` clusters beyond count
      as resolved.  The exact β_k is the same chord on 2
      :func:`~particles.sticky_exact.exact_velocity_survival`.

    The finite-t corrections to scaling are the only systematic difference (finite N enters
    through the ring's length only), so χ²/dof → 1 as t grows at fixed N per bin.

    Parameters
    ----------
    t : float
        The time of the states, > 0.
    variance : float
        T₀.
    w_edges : array_like
        The velocity histogram's edges in w.
    tail_w : array_like, optional
        The tail grid (default 10 geometric points from 0.5 to 4).
    min_clusters : int
        Clusters needed per outer bin and beyond a resolved tail point.

    Raises
    ------
    InvalidArgumentError
        Naming the argument that is out of its domain.
    """

    def __init__(self, t: float, *, variance: float = 1.0, w_edges=EXACT_W_EDGES,
                 tail_w=None, min_clusters: int = 25):
        self.t = check_positive(t, "t")
        self.variance = check_positive(variance, "variance")
        self.w_edges = np.asarray(w_edges, dtype=float)
        if self.w_edges.ndim != 1 or self.w_edges.size < 2 or np.any(np.diff(self.w_edges) <= 0):
            raise InvalidArgumentError("w_edges", w_edges, "increasing bin edges")
        grid = np.geomspace(0.5, 4.0, 10) if tail_w is None else np.asarray(tail_w, float)
        if grid.ndim != 1 or grid.size < 2 or grid[0] <= 0 or np.any(np.diff(grid) <= 0):
            raise InvalidArgumentError("tail_w", tail_w, "increasing positive velocities")
        self.tail_w = grid
        self.min_clusters = check_count(min_clusters, "min_clusters", 1)
        nb = self.w_edges.size + 1  # with the open bins below and above
        self.particles = 0
        self.runs = 0
        self.energy = []  # E (n t)^{2/3} T₀^{−2/3} per run
        self.cluster_count = []  # clusters × M / N per run
        self._v = np.zeros((3, nb))  # Σ m, Σ m², clusters per velocity bin
        self._m = np.zeros(0)  # clusters per integer mass
        self._s = np.zeros((3, grid.size + 1))  # the same per tail interval
        self._top = (np.zeros(0), np.zeros(0))  # the fastest clusters' |w| and masses
        self._scales = None

    def _scale(self, state):
        n = state.velocities.size / state.length
        wscale = (n * self.t / self.variance) ** (1.0 / 3.0)
        mscale = (n * n * self.variance * self.t * self.t) ** (1.0 / 3.0)
        if self._scales is None:
            self._scales = (n, wscale, mscale)
        elif not math.isclose(n, self._scales[0], rel_tol=1e-12):
            raise InvalidArgumentError("state", f"density {n}", f"density {self._scales[0]}")
        return wscale, mscale

    def add(self, state: StickyState) -> None:
        """Add one run's state at time t to the histograms.

        Parameters
        ----------
        state : StickyState
            A state at time t.

        Raises
        ------
        InvalidArgumentError
            Naming ``state`` when it is at another time or of another density.
        """
        check_state(state)
        if not math.isclose(state.time, self.t, rel_tol=1e-12):
            raise InvalidArgumentError("state", f"time {state.time}", f"time {self.t}")
        wscale, mscale = self._scale(state)
        m = state.masses
        mf = m.astype(float)
        w = state.cluster_velocities * wscale
        n = int(m.sum())
        idx = np.searchsorted(self.w_edges, w, side="right")  # 0: below, size: above
        for row, weight in enumerate((mf, mf * mf, None)):
            self._v[row] += np.bincount(idx, weights=weight, minlength=self._v.shape[1])
        counts = np.bincount(m)
        if counts.size > self._m.size:
            self._m = np.pad(self._m, (0, counts.size - self._m.size))
        self._m[:counts.size] += counts
        aw = np.abs(w)
        k = np.searchsorted(self.tail_w, aw, side="left")  # grid points below |w|
        for row, weight in enumerate((mf, mf * mf, None)):
            self._s[row] += np.bincount(k, weights=weight, minlength=self._s.shape[1])
        keep = 4 * self.min_clusters
        top_w = np.concatenate([self._top[0], aw])
        top_m = np.concatenate([self._top[1], mf])
        if top_w.size > keep:
            sel = np.argpartition(top_w, top_w.size - keep)[-keep:]
            top_w, top_m = top_w[sel], top_m[sel]
        self._top = (top_w, top_m)
        self.particles += n
        self.runs += 1
        self.energy.append(float(np.sum(mf * w * w)) / n)
        self.cluster_count.append(m.size * mscale / n)

    def _need(self):
        if self.runs == 0:
            raise InvalidArgumentError("states", 0, "at least one added state")

    def velocity(self) -> dict:
        """χ² of the velocity histogram (class docstring): ``chi2``, ``dof``, the bins
        ``edges`` (±inf at the open ends), ``observed``, ``expected``, ``sigma`` (particles per
        merged bin) and, on the unmerged bins of ``w_edges``, ``density`` (observed particles /
        (N × width)) and ``density_error``.

        Returns
        -------
        dict
        """
        self._need()
        e = self.w_edges
        inner = _cached(("velocity", tuple(e.tolist())),
                        lambda: _bin_integrals(exact_velocity_density, e, 8))
        below, above = 0.5 * _two_sided_survival(np.abs(e[[0, -1]]))
        below = 1.0 - below if e[0] > 0 else below
        above = 1.0 - above if e[-1] < 0 else above
        expected = self.particles * np.concatenate([[below], inner, [above]])
        counts, var, ncl = self._v
        groups = _merge_outer(ncl, self.min_clusters)
        obs, var_g, exp_g = (np.add.reduceat(a, groups) for a in (counts, var, expected))
        ok = var_g > 0
        chi2 = float(np.sum((obs[ok] - exp_g[ok]) ** 2 / var_g[ok]))
        full = np.concatenate([[-np.inf], e, [np.inf]])
        width = np.diff(e) * self.particles
        return {"t": self.t, "chi2": chi2, "dof": int(ok.sum()),
                "edges": np.append(full[groups], np.inf), "observed": obs, "expected": exp_g,
                "sigma": np.sqrt(var_g), "density": counts[1:-1] / width,
                "density_error": np.sqrt(var[1:-1]) / width}

    def mass(self) -> dict:
        """χ² of the cluster-mass histogram (class docstring): ``chi2``, ``dof``, the integer
        bins ``lo``, ``hi`` (inclusive; the last open), ``observed``, ``expected``, and
        ``mu`` (bin centres (lo + hi)/2M), ``density`` (observed F: clusters / (N/M × bin width
        in μ)), ``density_error`` (Poisson), ``exact`` (the expected F on the same bins).

        Returns
        -------
        dict
        """
        self._need()
        mscale = self._scales[2]
        upper = max(2, int(8.0 * mscale + 1e-9))
        per_decade = 12
        cuts = np.unique(np.round(np.geomspace(
            1, upper + 1, max(per_decade, int(per_decade * math.log10(upper + 1))) + 1)))
        edges = cuts - 0.5
        fine = self.particles / mscale * _bin_integrals(exact_mass_density, edges / mscale, 8)
        starts = [0]
        acc = 0.0
        for i, x in enumerate(fine):  # merge bins with fewer than min_clusters expected
            acc += x
            if acc >= self.min_clusters and i < fine.size - 1:
                starts.append(i + 1)
                acc = 0.0
        if acc < self.min_clusters and len(starts) > 1:
            starts.pop()  # the last group is short: merge it with the one before
        starts = np.array(starts)
        expected = np.add.reduceat(fine, starts)
        lo = cuts[starts].astype(int)
        hi = np.append(cuts[starts[1:]] - 1, upper).astype(int)
        per_mass = self._m
        csum = np.concatenate([[0.0], np.cumsum(per_mass)])
        top = min(per_mass.size, upper + 1)
        observed = (csum[np.minimum(hi + 1, top)] - csum[np.minimum(lo, top)])
        observed[-1] += csum[-1] - csum[top]  # masses beyond the last edge
        chi2 = float(np.sum((observed - expected) ** 2 / expected))
        width = (hi - lo + 1) / mscale
        norm = self.particles / mscale * width
        return {"t": self.t, "chi2": chi2, "dof": int(expected.size), "lo": lo, "hi": hi,
                "observed": observed, "expected": expected, "mu": 0.5 * (lo + hi) / mscale,
                "density": observed / norm, "density_error": np.sqrt(expected) / norm,
                "exact": expected / norm}

    def tail(self, exact: bool = True) -> dict:
        """The two-sided survival S(w) = P(|w| > w_k) on ``tail_w`` and its chord exponents
        (class docstring): ``w``, ``survival``, ``survival_error``, ``clusters_beyond``,
        ``resolved`` (bool per point), ``exact_survival`` (resolved points only, NaN
        elsewhere), ``beta`` / ``beta_error`` / ``beta_exact`` per chord between consecutive
        resolved points (at ``beta_w``, the geometric middles), and ``deepest``: the
        ``min_clusters``-th fastest cluster's |w|, the engine's S there (clusters at or beyond
        it) with its error, and the exact S.  ``exact=False`` leaves the exact values NaN (they
        cost ~0.16 s per point; each point is computed once per process).

        Parameters
        ----------
        exact : bool
            Compute the exact values too.

        Returns
        -------
        dict
        """
        self._need()
        grid = self.tail_w
        mass, mass2, ncl = (np.cumsum(row[::-1])[::-1][1:] for row in self._s)
        total = float(self.particles)
        s = mass / total
        ds = np.sqrt(mass2) / total
        resolved = ncl >= self.min_clusters
        res = np.flatnonzero(resolved)
        exact_s = np.full(grid.size, np.nan)
        if res.size and exact:
            exact_s[res] = _two_sided_survival(grid[res])
        k0, k1 = res[:-1], res[1:]
        dlw = np.log(grid[k1]) - np.log(grid[k0])
        with np.errstate(divide="ignore", invalid="ignore"):
            beta = (np.log(-np.log(s[k1])) - np.log(-np.log(s[k0]))) / dlw
            beta_exact = (np.log(-np.log(exact_s[k1])) - np.log(-np.log(exact_s[k0]))) / dlw
            g0 = 1.0 / (s[k0] * np.log(s[k0]))
            g1 = 1.0 / (s[k1] * np.log(s[k1]))
        var_b = mass2[k1] / total**2
        var_d = (mass2[k0] - mass2[k1]) / total**2
        beta_error = np.sqrt((g1 - g0) ** 2 * var_b + g0**2 * var_d) / dlw
        tw, tm = self._top
        order = np.argsort(tw)[::-1]
        j = min(self.min_clusters, order.size) - 1
        w_deep = float(tw[order[j]])
        m_deep = tm[order[: j + 1]]
        deep = {"w": w_deep, "clusters": j + 1, "survival": float(m_deep.sum()) / total,
                "survival_error": float(np.sqrt(np.sum(m_deep**2))) / total,
                "exact_survival": float(_two_sided_survival(w_deep)[0]) if exact else math.nan}
        return {"t": self.t, "w": grid, "survival": s, "survival_error": ds,
                "clusters_beyond": ncl, "resolved": resolved, "exact_survival": exact_s,
                "beta_w": np.sqrt(grid[k0] * grid[k1]), "beta": beta, "beta_error": beta_error,
                "beta_exact": beta_exact, "deepest": deep}

    def corrections(self) -> dict:
        """The scale-free corrections to scaling: E (n t)^{2/3} T₀^{−2/3} and the number of
        clusters × M/N, mean ± standard error over the runs, against their exact limits
        (:func:`~particles.sticky_exact.exact_moments` ``velocity_variance`` and ``clusters``).

        Returns
        -------
        dict
            ``energy`` and ``clusters``: ``value`` (mean, standard error), ``exact`` and
            ``relative``.
        """
        self._need()
        mom = exact_moments()
        out = {}
        for key, values, limit in (("energy", self.energy, mom["velocity_variance"]),
                                   ("clusters", self.cluster_count, mom["clusters"])):
            x = np.asarray(values)
            se = float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else None
            out[key] = {"value": [float(x.mean()), se], "exact": limit,
                        "relative": float(x.mean() / limit - 1.0)}
        return out

    def sums(self) -> dict:
        """The pooled histograms this comparison has accumulated (copies): what
        :meth:`merge` adds.

        Returns
        -------
        dict
            ``scales`` (the density n and the scales of w and μ; None before the first
            state), ``velocity_bins``
            (Σ m, Σ m², clusters per velocity bin, 3 rows), ``tail_bins`` (the same per tail
            interval), ``masses`` (clusters per integer mass), ``fastest`` (|w| and masses
            of the fastest clusters kept for the deepest point), ``particles``, ``runs``,
            ``energy`` and ``cluster_count`` (per run).
        """
        return {"scales": self._scales, "velocity_bins": self._v.copy(),
                "tail_bins": self._s.copy(), "masses": self._m.copy(),
                "fastest": (self._top[0].copy(), self._top[1].copy()),
                "particles": self.particles, "runs": self.runs,
                "energy": list(self.energy), "cluster_count": list(self.cluster_count)}

    def merge(self, other: ExactLawComparison) -> None:
        """Add the runs of ``other`` (another comparison at the same time, on the same bins
        and grid, of a gas of the same density) to this one, as if they had been added here.

        Parameters
        ----------
        other : ExactLawComparison
            The comparison whose runs are added; it is not changed.

        Raises
        ------
        InvalidArgumentError
            Naming ``other`` when its time, variance, bins, grid, ``min_clusters`` or density
            differ from this one's.
        """
        theirs = other.sums() if isinstance(other, ExactLawComparison) else None
        same = (theirs is not None and other.t == self.t
                and other.variance == self.variance and other.min_clusters == self.min_clusters
                and np.array_equal(other.w_edges, self.w_edges)
                and np.array_equal(other.tail_w, self.tail_w)
                and (self._scales is None or theirs["scales"] is None
                     or math.isclose(theirs["scales"][0], self._scales[0], rel_tol=1e-12)))
        if not same:
            raise InvalidArgumentError("other", other, "a comparison at the same time, bins, "
                                       "grid, min_clusters and density")
        if theirs["runs"] == 0:
            return
        self._scales = self._scales or theirs["scales"]
        self._v += theirs["velocity_bins"]
        self._s += theirs["tail_bins"]
        masses = theirs["masses"]
        size = max(self._m.size, masses.size)
        self._m = np.pad(self._m, (0, size - self._m.size))
        self._m[:masses.size] += masses
        keep = 4 * self.min_clusters
        top_w = np.concatenate([self._top[0], theirs["fastest"][0]])
        top_m = np.concatenate([self._top[1], theirs["fastest"][1]])
        if top_w.size > keep:
            sel = np.argpartition(top_w, top_w.size - keep)[-keep:]
            top_w, top_m = top_w[sel], top_m[sel]
        self._top = (top_w, top_m)
        self.particles += theirs["particles"]
        self.runs += theirs["runs"]
        self.energy += theirs["energy"]
        self.cluster_count += theirs["cluster_count"]


def exact_law_runs(n: int, seeds, times, *, density: float = 1.0, tail_w=None,
                   min_clusters: int = 25) -> list[ExactLawComparison]:
    """Runs of the sticky gas (Gaussian initial velocities of unit variance) added to one
    :class:`ExactLawComparison` per time: the unit of work of a large ensemble, whose pieces
    are joined by :meth:`ExactLawComparison.merge`.

    Each seed is one gas of ``n`` particles drawn by
    :meth:`particles.sticky.StickyGas.initial_state` from ``numpy.random.default_rng(seed)``
    and advanced exactly to every time of ``times``.

    Parameters
    ----------
    n : int
        Particles per gas.
    seeds : iterable of int
        One gas per seed, in this order.
    times : sequence of float
        The times t (physical time) at which each gas is compared.
    density : float
        Number density N/L.
    tail_w, min_clusters
        As for :class:`ExactLawComparison`.

    Returns
    -------
    list of ExactLawComparison
        One per time, in the order of ``times``.
    """
    engine = StickyGas(StickyParams(n, density, "gaussian"))
    out = [ExactLawComparison(float(t), tail_w=tail_w, min_clusters=min_clusters) for t in times]
    for seed in seeds:
        s0 = engine.initial_state(np.random.default_rng(int(seed)))
        for cmp in out:
            cmp.add(engine.advance(s0, cmp.t))
        del s0
    return out
