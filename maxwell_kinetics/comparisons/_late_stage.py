"""Comparison 9: the paper's late-stage figures at the paper's sizes, with the exact sticky gas
(:mod:`particles.sticky`) standing in for late MD — rescaled P(x), E ~ t^{−2/3}, the
cluster-mass law m^{−1/2}, S(k) against k t^{2/3} with its Porod tail, the shocks of v(x) and
v(i), and the velocity tail.  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.models import get_model
from particles.observables import mean_sem, mean_sem_json, structure_factor
from particles.progress import progress_bar
from particles.sticky import (
    CHERNOFF_VARIANCE,
    chernoff_density,
    cluster_mass_distribution,
    displacement_scale,
    displacements,
    profile_x,
    velocity_tail_exponent,
)

from .analysis import (
    binned_porod_fit,
    block_means,
    coarse_increment_skewness,
    log_binned,
    porod_fit,
    profile_scales,
    velocity_on_grid,
)
from .base import Comparison, jsonable, preset, register_plot
from .drawing import colors, panels

__all__ = ["NAME", "PRESETS", "run", "plot", "mass_density"]

NAME = "late_stage"


def _times(lo, hi, count):
    return tuple(float(t) for t in np.round(np.geomspace(lo, hi, count), 3))


#: ``times`` (t, density 1) span two decades or more; ``mass_t_min``: the cluster-mass law is
#: fitted on the times t ≥ it (typical mass (n t)^{2/3} ≥ 20, so that 1 ≪ m ≪ (n t)^{2/3} has
#: room); ``tail_time``: where the velocity tail is measured (early in the late stage: most
#: clusters, so the deepest tail); ``tail_quantiles``: the upper-tail fractions of the global
#: tail fit (the lowest holds ≥ 10 particles' worth of clusters at ``tail_time``).
#: ``mass_n``, ``mass_seeds``, ``mass_times``: separate, later runs for the small-μ mass law
#: (typical masses 460–2150, so that m ≥ ``mass_small_m_min`` = 10 still reaches μ ~ 0.005;
#: the sticky gas costs the same at any t), fitted for μ ≤ ``mass_mu_max``.
_SHARED = {"mass_t_min": 90.0, "mass_mu": (0.03, 0.3), "mass_m_min": 2,
           "mass_times": (1e4, 3e4, 1e5), "mass_small_m_min": 10, "mass_mu_max": 0.3,
           "porod_x": (3.0, 15.0), "k_max": 0.6, "tail_time": 10.0}
PRESETS = {
    "small": {**_SHARED, "n": 100_000, "seeds": 3, "times": _times(10.0, 1000.0, 9),
              "mass_n": 4_000_000, "mass_seeds": 4,
              "tail_quantiles": (1e-2, 1e-4), "x_edges": (-5.0, 5.0, 0.2)},
    "default": {**_SHARED, "n": 1_000_000, "seeds": 4, "times": _times(10.0, 2000.0, 11),
                "mass_n": 10_000_000, "mass_seeds": 8,
                "tail_quantiles": (1e-2, 1e-5), "x_edges": (-5.0, 5.0, 0.1)},
    "full": {**_SHARED, "n": 10_000_000, "seeds": 4, "times": _times(10.0, 5000.0, 13),
             "mass_n": 10_000_000, "mass_seeds": 32,
             "tail_quantiles": (1e-2, 1e-6), "x_edges": (-5.0, 5.0, 0.1)},
}


def mass_density(masses_counts, times, length, mu_edges, m_min=1, *, errors=False):
    """Scaled cluster-mass density Φ(μ) = M² n(m, t) with μ = m/M, M = t^{2/3} (density 1),
    pooled over ``times``: ``masses_counts`` is a list (one per time) of ``(m, count)`` from
    :func:`particles.sticky.cluster_mass_distribution`, n(m, t) = count(m)/L the number of
    clusters of mass m per unit length.  In each bin [a, b) of ``mu_edges``, with C_t the
    clusters and k_t the integers m ≥ ``m_min`` with a M ≤ m < b M at time t,
    Φ = Σ_t M² C_t / (L Σ_t k_t) (bins with no integer are NaN).  Σ_m m n(m) = n = 1 makes
    ∫ μ Φ dμ time-independent in the scaling state; the sticky gas has Φ ~ μ^{−1/2} at small μ.

    With ``errors=True`` it returns ``(Φ, σ, clusters)``: σ is the standard error of Φ with the
    cluster counts taken as independent Poisson numbers (var Σ_t M² C_t / L = Σ_t M⁴ C_t / L²),
    and ``clusters`` the number of clusters counted per bin.  Several runs (seeds) are pooled
    by passing one table per run and time."""
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
    exclude; on those data 22.5, 15.9, 33.3 for 16 degrees of freedom."""
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


