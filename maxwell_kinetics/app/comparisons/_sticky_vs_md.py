"""Comparison 8: paired validation of the sticky gas as the late stage of MD — MD at
r = 0.5, δ = 10⁻⁴ and the exact sticky gas from the SAME initial state agree in E t^(2/3)
closer than independent seeds do, and where the equivalence ends (t δ ≫ 1, Shinde, Das and
Rajesh 2007).  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import time

import numpy as np

from particles.observables import mean_sem_json

from .analysis import paired_numbers
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import colors, panels
from .particle_runs import ParticleRuns, md_record_times
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts"]

NAME = "sticky_vs_md"

#: ``n``, ``t_max``, ``seeds`` and ``delta`` of the paired runs are those of comparison 5's MD
#: (``small``: N = 1000 to t = 40; ``default``: N = 2000 to t = 100; recorded at
#: :func:`.particle_runs.md_record_times`), so that within one ``reproduce`` they share the runs;
#: ``full`` is the size of the independent reference, N = 2·10⁴ to t = 300.
#: ``window``: the late stage compared (t ≥ 10 ≈ 4 Haff times t₀ = √π/(1 − r²) = 2.4).
#: ``departure``: (δ, N) of the runs to ``departure_t_max`` (one seed each, 12 geometric
#: times from t = 10) that show where the equivalence ends; two N at one δ separate the
#: departure from finite-size effects (a run holds about N / t^{2/3} clusters).
#: Measured cost (loaded 2-core machine): MD N = 1000, δ = 10⁻⁴ to t = 40: 4.6 s per seed;
#: N = 5000, δ = 0.1 to t = 5000: 12 s.
PRESETS = {
    "small": {"restitution": 0.5, "delta": 1e-4, "n": 1000, "t_max": 40.0, "seeds": 3,
              "window": (10.0, 40.0), "departure": ((0.1, 1000), (0.1, 2000)),
              "departure_t_max": 2000.0},
    "default": {"restitution": 0.5, "delta": 1e-4, "n": 2000, "t_max": 100.0, "seeds": 3,
                "window": (10.0, 100.0), "departure": ((0.1, 5000), (0.1, 20_000)),
                "departure_t_max": 5000.0},
    "full": {"restitution": 0.5, "delta": 1e-4, "n": 20_000, "t_max": 300.0, "seeds": 3,
             "window": (38.0, 300.0),
             "departure": ((0.1, 10_000), (0.1, 40_000), (0.01, 10_000)),
             "departure_t_max": 5000.0},
}


def run(size=None, progress: bool | None = None, checkpoint_dir=None,
        runner=None, **overrides) -> Comparison:
    """Comparison 8: MD (r = ``restitution``, δ = ``delta``) against the exact sticky gas from
    the same initial state (seed s of :func:`.particle_runs.md_runs` and of
    :func:`.particle_runs.sticky_runs` draws the same positions and velocities: N, density 1,
    Gaussian law).

    Per recorded time t in ``window`` (``paired``):

    * ``md_e_t23``, ``sticky_e_t23``: E t^{2/3}, mean ± standard error over seeds;
    * ``relative_difference``: E_MD/E_sticky − 1 of the same seed, mean ± standard error over
      seeds, and ``abs_relative_difference`` (mean |·| ± s.e.);
    * ``unpaired_rms``: rms of E_MD,i/E_sticky,j − 1 over the seed pairs i ≠ j (independent
      initial states), and ``seed_relative_std``: std over seeds of the sticky E t^{2/3}
      divided by its mean (unpaired differences have about √2 times this);
    * over the whole window: ``paired_rms`` and ``unpaired_rms`` (rms over times and seeds or
      seed pairs) and their ratio.

    ``departure``: for each (δ, N) of the preset, one seed (0) of MD and the sticky gas to
    ``departure_t_max``: E t^{2/3} of both, E_MD/E_sticky against t δ, the sticky gas's
    number of clusters (finite-size: few clusters make one run noisy, though paired) and MD's
    collisions per particle; ``first_t_delta_beyond_10pc``: the first t δ where
    |E_MD/E_sticky − 1| > 0.1 (None if never).

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
    r, n, delta = params["restitution"], int(params["n"]), params["delta"]
    seeds = tuple(range(int(params["seeds"])))
    times = md_record_times(params["t_max"])
    md = runner.md_runs(r, n, delta, times, seeds, progress=progress,
                        checkpoint_dir=checkpoint_dir)
    sticky = runner.sticky_runs(n, times, seeds, progress=False)
    t_all = np.asarray(times)
    sel = (t_all >= params["window"][0]) & (t_all <= params["window"][1])
    t = t_all[sel]
    e_md, e_st = md["energy"][:, sel], sticky["energy"][:, sel]
    paired, unpaired = paired_numbers(e_md, e_st)
    scale = t ** (2.0 / 3.0)

    def mean_se(a):  # per time: [mean, standard error] over the rows (seeds)
        return [mean_sem_json(column) for column in np.asarray(a, float).T]

    rms = float(np.sqrt(np.mean(paired**2)))
    rms_un = float(np.sqrt(np.mean(unpaired**2))) if unpaired.size else None
    seed_std = (e_st * scale).std(axis=0, ddof=1) / (e_st * scale).mean(axis=0)
    paired_out = {
        "times": t.tolist(),
        "md_e_t23": mean_se(e_md * scale), "sticky_e_t23": mean_se(e_st * scale),
        "relative_difference": mean_se(paired),
        "abs_relative_difference": mean_se(np.abs(paired)),
        "unpaired_rms": np.sqrt(np.mean(unpaired**2, axis=0)).tolist(),
        "seed_relative_std": seed_std.tolist(),
        "paired_rms": rms, "unpaired_rms_window": rms_un,
        "paired_over_unpaired": None if not rms_un else rms / rms_un,
        "md_tau_last": md["tau"][:, -1].tolist(), "md_seconds": md["seconds"],
    }
    departure, dep_data = [], []
    t_dep = tuple(float(x) for x in np.round(np.geomspace(10.0, params["departure_t_max"], 12), 3))
    sc = np.asarray(t_dep) ** (2.0 / 3.0)
    for d_delta, d_n in params["departure"]:
        m = runner.md_runs(r, int(d_n), d_delta, t_dep, (0,), progress=progress,
                           checkpoint_dir=checkpoint_dir)
        s = runner.sticky_runs(int(d_n), t_dep, (0,), progress=False)
        ratio = m["energy"][0] / s["energy"][0]
        beyond = np.flatnonzero(np.abs(ratio - 1.0) > 0.1)
        departure.append({
            "delta": float(d_delta), "n": int(d_n), "seed": 0, "times": list(t_dep),
            "t_delta": (np.asarray(t_dep) * d_delta).tolist(),
            "md_e_t23": (m["energy"][0] * sc).tolist(),
            "sticky_e_t23": (s["energy"][0] * sc).tolist(), "ratio": ratio.tolist(),
            "sticky_clusters": s["clusters"][0].tolist(), "md_tau": m["tau"][0].tolist(),
            "first_t_delta_beyond_10pc": (float(t_dep[beyond[0]] * d_delta) if beyond.size
                                          else None),
            "md_seconds": m["seconds"],
        })
        dep_data.append({"times": np.asarray(t_dep), "md": m["energy"][0] * sc,
                         "sticky": s["energy"][0] * sc, "delta": float(d_delta), "n": int(d_n)})
    summary = {"parameters": jsonable(params), "paired": paired_out, "departure": departure,
               "seconds": time.perf_counter() - start}
    data = {"times": t, "md_e_t23": e_md * scale, "sticky_e_t23": e_st * scale,
            "paired": paired, "unpaired": unpaired, "departure": tuple(dep_data),
            "delta": float(delta), "n": n}
    return Comparison(NAME, with_verdicts(summary, verdicts), data)


