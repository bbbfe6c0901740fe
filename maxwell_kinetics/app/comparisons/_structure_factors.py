"""Comparison 6 (paper Fig. 3): S(k) of the lattice (with and without the kinematic constraint)
and of MD against scaled k, with the Porod tail.  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import time

import numpy as np

from particles.md.observables import haff_time
from particles.observables import log_bin, mean_sem_json, structure_factor

from .analysis import jackknife, log_binned, porod_fit, porod_slope
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import colors, panels
from .particle_runs import ParticleRuns, md_record_times
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts", "z_drift"]

NAME = "structure_factors"

PRESETS = {
    "small": {"restitution": 0.5, "lattice_n": 20_000,
              "lattice_tau": (25.0, 50.0, 100.0, 200.0, 2000.0), "lattice_seeds": 4,
              "porod_x": (3.0, 15.0), "k_max": 0.6, "lattice_porod_x": (8.0, 30.0),
              "lattice_k_max": 0.5,
              "md_n": 1000, "md_t_max": 40.0, "md_seeds": 3, "md_delta": 1e-4,
              "md_times": (10.0, 20.0, 40.0)},
    "default": {"restitution": 0.5, "lattice_n": 100_000,
                "lattice_tau": (50.0, 100.0, 200.0, 400.0, 800.0, 2000.0), "lattice_seeds": 4,
                "porod_x": (3.0, 15.0), "k_max": 0.6, "lattice_porod_x": (8.0, 30.0),
                "lattice_k_max": 0.5, "md_n": 2000, "md_t_max": 100.0,
                "md_seeds": 3, "md_delta": 1e-4, "md_times": (25.0, 50.0, 100.0)},
    "full": {"restitution": 0.5, "lattice_n": 1_000_000,
             "lattice_tau": (50.0, 100.0, 200.0, 400.0, 800.0, 1600.0, 3200.0), "lattice_seeds": 2,
             "porod_x": (3.0, 15.0), "k_max": 0.6, "lattice_porod_x": (8.0, 30.0),
             "lattice_k_max": 0.5, "md_n": 100_000, "md_t_max": 287.0,
             "md_seeds": 2, "md_delta": 1e-4, "md_times": (48.0, 100.0, 287.0)},
}


def _collapse_spread(k, spectra, times, z, x_range):
    """rms over scaled x = k·t^z in ``x_range`` (log grid of 40 points) of the spread (std over
    times) of ln S, each curve interpolated in ln x."""
    xs = np.geomspace(*x_range, 40)
    curves = []
    for s, t in zip(spectra, times, strict=True):
        kb, sb = log_binned(k, s)
        curves.append(np.interp(np.log(xs), np.log(kb * t**z), np.log(sb)))
    return float(np.sqrt(np.mean(np.var(np.array(curves), axis=0, ddof=1))))


def run(size=None, progress: bool | None = None, checkpoint_dir=None,
        runner=None, **overrides) -> Comparison:
    """Comparison 6 (paper Fig. 3): S(k, τ) of the lattice against k τ^{1/2} (with and without the
    kinematic constraint) and S(k, t) of MD against k t^{2/3}, r = 0.5.

    S(k) = |v̂(k)|²/N over labels (:func:`particles.observables.structure_factor`), averaged over
    seeds and log-binned (10 bins per decade).  Numbers:

    * collapse quality: rms over x = k t^z ∈ [0.5, porod_x[1]] of the spread (std over the
      times) of ln S, at the theory's z and at z = 0 (no rescaling), each [value, jackknife
      error over seeds], and ``z_best``, the z that minimises it (scan of [0, 1] in steps of
      0.01, refined between grid points), [value, jackknife error]; at the edge of the scan
      ``z_best_at_scan_edge`` is true and the error None (see :func:`_structure_numbers`);
    * Porod slope: ln S against ln k on x ∈ ``porod_x`` and k ≤ ``k_max`` (MD), on
      x ∈ ``lattice_porod_x`` and k ≤ ``lattice_k_max`` (lattice): of the seed-mean spectrum at
      each time (``porod_slope_per_time``, [value, jackknife error]; None where the window holds
      fewer than 3 log bins), and the mean and standard error over seeds of per-seed fits at the
      last time (``porod_slope_last_time``).  Jackknife errors need 3 seeds (None below);
    * MD only, the drift of the collapse exponent within the run (:func:`z_drift`):
      ``z_best_early_pair`` and ``z_best_late_pair`` (the first two and the last two of
      ``md_times`` alone) and ``z_drift`` (late − early), [value, jackknife error].

    The lattice window x = k τ^{1/2} ∈ [8, 30], k ≤ 0.5 lies where the local slope of S has
    come back to −2 after overshooting to about −3 at the knee of the scaling function (x ≈ 2),
    and below the lattice scale (k ≳ 1); such a range first exists at τ ≈ 2000 (r = 0.5).  Why,
    with the slopes on other windows: the page "Measured results" of the documentation.

    ``checkpoint_dir``: an existing folder where each MD run checkpoints and from which it
    resumes (:func:`.particle_runs.md_runs`); None (default): no checkpoints.

    Parameters
    ----------
    size : str, optional
        ``"small"``, ``"default"`` or ``"full"`` (the presets of ``PRESETS``); None (default):
        :func:`maxwell_kinetics.app.comparisons.base.default_size`.
    progress : bool or None, optional
        Show progress of the runs and solves (None, the default: a bar on a terminal or in a
        notebook, nothing otherwise).
    checkpoint_dir : str or os.PathLike, optional
        Existing folder for the MD runs' checkpoints (see above); default none.
    runner : maxwell_kinetics.app.comparisons.particle_runs.ParticleRuns, optional
        Where the particle runs execute and are kept; default a new serial one.
    **overrides
        Replace single parameters of the size's preset (e.g. ``n=20000``).

    Returns
    -------
    maxwell_kinetics.app.comparisons.base.Comparison
        ``summary``: the numbers above with their uncertainties, the parameters used and the
        wall-clock ``seconds``; ``data``: the arrays its figure is drawn from.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From :func:`maxwell_kinetics.app.comparisons.base.preset`: an unknown ``size`` or an
        override that is not a parameter of the preset.
    """
    runner = ParticleRuns() if runner is None else runner
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    r = params["restitution"]
    seeds = tuple(range(params["lattice_seeds"]))
    out, data = {}, {}
    x_range = (0.5, params["porod_x"][1])
    zs = np.round(np.arange(0.0, 1.0001, 0.01), 2)
    for label, constraint in (("lattice", True), ("lattice_no_constraint", False)):
        runs = runner.lattice_runs(r, params["lattice_n"], params["lattice_tau"], seeds, constraint,
                                   progress=progress, structure=True)
        k, spec = runs["k"], runs["structure"]  # (R, T, K)
        mean = spec.mean(axis=0)
        times = runs["times"]
        out[label] = _structure_numbers(k, spec, mean, times, 0.5, zs, x_range, params,
                                        lattice=True)
        data[label] = {"k": k, "S": mean, "times": times, "z": 0.5}
    md = runner.md_runs(r, params["md_n"], params["md_delta"], md_record_times(params["md_t_max"]),
                        tuple(range(params["md_seeds"])), progress=progress,
                        checkpoint_dir=checkpoint_dir)
    idx = [int(np.argmin(np.abs(md["times"] - t))) for t in params["md_times"]]
    times = md["times"][idx]
    spec = np.array([[structure_factor(md["snapshots"][i, j])[1] for j in idx]
                     for i in range(md["snapshots"].shape[0])])
    k = structure_factor(md["snapshots"][0, 0])[0]
    mean = spec.mean(axis=0)
    out["md"] = _structure_numbers(k, spec, mean, times, 2.0 / 3.0, zs, x_range, params,
                                   lattice=False)
    out["md"].update(z_drift(k, spec, times, zs, x_range))
    data["md"] = {"k": k, "S": mean, "times": times, "z": 2.0 / 3.0}
    summary = {"parameters": jsonable(params), **out, "seconds": time.perf_counter() - start}
    return Comparison(NAME, with_verdicts(summary, verdicts), data)


def _z_minimum(k, spectra, times, zs, x_range) -> tuple[float, bool]:
    """The z minimising the collapse spread: grid scan over ``zs``, then a bounded Brent search
    between the grid minimum's two neighbours (to 1e-5; the vertex of a parabola through the
    three grid points was off by up to 1e-3, more than the jackknife error, because the spread
    is only piecewise smooth in z).  Returns (z, at_edge); at_edge when the grid minimum is the
    first or last z (the spread still falls toward the end of the scan: no minimum inside it;
    z is then the edge value)."""
    from scipy.optimize import minimize_scalar

    spread = np.array([_collapse_spread(k, spectra, times, z, x_range) for z in zs])
    i = int(np.argmin(spread))
    if i == 0 or i == len(zs) - 1:
        return float(zs[i]), True
    res = minimize_scalar(lambda z: _collapse_spread(k, spectra, times, z, x_range),
                          bounds=(float(zs[i - 1]), float(zs[i + 1])), method="bounded",
                          options={"xatol": 1e-5})
    z = float(res.x) if res.fun <= spread[i] else float(zs[i])
    return z, False


def _structure_numbers(k, spec, mean, times, z_theory, zs, x_range, params, *,
                       lattice: bool) -> dict:
    """Numbers of one model (see :func:`run`); ``spec`` (R, T, K) per seed.

    Every number of the seed-mean spectrum gets a jackknife error over the seeds (leave one
    seed out, recompute from the mean of the others); with fewer than 3 seeds (the ``full``
    lattice has 2) the error is None.

    ``z_best``: [z, jackknife error] of the refined minimum of the collapse spread (see
    :func:`_z_minimum`).  The grid alone (step 0.01) made the jackknife useless: at the small
    size all replicas hit the same grid point (error 0.0).  When the minimum is at the edge of
    the scan (``z_best_at_scan_edge``: the lattice without the constraint, whose spread keeps
    falling up to z = 1) there is no minimum to locate and the error is None.
    """
    n_runs = spec.shape[0]
    z_best, at_edge = _z_minimum(k, mean, times, zs, x_range)
    window, k_max = ((params["lattice_porod_x"], params["lattice_k_max"]) if lattice
                     else (params["porod_x"], params["k_max"]))

    def numbers(m):
        return {"theory": _collapse_spread(k, m, times, z_theory, x_range),
                "unscaled": _collapse_spread(k, m, times, 0.0, x_range),
                "slopes": [porod_slope(k, s, t, z_theory, window, k_max)
                           for s, t in zip(m, times, strict=True)]}

    full = numbers(mean)
    leave_one_out = ([np.delete(spec, i, axis=0).mean(axis=0) for i in range(n_runs)]
                     if n_runs >= 3 else [])
    jack = [numbers(m) for m in leave_one_out]
    z_jack = ([_z_minimum(k, m, times, zs, x_range)[0] for m in leave_one_out]
              if not at_edge else [])

    def with_error(value, key, index=None):
        if value is None:
            return None
        reps = [j[key] if index is None else j[key][index] for j in jack]
        return [value, jackknife(reps) if reps else None]

    per_seed = [porod_slope(k, spec[i, -1], times[-1], z_theory, window, k_max)
                for i in range(n_runs)]
    per_seed = [p for p in per_seed if p is not None]
    return {
        "times": list(map(float, times)),
        "z_theory": z_theory,
        "collapse_spread_at_z_theory": with_error(full["theory"], "theory"),
        "collapse_spread_unscaled": with_error(full["unscaled"], "unscaled"),
        "z_best": [z_best, None if at_edge else (jackknife(z_jack) if z_jack else None)],
        "z_best_at_scan_edge": at_edge,
        "z_scan": [float(zs[0]), float(zs[-1]), float(zs[1] - zs[0])],
        "porod_window": {"x": list(map(float, window)), "k_max": float(k_max)},
        "porod_slope_per_time": [with_error(v, "slopes", i) for i, v in enumerate(full["slopes"])],
        "porod_slope_last_time": mean_sem_json(per_seed),
    }


def z_drift(k, spec, times, zs, x_range) -> dict:
    """The drift of the collapse exponent within one run: ``z_best_early_pair`` and
    ``z_best_late_pair``, the z of the best collapse (:func:`_z_minimum`) of the first two and
    of the last two ``times`` alone, and ``z_drift`` = late − early, each [value, jackknife
    error over the seeds] (the difference's error from the leave-one-out differences, so that
    the shared middle time counts once).  A value at the edge of the scan is None, and so is
    the drift then.

    Parameters
    ----------
    k : numpy.ndarray
        Wave numbers, shape (K,).
    spec : numpy.ndarray
        S(k) per seed and time, shape (R, T, K), T ≥ 3.
    times : numpy.ndarray
        The T times.
    zs : numpy.ndarray
        The scan of z.
    x_range : tuple of float
        The scaled range of the collapse spread.

    Returns
    -------
    dict
        ``{"pair_times": [[t₀, t₁], [t_{T−2}, t_{T−1}]], "z_best_early_pair",
        "z_best_late_pair", "z_drift"}``.
    """
    times = np.asarray(times, dtype=float)
    pairs = {"early": [0, 1], "late": [len(times) - 2, len(times) - 1]}
    n_runs = spec.shape[0]
    replicas = [spec.mean(axis=0)] + ([np.delete(spec, i, axis=0).mean(axis=0)
                                      for i in range(n_runs)] if n_runs >= 3 else [])
    z = {}
    for name, sel in pairs.items():
        found = [_z_minimum(k, m[sel], times[sel], zs, x_range) for m in replicas]
        z[name] = [None if edge else value for value, edge in found]
    out = {"pair_times": [[float(times[i]) for i in sel] for sel in pairs.values()]}
    for name in pairs:
        reps = z[name][1:]
        out[f"z_best_{name}_pair"] = [z[name][0], jackknife(reps) if reps else None]
    diff = [None if a is None or b is None else b - a for a, b in zip(z["early"], z["late"],
                                                                       strict=True)]
    out["z_drift"] = [diff[0], jackknife(diff[1:]) if diff[0] is not None and diff[1:]
                      else None]
    return out


#: The first time of MD's collapse, in Haff times t₀, from which its exponent z is measured.
MD_Z_FIRST_TIME = 10.0


def verdicts(s: dict) -> list:
    """The verdicts of comparison 6 (Fig. 3) from its summary ``s``: the collapse exponent z
    of the lattice (1/2) and of MD (2/3), the Porod tails k⁻² of both, and no Porod tail without
    the kinematic constraint, each under the t law of its σ over the seeds (the jackknife's
    for z, the per-run fits' for the Porod slopes): Student's t with seeds − 1 dof at the
    coverage of 3σ, 19.2σ for the 3 MD seeds, 9.22σ for the 4 lattice seeds (z is refined
    between the points of its scan, so the scan's step adds nothing).

    The MD exponent has no explanation check: the drift measured within the run
    (``z_drift``, :func:`z_drift`) is no crossover that settles at 2/3.  The z of pairs of
    recorded times falls through 2/3 without a plateau (r = 0.5: from about 1 at t ≈ 6 to
    about 0.55 at the last times, N = 1000 and N = 2000 alike), so z over all the times is a
    mean over a drifting exponent, and a resolved fall would not show why it differs from
    2/3.

    The MD exponent is ``not measured`` by a run whose first collapse time is earlier than
    :data:`MD_Z_FIRST_TIME` Haff times t₀ = √π/(1 − r²) (the small size: t = 10, 4 t₀ at
    r = 0.5, where S(k, t) has not reached its late scaling; z of its pairs of times runs from
    about 1 down); the default size (from t = 25, 10.6 t₀) measures it."""
    out = []
    par = s["parameters"]

    def seeds(part, how):
        n = int(par.get(f"{part}_seeds", 0))  # 0: not recorded (degrees of freedom unknown)
        return {"dof": n - 1 if n > 1 else None, "t_law": True,
                "sigma_source": f"seeds: {how} over {n or 'the'} runs; Student's t law"}

    def z_check(part, label):
        p = s[part]
        z, err = pair(p["z_best"])
        if p.get("z_best_at_scan_edge"):
            z = None  # the scan's edge is no measurement
        return Check(f"z of the best collapse of S(k, t) against k t^z ({label})", z, err,
                     p["z_theory"], "paper: " + ("τ^(1/2), diffusive" if part == "lattice"
                                                 else "t^(2/3)"),
                     **seeds(part, "jackknife (leave one run out)"))

    out.append(judge("Fig. 3: lattice S(k, τ) = f₁(k τ^(1/2))", z_check("lattice", "lattice"),
                     short="3: lattice collapse z = 1/2"))
    t0 = haff_time(par["restitution"], 1.0)  # the presets' MD runs are at density 1
    out.append(judge("Fig. 3: MD S(k, t) = f₂(k t^(2/3))", z_check("md", "MD"),
                     why=f"the first collapse time is {min(par['md_times']) / t0:.2g} Haff times, "
                         f"before the late scaling (needs {MD_Z_FIRST_TIME:g})",
                     resolution=Check("first MD collapse time in Haff times t₀",
                                      min(par["md_times"]) / t0, None, MD_Z_FIRST_TIME,
                                      "model: the late (clustered) stage", relation="at_least"),
                     measured_at="default", short="3: MD collapse z = 2/3"))
    for part, label in (("lattice", "lattice"), ("md", "MD")):
        slope, err = pair(s[part]["porod_slope_last_time"])
        out.append(judge(f"Porod's law S(k) ∼ k⁻² (shocks) in the {label}",
                         Check(f"slope of log S(k) at large k t^z, {label}, last time", slope,
                               err, -2.0, "paper: Porod's law",
                               **seeds(part, "standard error of the per-run fits"))))
    slope, err = pair(s["lattice_no_constraint"]["porod_slope_last_time"])
    out.append(judge("without the kinematic constraint the Porod tail disappears",
                     Check("slope of log S(k), lattice without the constraint", slope, err,
                           -2.0, "paper: no shocks without the constraint",
                           relation="above",
                           **seeds("lattice", "standard error of the per-run fits"))))
    return out


def plot(c, ax=None):
    """S(k) of the seed mean against scaled k per time; the fitted Porod line (seed-mean
    spectrum at the last time, over the log bins of the fit window) drawn on its window with
    its slope, and a k⁻² reference below it."""
    d = c.data
    labels = ("md", "lattice", "lattice_no_constraint")
    titles = ("MD: S vs k t^(2/3)", "lattice: S vs k τ^(1/2)", "lattice, no constraint")
    clock = {"md": "t", "lattice": "τ", "lattice_no_constraint": "τ"}
    own = ax is None
    fig, axes = panels(3, ax, width=4.2, height=4.4)
    for ax, lab, title in zip(axes, labels, titles, strict=True):
        dd = d[lab]
        z = dd["z"]
        cols = colors(len(dd["times"]))
        for i, t in enumerate(dd["times"]):
            kb, sb, _ = log_bin(dd["k"], dd["S"][i], 10)
            ax.loglog(kb * t**z, sb, "o-", ms=2, lw=0.8, color=cols[i],
                      label=f"{clock[lab]} = {t:.0f}")
        s = c.summary[lab]
        window, k_max = s["porod_window"]["x"], s["porod_window"]["k_max"]
        t_last = dd["times"][-1]
        fit = porod_fit(dd["k"], dd["S"][-1], t_last, z, window, k_max)
        if fit is not None:
            slope, icpt, kf = fit
            kl = np.array([kf[0], kf[-1]])
            err = (s["porod_slope_per_time"][-1] or [None, None])[1]
            pm = f" ± {err:.2f}" if err is not None else ""
            ax.loglog(kl * t_last**z, np.exp(icpt) * kl**slope, "r-", lw=2.5, alpha=0.8,
                      label=f"fit at {clock[lab]} = {t_last:.0f}: slope {slope:.2f}{pm}")
            ax.loglog(kl * t_last**z, 0.3 * np.exp(icpt) * kl[0] ** (slope + 2.0) * kl**-2.0,
                      "k:", lw=1, label="k⁻² (reference)")
        ax.axvspan(*window, color="0.9", zorder=0, label="Porod fit window")
        ax.set(xlabel=f"k {clock[lab]}^{z:.3g}" if lab != "md" else "k t^(2/3)",
               ylabel="S(k)",
               title=f"{title}\nspread {s['collapse_spread_at_z_theory'][0]:.2f}"
               f" (unscaled {s['collapse_spread_unscaled'][0]:.2f})")
        ax.legend(fontsize=6, loc="lower left")
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=6))