def _line_fit(x, y):
    """Least-squares slope of ln y on ln x over the finite positive points (None below 3)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(y) & (y > 0)
    if ok.sum() < 3:
        return None
    return float(np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)[0])


def _mean_se(values):
    return mean_sem_json([x for x in values if x is not None])


def run(size=None, progress: bool = True, runner=None, **overrides) -> Comparison:
    """Comparison 9: the late stage at the paper's sizes (N = 10⁵ small, 10⁶ default, 10⁷
    full), with the exact sticky gas standing in for late MD (from the same initial
    state MD at r = 0.5, δ = 10⁻⁴ and the sticky gas agree within a few per cent, comparison 8).
    Gaussian initial velocities of unit variance, uniform positions, density 1, one run per
    seed; every number is mean ± standard error over the seeds (each run's own fit):

    * ``energy``: E t^{2/3} per time, and the exponent of E ~ t^{z}: slope of ln E on ln t over
      all ``times`` (two decades or more), with the window ``drift`` (half the difference of the
      slopes on the two halves) reported beside it;
    * ``mass``: the scaled cluster-mass density Φ(μ) = M² n(m, t), μ = m/M, M = t^{2/3}
      (:func:`mass_density`, 10 log bins per decade).  ``window_exponent``: the slope of a
      pure power law per seed over μ ∈ ``mass_mu``, pooled over times t ≥ ``mass_t_min``,
      m ≥ ``mass_m_min`` (measured at N = 10⁶, 4 seeds: −0.431 ± 0.008: not asymptotic).
      ``small_mu`` and ``exponent``: the separate late runs of :func:`_small_mass_runs`, fitted
      by :func:`small_mass_law` (expected −1/2 with corrections to scaling);
    * ``structure``: S(k) of v(i) in label order (:func:`particles.observables.structure_factor`,
      as for MD) against k t^{2/3}; the collapse spread (rms over x ∈ [0.5, porod_x[1]] of the
      std over times of ln S) at z = 2/3 and unscaled; Porod slope of ln S on ln k over
      x ∈ ``porod_x``, k ≤ ``k_max`` (:func:`.analysis.porod_fit`) per time (expected −2);
    * ``kurtosis``: ⟨x⁴⟩ of x = v/√E per time (Gaussian 3; Fig. 1b: late P(x) is
      Gaussian-like), the histograms at the first and last time in the figure;
    * ``skewness``: the sign of the large gradients of v(i) and of v(x) (particles' velocities
      interpolated on a grid of spacing L/N, :func:`.analysis.velocity_on_grid`) at the last
      time, raw and coarse-grained over m = 1, 4, 16, … ≤ N/64
      (:func:`.analysis.coarse_increment_skewness`; paper Fig. 4: v(x) negative, v(i)
      positive);
    * ``tail``: the local exponent β of P(|v| > w) ~ exp(−c w^β) at ``tail_time``
      (:func:`particles.sticky.velocity_tail_exponent`) over ``tail_quantiles`` and per decade
      of quantile; the sticky gas tends to β = 3 (Frachebourg 1999) only for N far beyond
      these sizes (1.2–1.7 at ~10⁴ clusters);
    * ``displacement``: each particle's displacement D since t = 0 at the last time, as
      z = D / (b t^{2/3}) (:func:`particles.sticky.displacement_scale`): ⟨z²⟩ per seed against
      Var Z = 0.26356 of Chernoff's law, the exact large-t limit, and the histogram of z
      against Chernoff's density in the figure.
    """
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    n, times = int(params["n"]), np.asarray(params["times"], dtype=float)
    seeds = tuple(range(int(params["seeds"])))
    engine = get_model("sticky").build({"n": n, "density": 1.0, "initial": "gaussian"})
    length = engine.params.length
    lo, hi, step = params["x_edges"]
    edges = np.round(np.arange(lo, hi + 0.5 * step, step), 12)
    nt = times.size
    energy = np.empty((len(seeds), nt))
    kurt = np.empty_like(energy)
    clusters = np.empty_like(energy)
    sb_sum = None  # log-binned S(k) summed over seeds, per time (binning is linear)
    j_tail = int(np.argmin(np.abs(times - params["tail_time"])))
    porod_seed = [[None] * nt for _ in seeds]
    hist = np.zeros((2, edges.size - 1))
    mass_tables = [[] for _ in seeds]
    mu_edges = 10.0 ** np.arange(-2.0, 1.01, 0.1)
    mass_times = times[times >= params["mass_t_min"]]
    scales = profile_scales(n)
    skew = {"vi": [], "vx": []}
    tail_rows, profile = [], {}
    scale = displacement_scale(1.0, 1.0)  # D / t^{2/3} → scale · Z (density 1, unit variance)
    z_edges = np.round(np.arange(-3.0, 3.0 + 1e-9, 0.1), 12)
    disp_hist = np.zeros(z_edges.size - 1)
    disp_var = []
    decades = np.geomspace(params["tail_quantiles"][0], params["tail_quantiles"][1],
                           round(math.log10(params["tail_quantiles"][0]
                                            / params["tail_quantiles"][1])) + 1)
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
                if j in (0, nt - 1):
                    hist[0 if j == 0 else 1] += np.histogram(v / math.sqrt(e), edges)[0]
                if t >= params["mass_t_min"]:
                    mass_tables[i].append(cluster_mass_distribution(st))
                if j == j_tail:
                    beta = velocity_tail_exponent(v, quantiles=tuple(params["tail_quantiles"]))
                    local = [velocity_tail_exponent(v, quantiles=(a, b))
                             for a, b in zip(decades[:-1], decades[1:], strict=True)]
                    tail_rows.append((beta, local, float(t)))
                if j == nt - 1:
                    z = displacements(st) / (scale * float(t) ** (2.0 / 3.0))
                    disp_var.append(float(np.mean(z * z)))
                    disp_hist += np.histogram(z, z_edges)[0]
                    y, vv = profile_x(st)
                    vx = velocity_on_grid(y, vv, length)
                    skew["vi"].append([coarse_increment_skewness(v, m) for m in scales])
                    skew["vx"].append([coarse_increment_skewness(vx, m) for m in scales])
                    if i == 0:
                        show = min(5000, n)
                        profile = {"vi": np.array(v[:show]), "vx": vx[:show],
                                   "means_vi": block_means(v[:show], 64),
                                   "means_vx": block_means(vx[:show], 64)}
                bar.update(1)
    # energy
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
        "clusters": clusters.mean(axis=0).tolist(),
    }
    # cluster masses
    mu_mid = np.sqrt(mu_edges[:-1] * mu_edges[1:])
    phi = np.array([mass_density(tab, mass_times, length, mu_edges, params["mass_m_min"])
                    for tab in mass_tables])
    win = (mu_mid >= params["mass_mu"][0]) & (mu_mid <= params["mass_mu"][1])
    mslopes = [_line_fit(mu_mid[win], row[win]) for row in phi]
    small = _small_mass_runs(params, progress)
    mass_out = {"window_exponent": _mean_se(mslopes), "per_seed": mslopes, "expected": -0.5,
                "mu_window": list(params["mass_mu"]), "times": mass_times.tolist(),
                "m_min": int(params["mass_m_min"]), "small_mu": small["summary"],
                "exponent": small["summary"]["exponent"]}
    # structure factor
    sb_mean = sb_sum / len(seeds)
    structure_out = _structure_numbers(kb, sb_mean, times, porod_seed, params)
    # kurtosis, skewness, tail
    kurt_out = {"times": times.tolist(), "kurtosis": [_mean_se(kurt[:, j]) for j in range(nt)],
                "gaussian": 3.0}
    sk = {key: np.array(rows) for key, rows in skew.items()}
    skew_out = {"time": float(times[-1]), "scales": list(scales),
                **{key: [_mean_se(sk[key][:, q]) for q in range(len(scales))] for key in sk}}
    betas = [b[0][0] for b in tail_rows]
    local = np.array([[x[0] for x in b[1]] for b in tail_rows])
    w_local = [float(np.sqrt(x[2][0] * x[2][1])) for x in tail_rows[0][1]]
    tail_out = {"time": tail_rows[0][2], "quantiles": list(params["tail_quantiles"]),
                "beta": _mean_se(betas), "per_seed": betas,
                "fit_error_seed0": tail_rows[0][0][1],
                "w_range_seed0": list(tail_rows[0][0][2]),
                "local": {"quantiles": [[float(a), float(b)] for a, b in
                                        zip(decades[:-1], decades[1:], strict=True)],
                          "w": w_local,
                          "beta": [_mean_se(local[:, q]) for q in range(local.shape[1])]},
                "sticky_gas_limit": 3.0, "gaussian": 2.0}
    disp_out = {"time": float(times[-1]), "scale": scale, "variance": _mean_se(disp_var),
                "per_seed": disp_var, "chernoff_variance": CHERNOFF_VARIANCE}
    summary = {"parameters": jsonable(params), "model": "exact sticky gas standing in for late MD",
               "energy": energy_out, "mass": mass_out, "structure": structure_out,
               "kurtosis": kurt_out, "skewness": skew_out, "tail": tail_out,
               "displacement": disp_out,
               "seconds": time.perf_counter() - start}
    data = {"times": times, "e_t23": et, "mu": mu_mid, "phi": phi, **small["data"],
            "kb": kb, "sb": sb_mean, "x_edges": edges,
            "hist": hist / (hist.sum(axis=1, keepdims=True) * step), "profile": profile,
            "z_edges": z_edges, "z_hist": disp_hist / (disp_hist.sum() * 0.1),
            "length": length, "n": n}
    return Comparison(NAME, summary, data)


def _small_mass_runs(params, progress) -> dict:
    """The small-μ cluster-mass law from separate late runs (``mass_n`` particles,
    ``mass_seeds`` seeds 1000, 1001, …, times ``mass_times``, density 1): Φ pooled over runs
    and times with Poisson errors (:func:`mass_density`), masses m ≥ ``mass_small_m_min``,
    fitted by :func:`small_mass_law` for μ ≤ ``mass_mu_max``, plus the pure power law's slope
    on three windows of μ, to show it steepen towards −1/2 as μ → 0."""
    n, times = int(params["mass_n"]), [float(t) for t in params["mass_times"]]
    engine = get_model("sticky").build({"n": n, "density": 1.0, "initial": "gaussian"})
    tables, table_times = [], []
    with progress_bar(int(params["mass_seeds"]) * len(times), f"sticky masses N={n}", "time",
                      enabled=progress) as bar:
        for seed in range(1000, 1000 + int(params["mass_seeds"])):
            state = engine.initial_state(np.random.default_rng(seed))
            for t in times:
                tables.append(cluster_mass_distribution(engine.advance(state, t)))
                table_times.append(t)
                bar.update(1)
    edges = 10.0 ** np.arange(-3.5, 0.51, 0.1)
    mu = np.sqrt(edges[:-1] * edges[1:])
    phi, err, counted = mass_density(tables, table_times, engine.params.length, edges,
                                     int(params["mass_small_m_min"]), errors=True)
    fits = small_mass_law(mu, phi, err, counted, float(params["mass_mu_max"]))
    windows = {}
    for lo, hi in ((3e-3, 3e-2), (1e-2, 1e-1), (3e-2, 3e-1)):
        sub = small_mass_law(mu, phi, err, counted, hi, mu_min=lo, models=("power",))
        windows[f"{lo:g}-{hi:g}"] = None if sub["power"] is None else sub["power"]["a"]
    summary = {"n": n, "seeds": int(params["mass_seeds"]), "times": times,
               "m_min": int(params["mass_small_m_min"]), "mu_max": float(params["mass_mu_max"]),
               "fits": fits, "window_slopes": windows,
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


def plot(c, ax=None):
    """Seven panels: rescaled P(x) (first and last time, Gaussian), E t^{2/3} against t, the
    scaled cluster-mass density with its fits, S(k) against k t^{2/3} with the Porod fit and
    k⁻², the profiles v(i) and v(x) of seed 0 at the last time (first 5000 points), the
    skewness of their coarse-grained increments, the local tail exponent, and the displacements
    against Chernoff's density.  Every title says that this is the sticky gas standing in for
    late MD."""
    d, s = c.data, c.summary
    own = ax is None
    fig, axes = panels(7, ax, width=4.0, height=4.0)
    a, b, m_ax, sk_ax, pr, tl, dz = axes
    n = d["n"]
    tag = f"sticky gas for late MD, N={n:.0e}"
    centres = 0.5 * (d["x_edges"][:-1] + d["x_edges"][1:])
    times = d["times"]
    for row, t, style in ((0, times[0], "C0."), (1, times[-1], "C3-")):
        a.semilogy(centres, np.where(d["hist"][row] > 0, d["hist"][row], np.nan), style,
                   ms=3, label=f"t = {t:g}")
    a.semilogy(centres, np.exp(-centres**2 / 2) / math.sqrt(2 * math.pi), "k:", label="Gaussian")
    kur = s["kurtosis"]["kurtosis"][-1][0]
    a.set(xlabel="x = v/√E", ylabel="P(x)", ylim=(1e-6, 1),
          title=f"Fig. 1b-like: {tag}\nkurtosis at t={times[-1]:g}: {kur:.2f} (Gaussian 3)")
    a.legend(fontsize=7)
    et = d["e_t23"]
    b.errorbar(times, et.mean(axis=0),
               yerr=mean_sem(et, axis=0)[1] if et.shape[0] > 1 else None,
               fmt="o-", ms=3, capsize=2)
    ex = s["energy"]["exponent"]
    b.set(xscale="log", xlabel="t", ylabel="E t^(2/3)",
          title=f"E ~ t^z, z = {ex[0]:.4f} ± {ex[1] or 0:.4f}\n{tag}")
    mu, phi = d["mu"], d["phi"]
    finite = np.isfinite(phi).all(axis=0)
    ph = np.full(mu.size, np.nan)
    ph[finite] = phi[:, finite].mean(axis=0)
    m_ax.loglog(mu, ph, "o", ms=3, mfc="none", label=f"t ≤ {times[-1]:g}, N={n:.0e}")
    sm = s["mass"]["small_mu"]
    mm, mp, me = d["mass_mu"], d["mass_phi"], d["mass_err"]
    shown = np.isfinite(mp) & (d["mass_counted"] >= 50)
    m_ax.errorbar(mm[shown], mp[shown], yerr=me[shown], fmt="C3.", ms=3, capsize=0,
                  label=f"t = {sm['times'][0]:g}…{sm['times'][-1]:g}, N={sm['n']:.0e}, "
                        f"m ≥ {sm['m_min']}")
    fit = sm["fits"]["corrected"]
    if fit is not None:
        grid = np.geomspace(*sm["fits"]["mu_range"], 60)
        m_ax.loglog(grid, MASS_MODELS["corrected"][0](grid, *fit["parameters"]), "k-", lw=0.8,
                    label="A μ^a + B + C μ^(1/2)")
        a0, amp = -0.5, fit["parameters"][1]
        m_ax.loglog(grid, amp * grid**a0, "k--", lw=0.8, label="A μ^(-1/2)")
    mx = s["mass"]["exponent"]
    m_ax.set(xlabel="μ = m / t^(2/3)", ylabel="t^(4/3) n(m, t)",
             title=f"cluster masses: a = {mx[0]:.3f} ± {mx[1] or 0:.3f} (expected −1/2)\n{tag}")
    m_ax.legend(fontsize=7)
    cols = colors(len(times))
    for j, t in enumerate(times):
        sk_ax.loglog(d["kb"] * t ** (2 / 3), d["sb"][j], "-", lw=0.8, color=cols[j],
                     label=f"t = {t:g}" if j in (0, len(times) - 1) else None)
    st_ = s["structure"]
    fits = st_["porod_fit_of_mean"]
    jl = max((j for j, f in enumerate(fits) if f is not None), default=None)
    if jl is not None:
        slope, icpt, k0, k1 = fits[jl]
        kl = np.array([k0, k1])
        t = times[jl]
        sk_ax.loglog(kl * t ** (2 / 3), np.exp(icpt) * kl**slope, "r-", lw=2.5,
                     label=f"fit t={t:g}: slope {slope:.2f}")
        sk_ax.loglog(kl * t ** (2 / 3), 0.3 * np.exp(icpt) * kl[0] ** (slope + 2) * kl**-2.0,
                     "k:", label="k⁻²")
    sk_ax.axvspan(*st_["porod_window"]["x"], color="0.9", zorder=0)
    sk_ax.set(xlabel="k t^(2/3)", ylabel="S(k)",
              title=f"S(k) of v(i): spread {st_['collapse_spread_at_z']:.2f} "
              f"(unscaled {st_['collapse_spread_unscaled']:.2f})\n{tag}")
    sk_ax.legend(fontsize=6, loc="lower left")
    p = d["profile"]
    if p:
        xs = np.arange(p["vi"].size)
        pr.plot(xs, p["vi"], "-", lw=0.4, color="C2", alpha=0.7, label="v(i) (label)")
        pr.plot(xs, p["vx"] + 3 * np.std(p["vi"]), "-", lw=0.4, color="C0", alpha=0.7,
                label="v(x) (grid L/N), shifted")
        sk = s["skewness"]
        q = min(2, len(sk["scales"]) - 1)  # coarse-grained over 16 points where possible
        pr.set(xlabel="label i / grid point", ylabel="v",
               title=f"Fig. 4-like, t={sk['time']:g}: skewness (m={sk['scales'][q]}) "
               f"v(i) {sk['vi'][q][0]:+.2f}, v(x) {sk['vx'][q][0]:+.2f}\n{tag}")
        pr.legend(fontsize=7, loc="lower right")
    tail = s["tail"]
    wl = np.asarray(tail["local"]["w"])
    bl = np.array([np.nan if v is None else v for v, _ in tail["local"]["beta"]])
    el = np.array([0.0 if e is None else e for _, e in tail["local"]["beta"]])
    tl.errorbar(wl, bl, yerr=el, fmt="o-", capsize=2, label="local exponent")
    tl.axhline(3.0, color="k", ls="--", lw=0.8, label="sticky gas limit 3")
    tl.axhline(2.0, color="k", ls=":", lw=0.8, label="Gaussian 2")
    bt = tail["beta"]
    tl.set(xlabel="w = |v|/√E", ylabel="β: P(|v|>w) ~ exp(-c w^β)",
           title=f"velocity tail at t={tail['time']:g}: β = {bt[0]:.2f} ± {bt[1] or 0:.2f}\n{tag}")
    tl.legend(fontsize=7)
    ze = d["z_edges"]
    zc = 0.5 * (ze[:-1] + ze[1:])
    dz.semilogy(zc, np.where(d["z_hist"] > 0, d["z_hist"], np.nan), "C0.", ms=4,
                label=f"sticky gas, t = {times[-1]:g}")
    fine = np.linspace(ze[0], ze[-1], 301)
    dz.semilogy(fine, chernoff_density(fine), "k-", lw=0.8, label="Chernoff (exact limit)")
    dv = s["displacement"]["variance"]
    dz.set(xlabel="z = D / (2^(2/3) t^(2/3))", ylabel="P(z)", ylim=(1e-4, 1.5),
           title=f"displacements: ⟨z²⟩ = {dv[0]:.4f} ± {dv[1] or 0:.4f}\n"
                 f"(exact {CHERNOFF_VARIANCE:.5f}), {tag}")
    dz.legend(fontsize=7)
    if own:
        fig.tight_layout()
    return fig


register_plot(NAME, plot)