def verdicts(s: dict) -> list:
    """The verdict of comparison 8 from its summary ``s``: MD and the sticky gas from the same
    initial state have the same E t^{2/3}.  At each time of the window the paired relative
    difference E_MD/E_sticky − 1 of the same seed has a mean and a standard error over the
    seeds; the check is the time of the largest |mean/σ|, against 0 under the t law (σ from
    ``seeds`` runs only: Student's t with ``seeds − 1`` degrees of freedom, and the largest of
    the window's |z|, one per time, ``trials``: the Šidák quantile at the coverage of 3σ, so
    the allowance is that of a maximum, not of one value; 19.2σ for one value of 3 seeds,
    more for several times).  No stated tolerance: the pairing removes the seed-to-seed
    scatter, so the paired σ is what is left.  The calibration of the verdicts judges its z
    as the largest of that many Student's t values, as the tolerance does."""
    p = s["paired"]
    seeds = int(s["parameters"]["seeds"])
    rows = [(t, *pair(entry)) for t, entry in zip(p["times"], p["relative_difference"],
                                                   strict=True)]
    ok = [row for row in rows if row[1] is not None and row[2]]
    t, value, sigma = (max(ok, key=lambda row: abs(row[1]) / row[2]) if ok and len(ok) == len(rows)
                       else (p["times"][-1] if p["times"] else float("nan"), None, None))
    return [judge(
        "late MD is a sticky gas (Ben-Naim et al., quoted by the paper): paired runs agree",
        Check(f"E_MD/E_sticky − 1 of paired seeds at t = {t:g} (the window's largest |z|)",
              value, sigma, 0.0,
              f"model: the sticky gas; Student's t, {seeds - 1} degrees of freedom, the "
              f"largest of {max(len(rows), 1)}",
              dof=seeds - 1 if seeds > 1 else None, trials=max(len(rows), 1), t_law=True,
              sigma_source=f"seeds: standard error over {seeds} paired runs, at the time of "
                           f"the largest |z| of {len(rows)}; Student's t law"),
        short="late MD = sticky gas, paired")]


