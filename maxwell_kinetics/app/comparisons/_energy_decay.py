"""Comparison 5: E(t) of MD (Haff's t⁻², then t^(−2/3)) and E(τ) of the lattice (exponential,
then τ^(−1/2)).  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.md.observables import haff_time
from particles.observables import mean_sem_json

from ... import statistics as st
from ...inelastic_boltzmann import solve_boltzmann
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import panels
from .particle_runs import ParticleRuns, md_record_times
from .verdicts import Check, judge, welch_dof, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "lattice_times", "verdicts"]

NAME = "energy_decay"

PRESETS = {
    "small": {"restitution": 0.5, "delta": 1e-4, "md_n": 1000, "md_t_max": 40.0, "md_seeds": 3,
              "md_haff_window": (0.3, 2.0), "md_late_window": (12.0, 40.0),
              "lattice_n": 20_000, "lattice_tau_max": 400.0, "lattice_seeds": 4,
              "lattice_early_window": (0.0, 0.25), "lattice_late_window": (40.0, 400.0)},
    "default": {"restitution": 0.5, "delta": 1e-4, "md_n": 2000, "md_t_max": 100.0,
                "md_seeds": 3, "md_haff_window": (0.3, 2.0), "md_late_window": (25.0, 100.0),
                "lattice_n": 100_000, "lattice_tau_max": 2000.0, "lattice_seeds": 4,
                "lattice_early_window": (0.0, 0.25), "lattice_late_window": (100.0, 2000.0)},
    "full": {"restitution": 0.5, "delta": 1e-4, "md_n": 100_000, "md_t_max": 287.0,
             "md_seeds": 2, "md_haff_window": (0.3, 2.0), "md_late_window": (48.0, 287.0),
             "lattice_n": 1_000_000, "lattice_tau_max": 4000.0, "lattice_seeds": 4,
             "lattice_early_window": (0.0, 0.25), "lattice_late_window": (200.0, 4000.0)},
}


def lattice_times(tau_max):
    """τ at which the lattice runs record E: 10 points on [0.025, 0.25], 40 geometric on
    [0.35, ``tau_max``]."""
    early = np.linspace(0.025, 0.25, 10)
    late = np.geomspace(0.35, tau_max, 40)
    return tuple(float(t) for t in np.round(np.concatenate([early, late]), 6))


def run(size=None, progress: bool | None = None, checkpoint_dir=None,
        runner=None, **overrides) -> Comparison:
    """Comparison 5: E(t) of MD (Haff's t⁻², then t^{−2/3}) and E(τ) of the lattice
    (exponential, then τ^{−1/2}), r = ``restitution``.

    Fits, each run separately, mean ± standard error over the runs (seeds):

    * MD Haff: slope of ln E against ln(1 + t/t₀), t₀ = √π/((1 − r²) n), on
      ``md_haff_window`` (expected −2 while the gas is homogeneous);
    * kinetic theory of the same stage (``boltzmann_haff_exponent``): the same fit, at the
      same recorded times, of E(t) of the hard-rod Boltzmann equation (molecular chaos, same
      initial Gaussian, density 1; :func:`maxwell_kinetics.inelastic_boltzmann.solve_boltzmann`,
      its default grid).  Its velocity law leaves the Gaussian (its kurtosis at the window's
      end is reported), so its cooling rate −(1 − r²)/4 n⟨|v − w|³⟩ is not the Gaussian one
      and its slope is not exactly −2: it is what the homogeneous gas under molecular chaos
      gives on this window.  Deterministic (no error; the grid's error is ~1e-6 on the
      slope).  ``md_energy_over_boltzmann``: E of MD over E of the Boltzmann equation at the
      first and at the last recorded time of the window, [mean, standard error] over the runs
      (1 while MD follows molecular chaos);
    * MD late: slope of ln E against ln t on ``md_late_window`` (expected −2/3);
    * lattice early: the initial rate d ln E/dτ at τ = 0⁺ (exact: −(1 − r²)/2), the
      linear coefficient of a quadratic fit of ln E against τ on ``lattice_early_window``.  A
      straight line there would measure the mean slope over the window instead, which the
      build-up of correlations makes steeper;
    * lattice late: slope of ln E against ln τ on ``lattice_late_window`` (expected −1/2).

    Each fit reports its ``window`` (from the preset), ``fit_range`` (first and last recorded
    time inside it) and ``fit_points``.

    The late exponents' ``uncertainty`` adds in quadrature the seeds' standard error and the
    window drift (half the difference of the slopes on the two halves of the window): the local
    exponent still drifts inside the window, so the seeds' error alone would understate it.

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
    md = runner.md_runs(r, params["md_n"], params["delta"], md_record_times(params["md_t_max"]),
                        tuple(range(params["md_seeds"])), progress=progress,
                        checkpoint_dir=checkpoint_dir)
    lat = runner.lattice_runs(r, params["lattice_n"], lattice_times(params["lattice_tau_max"]),
                              tuple(range(params["lattice_seeds"])), progress=progress)
    t, e = md["times"], md["energy"]
    t0 = haff_time(r, 1.0)  # the presets' MD runs are at density 1
    tau, el = lat["times"], lat["energy"]
    # Each fit: (clock, energies, window name, abscissa of the fit as a function of the clock).
    # The lattice's early fit also uses the exact E(0) = 1 at τ = 0.
    # The lattice's early fit is a quadratic (its slope at τ = 0, see above) and also uses the
    # exact E(0) = 1 at τ = 0.
    lines, used, seed_fits = {}, {}, {}
    for name, clock, energy, key, fx, degree in (
            ("md_haff", t, e, "md_haff_window", lambda c: np.log1p(c / t0), 1),
            ("md_late", t, e, "md_late_window", np.log, 1),
            ("lattice_early", tau, el, "lattice_early_window", lambda c: c, 2),
            ("lattice_late", tau, el, "lattice_late_window", np.log, 1)):
        lo, hi = params[key]
        w = (clock >= lo) & (clock <= hi)
        c, y = clock[w], np.log(energy[:, w])
        if name == "lattice_early":
            c, y = np.concatenate([[0.0], c]), np.column_stack([np.zeros(len(energy)), y])
        used[name] = (fx(c), y)
        seed_fits[name] = st.seed_slope(fx(c), y, degree)
        # The coefficients of the seeds' mean ln E are the means of the per-seed ones (the fit
        # is linear in y); they draw the fitted curve in the figure.
        coef = np.polyfit(fx(c), y.mean(axis=0), degree)
        lines[name] = {"clock": c, "slope": float(coef[-2]), "intercept": float(coef[-1]),
                       "curvature": float(coef[0]) if degree == 2 else 0.0, "window": params[key]}
    lo, hi = params["md_haff_window"]
    boltzmann, md_over_boltzmann = _boltzmann_haff(r, t0, t[(t >= lo) & (t <= hi)],
                                                   e[:, (t >= lo) & (t <= hi)], params[
                                                       "md_haff_window"])
    haff, md_late, lat_early, lat_late = (
        seed_fits[k] for k in ("md_haff", "md_late", "lattice_early", "lattice_late"))
    md_late_xy, lat_late_xy = used["md_late"], used["lattice_late"]

    def fit(res, expected, name, x=None, ys=None):
        clock = lines[name]["clock"]
        out = {"slope": [res[0], res[1]], "per_run": res[2].tolist(), "expected": expected,
               "window": list(lines[name]["window"]),
               "fit_range": [float(clock[0]), float(clock[-1])], "fit_points": int(clock.size)}
        err = res[1]
        if x is not None:
            # Window systematic: half the difference of the slopes fitted on the two halves of
            # the window (the drift of the local exponent), added in quadrature to the seeds'.
            h = x.size // 2
            drift = 0.5 * abs(st.seed_slope(x[h:], ys[:, h:])[0] - st.seed_slope(x[:h + 1],
                                                                                  ys[:, :h + 1])[0])
            err = math.hypot(res[1], drift)
            out["window_drift"] = drift
        out["uncertainty"] = err
        out["deviation_in_sigma"] = (res[0] - expected) / err if err > 0 else None
        return out

    summary = {
        "parameters": jsonable(params),
        "md_haff_exponent": fit(haff, -2.0, "md_haff"),
        "boltzmann_haff_exponent": boltzmann,
        "md_energy_over_boltzmann": md_over_boltzmann,
        "md_late_exponent": fit(md_late, -2.0 / 3.0, "md_late", *md_late_xy),
        "md_collisions_per_particle_at_end": md["tau"][:, -1].tolist(),
        "md_seconds": md["seconds"],
        "lattice_initial_rate": fit(lat_early, -(1.0 - r * r) / 2.0, "lattice_early"),
        "lattice_late_exponent": fit(lat_late, -0.5, "lattice_late", *lat_late_xy),
        "lattice_seconds": lat["seconds"],
        "seconds": time.perf_counter() - start,
    }
    data = {"md_t": t, "md_energy": e, "t0": t0, "lattice_tau": tau, "lattice_energy": el,
            "windows": {k: params[k] for k in ("md_haff_window", "md_late_window",
                                            "lattice_early_window", "lattice_late_window")},
            "fits": lines, "restitution": r}
    return Comparison(NAME, with_verdicts(summary, verdicts), data)


def _boltzmann_haff(r, t0, clock, md_energy, window):
    """The Haff fit of the hard-rod Boltzmann equation's E(t) at the MD's recorded times
    ``clock`` inside ``window`` (density 1, Gaussian start; see :func:`run`), and E of the MD
    runs ``md_energy`` (R, len(clock)) over it at the first and last of those times.

    Returns
    -------
    (dict, dict)
        ``{"slope", "expected", "window", "fit_range", "fit_points", "kurtosis_at_end",
        "grid_points", "grid_half_width", "seconds"}`` and ``{"times", "ratio"}`` (ratio: one
        [mean, standard error over the runs] per time).
    """
    sol = solve_boltzmann(r, np.concatenate([[0.0], clock]))
    energy = sol.energy[1:]
    slope = float(np.polyfit(np.log1p(clock / t0), np.log(energy), 1)[0])
    record = {"slope": slope, "expected": -2.0, "window": list(window),
              "fit_range": [float(clock[0]), float(clock[-1])], "fit_points": int(clock.size),
              "kurtosis_at_end": float(sol.kurtosis[-1]), "grid_points": sol.grid.points,
              "grid_half_width": sol.grid.half_width, "seconds": sol.seconds}
    ratio = md_energy / energy
    ends = [0, clock.size - 1]
    return record, {"times": [float(clock[i]) for i in ends],
                    "ratio": [mean_sem_json(ratio[:, i]) for i in ends]}


def _fit_check(rec: dict, quantity: str, source: str):
    """The check of one fit record: slope ± its stated uncertainty (seeds, and the window
    drift for the late exponents) against its expected value, under the t law: Student's t
    with the Welch–Satterthwaite dof of the seeds' standard error (runs − 1) and the drift
    (a measured systematic: infinite dof) at the coverage of 3σ (19.2σ for 3 seeds' fits
    alone, 9.22σ for 4)."""
    runs = len(rec.get("per_run", []))
    seeds = rec["slope"][1]
    dof = welch_dof((seeds or 0.0, runs - 1 if runs > 1 else None),
                    (rec.get("window_drift") or 0.0, None))
    where = f"seeds: standard error over {runs} runs' fits"
    if rec.get("window_drift"):
        where += (", and the window drift (half the slopes' difference on its halves, a "
                  "measured systematic) in quadrature")
    return Check(f"{quantity}, fit on [{rec['window'][0]:g}, {rec['window'][1]:g}]",
                 rec["slope"][0], rec["uncertainty"], rec["expected"], source, dof=dof,
                 sigma_source=where + "; Student's t law", t_law=True)


def early_chaos_check(s: dict):
    """MD's E over the hard-rod Boltzmann equation's E at the Haff window's FIRST time equals 1
    (σ: standard error over the seeds; Student's t with seeds − 1 dof at the coverage of 3σ,
    19.2σ for 3 seeds): there molecular chaos must still hold, so a
    departure is an engine that does not make the Boltzmann equation's collisions (a wrong
    restitution, a wrong rate), not correlations.  None for a summary without that ratio.

    Parameters
    ----------
    s : dict
        The comparison's summary.

    Returns
    -------
    Check or None
    """
    ratio = s.get("md_energy_over_boltzmann")
    if ratio is None:
        return None
    value, sigma = ratio["ratio"][0]
    runs = int(s.get("parameters", {}).get("md_seeds", 0))  # 0: not recorded
    return Check(f"E of MD over E of the hard-rod Boltzmann equation at t = "
                 f"{ratio['times'][0]:g} (the window's first time)", value, sigma, 1.0,
                 "exact: molecular chaos at the start (independent Gaussian velocities)",
                 dof=runs - 1 if runs > 1 else None, t_law=True,
                 sigma_source=f"seeds: standard error over {runs} MD runs; Student's t law")


def molecular_chaos_check(s: dict):
    """The explanation of a failed Haff check: MD has left molecular chaos within the fit's
    window.  Haff's law is the law of the homogeneous gas under molecular chaos, whose E(t) the
    hard-rod Boltzmann equation gives exactly (its non-Gaussian cooling included).  Two checks,
    both needed: MD's E over the Boltzmann equation's E equals 1 at the window's first time
    (:func:`early_chaos_check`: the engine makes the right collisions while molecular chaos
    holds), and differs from 1 at its last time by at least the t law's allowance of the
    seeds' σ (seeds − 1 dof at the coverage of 3σ: correlations the Boltzmann equation lacks
    change the cooling there).  A broken engine departs from the Boltzmann
    equation from the start and is never explained.  None for a summary without that ratio.

    Parameters
    ----------
    s : dict
        The comparison's summary.

    Returns
    -------
    tuple of Check, or None
    """
    ratio = s.get("md_energy_over_boltzmann")
    if ratio is None:
        return None
    t_end = ratio["times"][-1]
    value, sigma = ratio["ratio"][-1]
    runs = int(s.get("parameters", {}).get("md_seeds", 0))  # 0: not recorded
    return (early_chaos_check(s),
            Check(f"E of MD over E of the hard-rod Boltzmann equation at t = {t_end:g} (the "
                  f"window's last time)", value, sigma, 1.0,
                  "model: hard-rod Boltzmann equation (molecular chaos), same initial law",
                  relation="differs", dof=runs - 1 if runs > 1 else None, t_law=True,
                  sigma_source=f"seeds: standard error over {runs} MD runs; Student's t law"))


def _boltzmann_slope_text(s: dict) -> str:
    b = s.get("boltzmann_haff_exponent")
    return "not computed" if b is None else f"{b['slope']:.3f}"


def verdicts(s: dict) -> list:
    """The verdicts of comparison 5 from its summary ``s``: Haff's t⁻² and the late t^{−2/3}
    of MD, the lattice's initial rate and its τ^{−1/2} (each under the t law of its stated
    uncertainty: Student's t with the Welch–Satterthwaite dof of the seeds' scatter and the
    window drift at the coverage of 3σ, see :func:`_fit_check`).

    Haff's law is judged against the paper's −2 (the exponent of every homogeneous scaling
    state).  Its explanation, when it fails, is :func:`molecular_chaos_check`: MD's E over the
    hard-rod Boltzmann equation's E equals 1 at the window's first time (the engine is right
    while molecular chaos holds) and differs from 1 beyond its allowance at its last time, so the
    window is no longer MD's homogeneous stage under molecular chaos (both under the t law of the
    MD seeds).  The first of these is
    also a verdict of its own (the last one): MD follows the Boltzmann equation at the start.
    The Boltzmann equation's own slope on the same times (``boltzmann_haff_exponent``) is
    printed with it: at r = 0.5 it is close to −2, so the departure is not the non-Gaussian
    cooling of the homogeneous gas but MD's correlations."""
    r = s["parameters"]["restitution"]
    out = [
        judge(f"Haff's law E ∝ t⁻² in the homogeneous regime of MD, r = {r:g}",
              _fit_check(s["md_haff_exponent"], "slope of ln E against ln(1 + t/t₀)",
                         "paper: Haff's law (exact for the homogeneous gas)"),
              molecular_chaos_check(s),
              why="MD leaves molecular chaos inside the window: its E departs from the hard-rod "
                  "Boltzmann equation's (whose own slope on the same times is "
                  f"{_boltzmann_slope_text(s)}), so the window is not MD's homogeneous stage",
              short="MD Haff's law E ∝ t⁻²"),
        judge(f"late MD energy E ∝ t^(−2/3) for any r < 1 (Ben-Naim et al.), r = {r:g}",
              _fit_check(s["md_late_exponent"], "slope of ln E against ln t",
                         "paper: t^(−2/3)"), short="MD late E ∝ t^(−2/3)"),
        judge(f"lattice: E(τ) first decays exponentially, rate (1 − r²)/2, r = {r:g}",
              _fit_check(s["lattice_initial_rate"], "d ln E/dτ at τ = 0⁺",
                         "exact: −(1 − r²)/2"), short="lattice: initial rate (1 − r²)/2"),
        judge(f"lattice: then E ∝ τ^(−1/2), r = {r:g}",
              _fit_check(s["lattice_late_exponent"], "slope of ln E against ln τ",
                         "paper: τ^(−1/2)"), short="lattice: late E ∝ τ^(−1/2)"),
    ]
    early = early_chaos_check(s)
    if early is not None:
        out.append(judge(f"MD's E equals the hard-rod Boltzmann equation's at the Haff window's "
                         f"start (molecular chaos), r = {r:g}", early,
                         short="MD E = Boltzmann E at window start"))
    return out


def plot(c, ax=None):
    """E(t) of each MD run and E(τ) of each lattice run with the theory curves, and every fit
    drawn over its window (shaded): the line of the seeds' mean ln E, whose slope is the
    reported mean of the per-seed slopes."""
    d, s = c.data, c.summary
    own = ax is None
    fig, axes = panels(2, ax, width=5.5, height=4.4)
    a, b = axes
    r = d["restitution"]
    t, e = d["md_t"], d["md_energy"]
    t0 = d["t0"]
    fits = d["fits"]

    def label(name, key, expected):
        res = s[key]
        return (f"{name} fit on [{res['window'][0]:g}, {res['window'][1]:g}]: "
                f"{res['slope'][0]:.3f} ± {res['uncertainty']:.3f} ({expected})")

    def shade(ax, fit, color):  # the recorded times inside the window (τ = 0 is off the axis)
        clock = fit["clock"][fit["clock"] > 0]
        ax.axvspan(clock[0], clock[-1], color=color, alpha=0.12, lw=0)

    for i in range(e.shape[0]):
        a.loglog(t, e[i], color="C0", alpha=0.6, lw=1, label="MD runs" if i == 0 else None)
    a.loglog(t, 1.0 / (1.0 + t / t0) ** 2, "k--", lw=1, label="Haff (1 + t/t₀)⁻²")
    f = fits["md_haff"]
    a.loglog(f["clock"], np.exp(f["intercept"]) * (1.0 + f["clock"] / t0) ** f["slope"], "-",
             color="C3", lw=2.5, label=label("Haff", "md_haff_exponent", "−2"))
    shade(a, f, "C3")
    f = fits["md_late"]
    a.loglog(f["clock"], np.exp(f["intercept"]) * f["clock"] ** f["slope"], "-", color="C2",
             lw=2.5, label=label("late", "md_late_exponent", "−2/3"))
    shade(a, f, "C2")
    a.set(xlabel="t", ylabel="E(t)", title=f"MD, r = {r:g}")
    a.legend(fontsize=7, loc="lower left")
    tau, el = d["lattice_tau"], d["lattice_energy"]
    for i in range(el.shape[0]):
        b.loglog(tau, el[i], color="C1", alpha=0.6, lw=1, label="lattice runs" if i == 0 else None)
    b.loglog(tau, np.exp(-(1 - r**2) / 2 * tau), "k--", lw=1, label="exp(−(1−r²)τ/2)")
    f = fits["lattice_early"]
    ce = f["clock"][f["clock"] > 0]
    b.loglog(ce, np.exp(f["intercept"] + f["slope"] * ce + f.get("curvature", 0.0) * ce**2),
             "-", color="C3", lw=2.5,
             label=label("initial rate", "lattice_initial_rate", f"{-(1 - r**2) / 2:g}"))
    shade(b, f, "C3")
    f = fits["lattice_late"]
    b.loglog(f["clock"], np.exp(f["intercept"]) * f["clock"] ** f["slope"], "-", color="C2",
             lw=2.5, label=label("late", "lattice_late_exponent", "−1/2"))
    shade(b, f, "C2")
    b.set(ylim=(el.min() / 2, 1.5), xlabel="τ", ylabel="E(τ)", title=f"lattice, r = {r:g}")
    b.legend(fontsize=7, loc="lower left")
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=5))
