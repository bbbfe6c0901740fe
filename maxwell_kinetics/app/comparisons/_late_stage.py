"""Comparison 9: the paper's late-stage figures at the paper's sizes, with the exact sticky gas
(:mod:`particles.sticky`) standing in for late MD, and the sticky gas against its exact late-time
laws: the velocity law and the cluster-mass law as whole curves (χ² per time, the corrections to
scaling shrinking with t), the local exponent β(w) of the velocity tail (engine and exact law),
E ~ t^(−2/3), S(k) against k t^(2/3) with its Porod tail, the shocks of v(x) and v(i), and the
displacements against Chernoff's law.  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.models import get_model
from particles.observables import mean_sem, mean_sem_json, structure_factor
from particles.progress import progress_bar
from particles.sticky_comparison import ExactLawComparison
from particles.sticky_exact import (
    CHERNOFF_VARIANCE,
    chernoff_density,
    displacement_scale,
    exact_mass_density,
    exact_moments,
    exact_velocity_density,
)
from particles.sticky_observables import cluster_mass_distribution, displacements, profile_x
from particles.validation import InvalidArgumentError

from .analysis import (
    binned_porod_fit,
    coarse_increment_skewness,
    log_binned,
    mass_density,
    porod_fit,
    profile_scales,
    small_mass_law,
    tail_grid,
    velocity_on_grid,
)
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import colors
from .sticky_tail import deep_tail_runs, exact_tail
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts"]

NAME = "late_stage"


def _times(lo, hi, count):
    return tuple(float(t) for t in np.round(np.geomspace(lo, hi, count), 3))


#: Two sets of runs (density 1, Gaussian initial velocities of unit variance, so w = v t^{1/3}
#: and μ = m / t^{2/3}):
#:
#: * ``n`` particles, ``seeds`` seeds 0, 1, …, at ``times`` (two decades or more): energy,
#:   S(k), kurtosis, skewness of the gradients, displacements and the zoomed profile;
#: * ``exact_n`` particles, ``exact_seeds`` seeds 1000, 1001, …, at ``exact_times``: the
#:   histograms against the exact laws (:class:`particles.sticky_comparison.ExactLawComparison`;
#:   outer bins merged until each holds ``min_clusters`` clusters, tail points resolved where that
#:   many clusters lie beyond), the tail survival on
#:   :func:`tail_grid` (``tail_w``: first point, last point, points per octave), its exponent
#:   reported at ``tail_time``, and the secondary small-μ fit of the mass law on the tables at
#:   ``fit_times`` (m ≥ ``fit_m_min``, μ ≤ ``fit_mu_max``: typical masses 460–2150, so that
#:   m ≥ 10 still reaches μ ~ 0.005).  ``beta_curve``: the exact β(w) is evaluated on
#:   ``count`` geometric points from ``lo`` to ``hi`` plus w = 1, 2, 3, 5, 10, 20, 30 up to
#:   ``hi`` (about 0.1 s per point; the crossings of 2 and 2.5 are interpolated between them,
#:   coarsely at the small size).
#:
#: * and, where ``deep_seeds`` > 0, ``deep_seeds`` gases of ``deep_n`` particles (seeds 2000,
#:   2001, …) at ``deep_times``, only for the deep tail: the survival and its chords β on
#:   :func:`tail_grid` (``deep_tail_w``) down to the ``min_clusters``-th fastest cluster,
#:   run on ``deep_workers`` processes (blocks of ``deep_block`` seeds, joined in seed order,
#:   so the numbers do not depend on the number of processes).
_SHARED = {"porod_x": (3.0, 15.0), "k_max": 0.6, "fit_times": (1e4, 3e4, 1e5), "fit_m_min": 10,
           "fit_mu_max": 0.3, "tail_time": 1000.0, "tail_w": (0.5, 8.0, 3), "min_clusters": 25,
           "deep_n": 10_000_000, "deep_seeds": 0, "deep_times": (31.6, 100.0, 316.0),
           "deep_tail_w": (1.0, 8.0, 6), "deep_block": 10, "deep_workers": 2}
PRESETS = {
    "small": {**_SHARED, "n": 100_000, "seeds": 3, "times": _times(10.0, 1000.0, 9),
              "exact_n": 2_000_000, "exact_seeds": 4,
              "exact_times": (10.0, 1000.0, 1e4, 3e4, 1e5), "tail_w": (1.0, 8.0, 3),
              "beta_curve": (1.0, 10.0, 2)},
    "default": {**_SHARED, "n": 1_000_000, "seeds": 4, "times": _times(10.0, 2000.0, 11),
                "exact_n": 10_000_000, "exact_seeds": 8,
                "exact_times": (10.0, 31.6, 100.0, 316.0, 1000.0, 1e4, 3e4, 1e5),
                "beta_curve": (0.5, 30.0, 19)},
    "full": {**_SHARED, "n": 10_000_000, "seeds": 4, "times": _times(10.0, 5000.0, 13),
             "exact_n": 10_000_000, "exact_seeds": 32,
             "exact_times": (10.0, 31.6, 100.0, 316.0, 1000.0, 1e4, 3e4, 1e5),
             "beta_curve": (0.5, 30.0, 25), "deep_seeds": 1000},
}


def _mean_se(values):
    return mean_sem_json([x for x in values if x is not None])


def run(size=None, progress: bool | None = None, runner=None, **overrides) -> Comparison:
    """Comparison 9: the late stage at the paper's sizes (N = 10⁵ small, 10⁶ default, 10⁷
    full), with the exact sticky gas standing in for late MD (from the same initial state MD at
    r = 0.5, δ = 10⁻⁴ and the sticky gas agree within a few per cent, comparison 8), and the
    sticky gas against its exact late-time laws (:data:`PRESETS` for the two sets of runs).
    Every number is mean ± standard error over the seeds unless said otherwise:

    * ``exact`` (the primary verdict): per time of ``exact_times``, χ² of the pooled
      mass-weighted velocity histogram in w = v t^{1/3} against
      :func:`particles.sticky_exact.exact_velocity_density` and of the pooled cluster-mass
      histogram in μ = m/t^{2/3} against :func:`particles.sticky_exact.exact_mass_density`, with
      their degrees of freedom (nothing is fitted) and the variance models of
      :class:`particles.sticky_comparison.ExactLawComparison` (velocity: Σ m² over the clusters in
      a bin;
      mass: Poisson); and the scale-free corrections to scaling E t^{2/3} and clusters ×
      t^{2/3}/N against their exact limits.  Finite t is the only systematic difference, so
      χ²/dof falls towards 1 as t grows;
    * ``tail``: the local exponent β(w) = d ln(−ln P(|w| > w))/d ln w.  Exact: on the
      ``beta_curve`` points (:func:`particles.sticky_exact.exact_velocity_tail_exponent`), with the
      w
      where β crosses 2 and 2.5 (cubic interpolation in ln w of those points) and the exact
      P(|w| > w) there.  Engine: chords of ln(−ln S) between neighbouring points of
      :func:`tail_grid`, pooled over the ``exact_seeds`` runs, at ``tail_time`` and per time,
      with their delta-method errors and the same chords of the exact S (z = difference /
      error), down to the deepest point with ``min_clusters`` clusters beyond, and the
      ``deepest`` resolved survival with the exact one there;
    * ``deep_tail`` (only where ``deep_seeds`` > 0, the full size): the same tail chords from
      ``deep_seeds`` independent gases of ``deep_n`` particles pooled at each of
      ``deep_times``, with the deepest resolved survival per time, to follow β(w) as far down
      as the ensemble reaches (the depth is set by the number of clusters beyond w);
    * ``mass``: the secondary small-μ fit of the mass law (:func:`small_mass_law` on the tables
      at ``fit_times``: A μ^a + B + C μ^{1/2}, expected a = −1/2);
    * ``energy``: E t^{2/3} per time, and the exponent of E ~ t^{z}: slope of ln E on ln t over
      all ``times``, with the window ``drift`` (half the difference of the slopes on the two
      halves) beside it;
    * ``structure``: S(k) of v(i) in label order (:func:`particles.observables.structure_factor`,
      as for MD) against k t^{2/3}; the collapse spread (rms over x ∈ [0.5, porod_x[1]] of the
      std over times of ln S) at z = 2/3 and unscaled; Porod slope of ln S on ln k over
      x ∈ ``porod_x``, k ≤ ``k_max`` (:func:`.analysis.porod_fit`) per time (expected −2);
    * ``kurtosis``: ⟨x⁴⟩ of x = v/√E per time (Gaussian 3; Fig. 1b: late P(x) is
      Gaussian-like);
    * ``skewness``: the sign of the large gradients of v(i) and of v(x) (particles' velocities
      interpolated on a grid of spacing L/N, :func:`.analysis.velocity_on_grid`) at the last
      time, raw and coarse-grained over m = 1, 4, 16, … ≤ N/64
      (:func:`.analysis.coarse_increment_skewness`; paper Fig. 4: v(x) negative, v(i)
      positive); the figure shows a window of a few clusters of seed 0;
    * ``displacement``: each particle's displacement D since t = 0 at the last time, as
      z = D / (b t^{2/3}) (:func:`particles.sticky_exact.displacement_scale`): ⟨z²⟩ per seed against
      Var Z = 0.26356 of Chernoff's law, the exact large-t limit, and the histogram of z
      against Chernoff's density in the figure.

    Parameters
    ----------
    size : str, optional
        "small", "default" or "full" (None: :func:`maxwell_kinetics.app.comparisons.default_size`);
        the parameters of each size are the module's ``PRESETS``.
    progress : bool
        Show progress on stderr.
    runner : maxwell_kinetics.app.comparisons.ParticleRuns, optional
        Shares particle runs between comparisons (default: a new serial runner).
    **overrides
        Parameters of the preset to replace.

    Returns
    -------
    maxwell_kinetics.app.comparisons.Comparison
        The summary (numbers with their uncertainties) and the data of the figure (:func:`plot`).

    Raises
    ------
    InvalidArgumentError
        Naming ``size`` or ``overrides`` (a parameter the preset does not have), or a parameter
        whose value is out of its domain.
    """
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    main = _main_runs(params, progress)
    exact = _exact_runs(params, progress)
    deep = deep_tail_runs(params, progress)
    summary = {"parameters": jsonable(params),
               "model": "exact sticky gas standing in for late MD",
               **main["summary"], **exact["summary"], **deep["summary"],
               "seconds": time.perf_counter() - start}
    return Comparison(NAME, with_verdicts(summary, verdicts),
                      {**main["data"], **exact["data"], **deep["data"]})


def _main_runs(params, progress) -> dict:
    """The runs of ``n`` particles at ``times`` (:func:`run`: energy, structure, kurtosis,
    skewness, displacement, and the zoomed window of seed 0 at the last time)."""
    n, times = int(params["n"]), np.asarray(params["times"], dtype=float)
    seeds = tuple(range(int(params["seeds"])))
    engine = get_model("sticky").build({"n": n, "density": 1.0, "initial": "gaussian"})
    length = engine.params.length
    nt = times.size
    energy = np.empty((len(seeds), nt))
    kurt = np.empty_like(energy)
    clusters = np.empty_like(energy)
    sb_sum = None  # log-binned S(k) summed over seeds, per time (binning is linear)
    porod_seed = [[None] * nt for _ in seeds]
    scales = profile_scales(n)
    skew = {"vi": [], "vx": []}
    window = {}
    scale = displacement_scale(1.0, 1.0)  # D / t^{2/3} → scale · Z (density 1, unit variance)
    z_edges = np.round(np.arange(-3.0, 3.0 + 1e-9, 0.1), 12)
    disp_hist = np.zeros(z_edges.size - 1)
    disp_var = []
    with progress_bar(len(seeds) * nt, f"sticky N={n}", "time", enabled=progress) as bar:
        for i, seed in enumerate(seeds):
            s0 = engine.initial_state(np.random.default_rng(seed))
            for j, t in enumerate(times):
                st = engine.advance(s0, float(t))
                v = st.velocities
                e = float(np.mean(v * v))
                energy[i, j] = e
                kurt[i, j] = float(np.mean(v**4)) / e**2
                clusters[i, j] = st.starts.size
                k, s = structure_factor(v)
                kb, sb = log_binned(k, s)
                if sb_sum is None:
                    sb_sum = np.zeros((nt, sb.size))
                sb_sum[j] += sb
                fit = porod_fit(k, s, t, 2.0 / 3.0, params["porod_x"], params["k_max"])
                porod_seed[i][j] = None if fit is None else fit[0]
                if j == nt - 1:
                    z = displacements(st) / (scale * float(t) ** (2.0 / 3.0))
                    disp_var.append(float(np.mean(z * z)))
                    disp_hist += np.histogram(z, z_edges)[0]
                    y, vv = profile_x(st)
                    vx = velocity_on_grid(y, vv, length)
                    skew["vi"].append([coarse_increment_skewness(v, m) for m in scales])
                    skew["vx"].append([coarse_increment_skewness(vx, m) for m in scales])
                    if i == 0:
                        window = _cluster_window(st)
                bar.update(1)
    lt, le = np.log(times), np.log(energy)
    slopes = [float(np.polyfit(lt, row, 1)[0]) for row in le]
    half = nt // 2
    drift = [0.5 * abs(float(np.polyfit(lt[:half + 1], row[:half + 1], 1)[0])
                       - float(np.polyfit(lt[half:], row[half:], 1)[0])) for row in le]
    et = energy * times ** (2.0 / 3.0)
    energy_out = {
        "times": times.tolist(), "e_t23": [_mean_se(et[:, j]) for j in range(nt)],
        "exponent": _mean_se(slopes), "per_seed": slopes, "drift": _mean_se(drift)[0],
        "fit_range": [float(times[0]), float(times[-1])], "expected": -2.0 / 3.0,
        "exact_limit": exact_moments()["velocity_variance"],
        "clusters": clusters.mean(axis=0).tolist(),
    }
    structure_out = _structure_numbers(kb, sb_sum / len(seeds), times, porod_seed, params)
    kurt_out = {"times": times.tolist(), "kurtosis": [_mean_se(kurt[:, j]) for j in range(nt)],
                "gaussian": 3.0}
    sk = {key: np.array(rows) for key, rows in skew.items()}
    skew_out = {"time": float(times[-1]), "scales": list(scales),
                **{key: [_mean_se(sk[key][:, q]) for q in range(len(scales))] for key in sk}}
    disp_out = {"time": float(times[-1]), "scale": scale, "variance": _mean_se(disp_var),
                "per_seed": disp_var, "chernoff_variance": CHERNOFF_VARIANCE}
    return {"summary": {"energy": energy_out, "structure": structure_out, "kurtosis": kurt_out,
                        "skewness": skew_out, "displacement": disp_out},
            "data": {"times": times, "e_t23": et, "kb": kb, "sb": sb_sum / len(seeds),
                     "window": window, "z_edges": z_edges,
                     "z_hist": disp_hist / (disp_hist.sum() * 0.1), "length": length, "n": n}}


def _cluster_window(state, count: int = 8) -> dict:
    """A window of ``count`` consecutive clusters from the middle of ``state`` (plus one on each
    side, for the gradients at the ends): their first labels, masses, positions (unwrapped, in
    the ring's order) and velocities, and the time."""
    k = state.starts.size
    lo = max(0, k // 2 - count // 2 - 1)
    hi = min(k, lo + count + 2)
    sel = slice(lo, hi)
    return {"starts": state.starts[sel].copy(), "masses": state.masses[sel].copy(),
            "positions": state.positions[sel].copy(),
            "velocities": state.cluster_velocities[sel].copy(), "time": float(state.time),
            "spacing": state.length / state.velocities.size}


def _exact_runs(params, progress) -> dict:
    """The runs of ``exact_n`` particles at ``exact_times`` against the exact laws, the tail
    exponent, and the secondary small-μ fit (:func:`run`)."""
    n, times = int(params["exact_n"]), [float(t) for t in params["exact_times"]]
    fit_times = [float(t) for t in params["fit_times"]]
    if not set(fit_times) <= set(times) or float(params["tail_time"]) not in times:
        raise InvalidArgumentError("fit_times", fit_times,
                                   f"times among exact_times {times} (tail_time too)")
    engine = get_model("sticky").build({"n": n, "density": 1.0, "initial": "gaussian"})
    grid = tail_grid(*params["tail_w"])
    mc = int(params["min_clusters"])
    cmps = [ExactLawComparison(t, tail_w=grid, min_clusters=mc) for t in times]
    tables, table_times = [], []
    seeds = range(1000, 1000 + int(params["exact_seeds"]))
    with progress_bar(len(seeds) * len(times), f"sticky exact laws N={n}", "time",
                      enabled=progress) as bar:
        for seed in seeds:
            s0 = engine.initial_state(np.random.default_rng(seed))
            for j, t in enumerate(times):
                state = engine.advance(s0, t)
                cmps[j].add(state)
                if t in fit_times:
                    tables.append(cluster_mass_distribution(state))
                    table_times.append(t)
                del state
                bar.update(1)
            del s0
    per_time, vel_data, mass_data, tails = [], [], [], []
    j_tail = times.index(float(params["tail_time"]))
    for c in cmps:
        vel, mass, corr = c.velocity(), c.mass(), c.corrections()
        tail = c.tail()
        z = (tail["beta"] - tail["beta_exact"]) / tail["beta_error"]
        per_time.append({
            "t": c.t, "clusters": int(round(np.sum(mass["observed"]))),
            "velocity": {"chi2": vel["chi2"], "dof": vel["dof"],
                         "chi2_dof": vel["chi2"] / vel["dof"]},
            "mass": {"chi2": mass["chi2"], "dof": mass["dof"],
                     "chi2_dof": mass["chi2"] / mass["dof"]},
            "energy": corr["energy"], "cluster_number": corr["clusters"],
            "tail": {"beta_w": tail["beta_w"].tolist(), "beta": tail["beta"].tolist(),
                     "beta_error": tail["beta_error"].tolist(),
                     "beta_exact": tail["beta_exact"].tolist(), "z": z.tolist(),
                     "deepest": tail["deepest"]},
        })
        vel_data.append({"density": vel["density"], "error": vel["density_error"]})
        mass_data.append({"mu": mass["mu"], "density": mass["density"],
                          "error": mass["density_error"], "exact": mass["exact"]})
        tails.append(tail)
    beta_law = exact_tail(params["beta_curve"])
    edges = cmps[0].w_edges
    w_fine = np.linspace(-4.0, 4.0, 49)
    mu_fine = np.geomspace(1e-3, 6.0, 80)
    small = _small_mass_fit(tables, table_times, engine.params.length, params)
    summary = {
        "exact": {
            "n": n, "seeds": len(seeds), "times": times, "per_time": per_time,
            "variance_models": "velocity: Σ m² over the clusters in a bin (clusters independent);"
                               " mass: Poisson (expected count); dof = bins, nothing fitted",
            "limits": exact_moments(),
        },
        "tail": {"time": times[j_tail], "grid": grid.tolist(), "min_clusters": mc,
                 "engine": per_time[j_tail]["tail"], "exact": beta_law["summary"],
                 "sticky_gas_limit": 3.0, "gaussian": 2.0},
        "mass": {"secondary_fit": small["summary"], "exponent": small["summary"]["exponent"],
                 "expected": -0.5},
    }
    data = {
        "exact_times": np.asarray(times), "w_edges": edges, "w_fine": w_fine,
        "p_fine": exact_velocity_density(w_fine), "mu_fine": mu_fine,
        "f_fine": exact_mass_density(mu_fine), "velocity_hist": vel_data, "mass_hist": mass_data,
        "tail_w": grid, "tail_survival": [t_["survival"] for t_ in tails],
        "tail_error": [t_["survival_error"] for t_ in tails],
        "tail_exact": [t_["exact_survival"] for t_ in tails],
        "beta_curve_w": beta_law["w"], "beta_curve": beta_law["beta"], **small["data"],
    }
    return {"summary": summary, "data": data}


def _small_mass_fit(tables, table_times, length, params) -> dict:
    """The secondary small-μ fit of the cluster-mass law: Φ pooled over the runs and the
    ``fit_times`` with Poisson errors (:func:`mass_density`), masses m ≥ ``fit_m_min``,
    fitted by :func:`small_mass_law` for μ ≤ ``fit_mu_max``, plus the pure power law's slope
    on three windows of μ, to show it steepen towards −1/2 as μ → 0.  (The whole curve is
    compared with the exact law in ``exact``; this fit only tests the exponent.)"""
    edges = 10.0 ** np.arange(-3.5, 0.51, 0.1)
    mu = np.sqrt(edges[:-1] * edges[1:])
    phi, err, counted = mass_density(tables, table_times, length, edges,
                                     int(params["fit_m_min"]), errors=True)
    fits = small_mass_law(mu, phi, err, counted, float(params["fit_mu_max"]))
    windows = {}
    for lo, hi in ((3e-3, 3e-2), (1e-2, 1e-1), (3e-2, 3e-1)):
        sub = small_mass_law(mu, phi, err, counted, hi, mu_min=lo, models=("power",))
        windows[f"{lo:g}-{hi:g}"] = None if sub["power"] is None else sub["power"]["a"]
    summary = {"n": int(params["exact_n"]), "seeds": int(params["exact_seeds"]),
               "times": sorted(set(table_times)), "m_min": int(params["fit_m_min"]),
               "mu_max": float(params["fit_mu_max"]), "fits": fits, "window_slopes": windows,
               "exponent": fits["corrected"]["a"] if fits["corrected"] else [None, None]}
    return {"summary": summary,
            "data": {"mass_mu": mu, "mass_phi": phi, "mass_err": err, "mass_counted": counted}}


def _structure_numbers(kb, sb_mean, times, porod_seed, params) -> dict:
    """Collapse spread and Porod slopes (see :func:`run`); ``sb_mean`` (T, bins) is the seed
    mean of the log-binned S(k) on the bin centres ``kb``."""
    x_range = (0.5, params["porod_x"][1])
    xs = np.geomspace(*x_range, 40)

    def spread(z):
        curves = [np.interp(np.log(xs), np.log(kb * t**z), np.log(sb))
                  for sb, t in zip(sb_mean, times, strict=True)]
        return float(np.sqrt(np.mean(np.var(np.array(curves), axis=0, ddof=1))))

    fits = [binned_porod_fit(kb, sb, t, 2.0 / 3.0, params["porod_x"], params["k_max"])
            for sb, t in zip(sb_mean, times, strict=True)]
    per_time = [_mean_se([row[j] for row in porod_seed]) for j in range(len(times))]
    last = max((j for j, f in enumerate(fits) if f is not None), default=None)
    return {
        "times": list(map(float, times)), "z": 2.0 / 3.0,
        "collapse_spread_at_z": spread(2.0 / 3.0), "collapse_spread_unscaled": spread(0.0),
        "porod_window": {"x": list(params["porod_x"]), "k_max": float(params["k_max"])},
        "porod_slope_per_time": per_time,
        "porod_fit_of_mean": [None if f is None else [f[0], f[1], float(f[2][0]),
                                                      float(f[2][-1])] for f in fits],
        "porod_slope_last_fitted_time": per_time[last] if last is not None else [None, None],
        "expected": -2.0,
    }


def _grid(ax):
    """Eight axes in two rows of four (a new figure), or the eight axes given."""
    if ax is None:
        from ...figures import new_figure

        fig, axes = new_figure(4, width=19.0 / 4, height=9.0 / 2, nrows=2)
        return fig, list(axes.ravel()), True
    axes = list(np.ravel(ax))
    if len(axes) != 8:
        raise InvalidArgumentError("ax", f"{len(axes)} axes", "8 axes (two rows of four)")
    return axes[0].figure, axes, False


def _shown_times(times) -> list[int]:
    """Indices of the first, a middle and the last time."""
    k = len(times)
    return sorted({0, k // 2, k - 1})


def _seed_dof(values) -> int | None:
    """seeds − 1 for a standard error over the runs ``values`` (None: fewer than 2, or none)."""
    n = 0 if values is None else len([v for v in values if v is not None])
    return n - 1 if n > 1 else None


def verdicts(s: dict) -> list:
    """The verdicts of comparison 9 from its summary ``s``.  Seed-based σ under the t law
    (Student's t with seeds − 1 dof at the coverage of 3σ: 19.2σ for 3 seeds, 9.22σ for 4):
    E ∝ t^{−2/3} (plus the window drift as a stated tolerance), the Porod tail and Chernoff's
    displacement variance.  σ from a law, 3σ: the cluster-mass exponent (a weighted fit with
    the counts' errors), the exact velocity law at the latest time (χ²/dof, 3√(2/dof)), and
    the exp(−w³) tail (the survival's counts): the local exponent at the deepest w against 3,
    explained when it equals the exact law's β(w) at that w."""
    e = s["energy"]
    seeds = int(s.get("parameters", {}).get("seeds", 0))  # 0: not recorded
    slope, err = pair(e["exponent"])
    out = [judge("late stage E ∝ t^(−2/3) (sticky gas)",
                 Check(f"slope of ln E against ln t on [{e['fit_range'][0]:g}, "
                       f"{e['fit_range'][1]:g}]", slope, err, e["expected"], "paper: t^(−2/3)",
                       tolerance=e.get("drift") or 0.0, dof=_seed_dof(e.get("per_seed")),
                       t_law=True,
                       sigma_source="seeds: standard error of the per-seed slopes, Student's "
                                    "t law; tolerance: the window drift (half the slopes' "
                                    "difference on its halves)"))]
    st = s["structure"]
    slope, err = pair(st["porod_slope_last_fitted_time"])
    out.append(judge("Porod's law S(k) ∼ k⁻² of the sticky gas",
                     Check("slope of log S(k), last fitted time", slope, err, st["expected"],
                           "paper: Porod's law", dof=_seed_dof(range(seeds)), t_law=True,
                           sigma_source="seeds: standard error of the per-seed fits, "
                                        "Student's t law")))
    tail = s["tail"]["engine"]
    if tail["beta"]:
        beta, beta_err = tail["beta"][-1], tail["beta_error"][-1]
        w = tail["beta_w"][-1]
        out.append(judge(
            "velocity tail ∝ exp(−v³) (Frachebourg, quoted by the paper)",
            Check(f"local exponent β of ln P(|w| > w) at w = {w:.3g}", beta, beta_err,
                  s["tail"]["sticky_gas_limit"], "paper: exp(−v³)"),
            Check(f"β at w = {w:.3g} against the exact law's β(w)", beta, beta_err,
                  tail["beta_exact"][-1], "exact: sticky-gas velocity law"),
            why="β(w) reaches 3 only as w → ∞ (exact law: 2 at w ≈ "
                f"{s['tail']['exact']['crossings'].get('2', {}).get('w', float('nan')):.3g})"))
    m, m_err = pair(s["mass"]["exponent"])
    out.append(judge("cluster masses: P(m) ∼ m^(−1/2) at small m/⟨m⟩ (exact sticky gas)",
                     Check("fitted exponent of the mass law", m, m_err, s["mass"]["expected"],
                           "exact: Frachebourg's mass law",
                           sigma_source="fit: weighted least squares, the counts' errors")))
    d = s["displacement"]
    var, var_err = pair(d["variance"])
    out.append(judge("displacements follow Chernoff's law (exact sticky gas)",
                     Check(f"variance of D/t^(2/3) at t = {d['time']:g}", var, var_err,
                           d["chernoff_variance"], "exact: Chernoff's distribution",
                           dof=_seed_dof(d.get("per_seed")), t_law=True,
                           sigma_source="seeds: standard error over the runs, Student's t "
                                        "law")))
    last = s["exact"]["per_time"][-1]
    vel = last["velocity"]
    out.append(judge("the sticky gas reaches its exact late-time velocity law",
                     Check(f"χ²/dof of the velocity law at t = {last['t']:g}", vel["chi2_dof"],
                           math.sqrt(2.0 / vel["dof"]), 1.0, "exact: χ² null expectation",
                           sigma_source="χ² law: √(2/dof) under the null")))
    return out


def plot(c, ax=None):
    """Two rows of four panels.  Top: the velocity law in w = v t^{1/3} and the cluster-mass
    law in μ = m/t^{2/3} at three times against the exact curves, the local tail exponent β(w)
    (exact, and the engine's chords at the first time and at ``tail_time``), and χ²/dof
    against t.  Bottom: E t^{2/3} against t with its exact limit, S(k) against k t^{2/3} with
    the Porod fit, a zoomed window of a few clusters (v(x) as ramps between clusters, v(i) as
    steps, the sign of each gradient marked), and the displacements against Chernoff's
    density.  Every panel is the sticky gas standing in for late MD."""
    d, s = c.data, c.summary
    fig, axes, own = _grid(ax)
    vel_ax, mass_ax, beta_ax, chi_ax, e_ax, sk_ax, zoom_ax, dz = axes
    ex = s["exact"]
    times = d["exact_times"]
    shown = _shown_times(times)
    cols = colors(len(shown))
    tag = f"sticky gas, N={ex['n']:.0e} × {ex['seeds']}"
    # velocity law
    edges = d["w_edges"]
    centres = 0.5 * (edges[:-1] + edges[1:])
    for col, j in zip(cols, shown, strict=True):
        h = d["velocity_hist"][j]
        ok = h["density"] > 0
        vel_ax.errorbar(centres[ok], h["density"][ok], yerr=h["error"][ok], fmt="o", ms=3,
                        color=col, capsize=0,
                        label=f"t = {times[j]:g}: χ²/dof = "
                              f"{ex['per_time'][j]['velocity']['chi2_dof']:.2f}")
    vel_ax.semilogy(d["w_fine"], d["p_fine"], "k-", lw=1, label="exact P(w)")
    var = ex["limits"]["velocity_variance"]
    vel_ax.semilogy(d["w_fine"], np.exp(-d["w_fine"] ** 2 / (2 * var)) / math.sqrt(2 * math.pi
                                                                                    * var),
                    "k:", lw=0.8, label="Gaussian, same variance")
    vel_ax.set(xlabel="w = v t^(1/3)", ylabel="P(w), particles", ylim=(1e-6, 1.5),
               title=f"velocity law against the exact one\n{tag}")
    vel_ax.legend(fontsize=7, loc="lower center")
    # mass law
    for col, j in zip(cols, shown, strict=True):
        h = d["mass_hist"][j]
        ok = h["density"] > 0
        mass_ax.errorbar(h["mu"][ok], h["density"][ok], yerr=h["error"][ok], fmt="o", ms=3,
                         color=col, capsize=0,
                         label=f"t = {times[j]:g}: χ²/dof = "
                               f"{ex['per_time'][j]['mass']['chi2_dof']:.2f}")
    mass_ax.loglog(d["mu_fine"], d["f_fine"], "k-", lw=1, label="exact F(μ)")
    mass_ax.loglog(d["mu_fine"], d["mu_fine"] ** -0.5 / math.sqrt(2 * math.pi), "k--", lw=0.7,
                   label="μ^(-1/2)/√(2π)")
    mx = s["mass"]["exponent"]
    mass_ax.set(xlabel="μ = m / t^(2/3)", ylabel="F(μ) = t^(4/3) clusters(m)/N",
                ylim=(1e-5, 30),
                title=f"cluster-mass law against the exact one\n(secondary fit: a = "
                      f"{mx[0]:.3f} ± {mx[1] or 0:.3f}, expected −1/2)")
    mass_ax.legend(fontsize=7, loc="lower left")
    # tail exponent
    tail = s["tail"]
    beta_ax.semilogx(d["beta_curve_w"], d["beta_curve"], "k-", lw=1, label="exact β(w)")
    j_tail = int(np.flatnonzero(times == tail["time"])[0])
    for j, style in ((0, "C1s"), (j_tail, "C3o")):
        e = ex["per_time"][j]["tail"]
        b = np.asarray(e["beta"], float)
        ok = np.isfinite(b)
        beta_ax.errorbar(np.asarray(e["beta_w"])[ok], b[ok],
                         yerr=np.asarray(e["beta_error"])[ok], fmt=style, ms=4, capsize=2,
                         label=f"engine, t = {times[j]:g}")
    deep = {**tail["engine"]["deepest"], "t": tail["time"]}
    if "deep_tail" in s:  # the large ensemble: its chords per time, and its deepest survival
        dt = s["deep_tail"]
        for row, color in zip(dt["per_time"], ("C2", "C4", "C5", "C6"), strict=False):
            b = np.asarray(row["beta"], float)
            ok = np.isfinite(b)
            beta_ax.errorbar(np.asarray(row["beta_w"])[ok], b[ok],
                             yerr=np.asarray(row["beta_error"])[ok], fmt="^", color=color,
                             ms=3, capsize=1.5, lw=0.8,
                             label=f"{dt['particles']:.1e} particles, t = {row['t']:g}")
        deep = min([{**row["deepest"], "t": row["t"]} for row in dt["per_time"]] + [deep],
                   key=lambda r: r["survival"])
    beta_ax.axhline(3.0, color="k", ls="--", lw=0.8, label="limit 3")
    beta_ax.axhline(2.0, color="k", ls=":", lw=0.8, label="Gaussian 2")
    lines = []
    for key, cross in tail["exact"]["crossings"].items():
        if cross is not None:
            beta_ax.plot([cross["w"]], [float(key)], "kx")
            lines.append(f"β = {key} at w = {cross['w']:.2f} (P = {cross['survival']:.0e})")
    beta_ax.set(xlabel="w", ylabel="β = d ln(−ln P(|w|>w)) / d ln w", ylim=(1.0, 3.2),
                title=f"velocity tail: deepest resolved P = {deep['survival']:.0e} "
                      f"at w = {deep['w']:.2f}, t = {deep['t']:g}\n" + "; ".join(lines))
    beta_ax.title.set_fontsize(8)
    beta_ax.legend(fontsize=6 if "deep_tail" in s else 7, loc="lower right")
    # chi2 against t
    for key, style in (("velocity", "C0o-"), ("mass", "C3s-")):
        vals = [row[key]["chi2_dof"] for row in ex["per_time"]]
        chi_ax.loglog(times, vals, style, ms=4, label=f"{key} law")
    chi_ax.axhline(1.0, color="k", ls=":", lw=0.8)
    chi_ax.set(xlabel="t", ylabel="χ²/dof against the exact law",
               title=f"corrections to scaling shrink with t\n{tag}")
    chi_ax.legend(fontsize=7)
    # energy
    et = d["e_t23"]
    e_ax.errorbar(d["times"], et.mean(axis=0),
                  yerr=mean_sem(et, axis=0)[1] if et.shape[0] > 1 else None,
                  fmt="o-", ms=3, capsize=2, label=f"N={d['n']:.0e}")
    ev = np.array([row["energy"]["value"][0] for row in ex["per_time"]])
    ee = np.array([row["energy"]["value"][1] or 0.0 for row in ex["per_time"]])
    e_ax.errorbar(times, ev, yerr=ee, fmt="s", ms=3, capsize=2, label=f"N={ex['n']:.0e}")
    e_ax.axhline(var, color="k", ls="--", lw=0.8, label=f"exact limit {var:.4f}")
    z = s["energy"]["exponent"]
    e_ax.set(xscale="log", xlabel="t", ylabel="E t^(2/3)",
             title=f"E ~ t^z, z = {z[0]:.4f} ± {z[1] or 0:.4f}")
    e_ax.legend(fontsize=7)
    # structure factor
    mt = d["times"]
    kcols = colors(len(mt))
    for j, t in enumerate(mt):
        sk_ax.loglog(d["kb"] * t ** (2 / 3), d["sb"][j], "-", lw=0.8, color=kcols[j],
                     label=f"t = {t:g}" if j in (0, len(mt) - 1) else None)
    st_ = s["structure"]
    fits = st_["porod_fit_of_mean"]
    jl = max((j for j, f in enumerate(fits) if f is not None), default=None)
    if jl is not None:
        slope, icpt, k0, k1 = fits[jl]
        kl = np.array([k0, k1])
        t = mt[jl]
        sk_ax.loglog(kl * t ** (2 / 3), np.exp(icpt) * kl**slope, "r-", lw=2.5,
                     label=f"fit t={t:g}: slope {slope:.2f}")
        sk_ax.loglog(kl * t ** (2 / 3), 0.3 * np.exp(icpt) * kl[0] ** (slope + 2) * kl**-2.0,
                     "k:", label="k⁻²")
    sk_ax.axvspan(*st_["porod_window"]["x"], color="0.9", zorder=0)
    sk_ax.set(xlabel="k t^(2/3)", ylabel="S(k) of v(i)",
              title=f"S(k): spread {st_['collapse_spread_at_z']:.2f} "
                    f"(unscaled {st_['collapse_spread_unscaled']:.2f})")
    sk_ax.legend(fontsize=6, loc="lower left")
    _draw_window(zoom_ax, d["window"], s["skewness"])
    # displacements
    ze = d["z_edges"]
    zc = 0.5 * (ze[:-1] + ze[1:])
    dz.semilogy(zc, np.where(d["z_hist"] > 0, d["z_hist"], np.nan), "C0.", ms=4,
                label=f"sticky gas, t = {mt[-1]:g}")
    fine = np.linspace(ze[0], ze[-1], 301)
    dz.semilogy(fine, chernoff_density(fine), "k-", lw=0.8, label="Chernoff (exact limit)")
    dv = s["displacement"]["variance"]
    dz.set(xlabel="z = D / (2^(2/3) t^(2/3))", ylabel="P(z)", ylim=(1e-4, 1.5),
           title=f"displacements: ⟨z²⟩ = {dv[0]:.4f} ± {dv[1] or 0:.4f}\n"
                 f"(exact {CHERNOFF_VARIANCE:.5f})")
    dz.legend(fontsize=7)
    if own:
        fig.suptitle("Comparison 9: the late stage, exact sticky gas standing in for late MD",
                     fontsize=11)
        fig.tight_layout()
    return fig


def _draw_window(ax, win, skew) -> None:
    """A few clusters of seed 0 at the last time: v(x) (top) as the particles' velocities
    interpolated linearly between the clusters (the convention of the skewness), its segments
    coloured by the sign of their gradient; v(i) (bottom, shifted down) as steps over the
    clusters' labels, its jumps marked by their sign.  The horizontal axis is x − x₀ for v(x)
    and (i − i₀) L/N for v(i)."""
    if not win:
        return
    x = win["positions"] - win["positions"][0]
    v = win["velocities"]
    starts = (win["starts"] - win["starts"][0]) * win["spacing"]
    ends = starts + win["masses"] * win["spacing"]
    shift = 2.5 * float(np.ptp(v)) if v.size > 1 else 1.0
    for a in range(x.size - 1):
        rising = v[a + 1] >= v[a]
        col = "C0" if rising else "C3"
        ax.plot(x[a:a + 2], v[a:a + 2], "-", color=col, lw=1.2)
        ax.annotate("+" if rising else "−", (0.5 * (x[a] + x[a + 1]), 0.5 * (v[a] + v[a + 1])),
                    textcoords="offset points", xytext=(0, 6), ha="center", color=col,
                    fontsize=9, fontweight="bold")
    size = 12.0 * np.sqrt(win["masses"] / win["masses"].max())
    ax.scatter(x, v, s=size**2, facecolors="none", edgecolors="k", lw=0.6, zorder=3,
               label="cluster (area ∝ mass)")
    ax.plot([], [], "-", color="C0", label="gradient > 0 (+)")
    ax.plot([], [], "-", color="C3", label="gradient < 0 (−)")
    ax.plot([], [], "-", color="C2", label="v(i): one step per cluster")
    for a in range(x.size):
        ax.plot([starts[a], ends[a]], [v[a] - shift] * 2, "-", color="C2", lw=1.5)
        if a + 1 < x.size:
            up = v[a + 1] >= v[a]
            ax.plot([ends[a], ends[a]], [v[a] - shift, v[a + 1] - shift], "-",
                    color="C0" if up else "C3", lw=1.5)
            ax.annotate("+" if up else "−", (ends[a], 0.5 * (v[a] + v[a + 1]) - shift),
                        textcoords="offset points", xytext=(5, 0), va="center",
                        color="C0" if up else "C3", fontsize=9, fontweight="bold")
    q = min(1, len(skew["scales"]) - 1)
    ax.set(xlabel="x − x₀ (v(x), top); (i − i₀) L/N (v(i), bottom)",
           ylabel=f"v(x) and v(i) − {shift:.2f}",
           title=f"{x.size} clusters at t = {win['time']:g}: v(x) ramps (+) and drops (−),\n"
                 f"v(i) steps; skewness (m={skew['scales'][q]}): v(x) {skew['vx'][q][0]:+.2f}, "
                 f"v(i) {skew['vi'][q][0]:+.2f}")
    ax.title.set_fontsize(8)
    ax.legend(fontsize=6, loc="center right")


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=9))