def plot(c, ax=None):
    """Three panels: E t^{2/3} against t (paired MD δ = ``delta`` and sticky gas, seed mean and
    each seed; the departure runs), the paired relative difference (mean ± s.e. over seeds)
    with the unpaired rms as a band, and E_MD/E_sticky against t δ for the departure runs."""
    d, s = c.data, c.summary
    own = ax is None
    fig, (a, b, e) = panels(3, ax, width=4.6, height=4.2)
    t = d["times"]
    for row_md, row_st in zip(d["md_e_t23"], d["sticky_e_t23"], strict=True):
        a.plot(t, row_md, "-", color="C0", lw=0.5, alpha=0.5)
        a.plot(t, row_st, "--", color="C1", lw=0.5, alpha=0.5)
    a.plot(t, d["md_e_t23"].mean(axis=0), "o-", color="C0", ms=3,
           label=f"MD δ={d['delta']:g}, N={d['n']} (seed mean)")
    a.plot(t, d["sticky_e_t23"].mean(axis=0), "s--", color="C1", ms=3,
           label="sticky gas, same initial states")
    cols = colors(len(d["departure"]))
    for col, dep in zip(cols, d["departure"], strict=True):
        a.plot(dep["times"], dep["md"], "-", color=col, lw=1,
               label=f"MD δ={dep['delta']:g}, N={dep['n']}")
        a.plot(dep["times"], dep["sticky"], ":", color=col, lw=1)
    a.set(xscale="log", xlabel="t", ylabel="E t^(2/3)",
          title="MD against the sticky gas, paired\n(dotted: sticky gas of the departure runs)")
    a.legend(fontsize=6)
    p = s["paired"]
    rel = np.array([v for v, _ in p["relative_difference"]])
    err = np.array([0.0 if e_ is None else e_ for _, e_ in p["relative_difference"]])
    un = np.asarray(p["unpaired_rms"])
    b.fill_between(t, -un, un, color="0.85", label="± unpaired rms (seeds i ≠ j)")
    b.errorbar(t, rel, yerr=err, fmt="o-", ms=3, capsize=2, color="C0",
               label="paired E_MD/E_sticky − 1")
    b.axhline(0.0, color="k", lw=0.5)
    ratio = p["paired_over_unpaired"]
    b.set(xscale="log", xlabel="t", ylabel="relative difference",
          title=f"paired rms {p['paired_rms']:.3f}, unpaired {p['unpaired_rms_window'] or 0:.3f}"
          f"\n(ratio {ratio if ratio is None else round(ratio, 2)})")
    b.legend(fontsize=7)
    for col, dep in zip(cols, s["departure"], strict=True):
        e.plot(dep["t_delta"], dep["ratio"], "o-", ms=3, color=col,
               label=f"δ={dep['delta']:g}, N={dep['n']}")
    e.axhline(1.0, color="k", lw=0.5)
    e.set(xscale="log", xlabel="t δ", ylabel="E_MD / E_sticky",
          title="where the equivalence ends (t δ ≫ 1)\none seed each, paired")
    e.legend(fontsize=7)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=8))
