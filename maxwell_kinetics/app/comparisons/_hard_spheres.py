"""Comparison 13: the Maxwell model judged against inelastic hard spheres (d = 3) and hard disks
(d = 2), restitution α, m = 1, density 1, from the unit Maxwellian.

    ∂f/∂t = Q(f, f),   rate |g·n| over the whole unit sphere,
    v′ = v − (1+α)/2 (g·n) n,

T = ⟨|v − u|²⟩/d and the Sonine coefficients a₂, a₃ of c = (v − u)/√(2T)
(:mod:`particles.sphere_observables`).  Two independent solutions of the same equation are
compared: the deterministic spectral solver (:mod:`maxwell_kinetics.sphere_spectral`) and the
exact DSMC (:mod:`particles.hard_sphere_dsmc`), at early times and in the homogeneous cooling
state (HCS); the HCS a₂ of hard spheres is set against the Maxwell model's (exact: its moment
equations close, :func:`maxwell_hcs_a2`), against the first Sonine approximation (van Noije and
Ernst) and Haff's law is checked with and without the a₂ correction of the cooling rate.
Where the solver's cooling state is computed, its overpopulated tail is set against the Maxwell
model's power law (:mod:`._hard_spheres_tail`: conventions, the window rule, the statistic).
The DSMC samples the cooling state far into its tail at every size
(:mod:`._hard_spheres_dsmc_tail`): its fitted rate against the Maxwell model's, against 2K/ζ*,
and its cooling rate ζ* against the solver's.
``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles import hard_sphere_dsmc
from particles.cooling_state_sample import sample_cooling_state
from particles.progress import progress_bar
from particles.sphere_kernels import HardSpheres
from particles.sphere_observables import (
    collision_frequency,
    first_sonine_a2,
    haff_temperature,
    maxwell_a2_relaxation,
    maxwell_hcs_a2,
    sonine_coefficients,
    window_times,
)

from ... import sphere_spectral
from ...sphere_grid import SphereGrid
from . import _hard_spheres_dsmc_tail as dsmc_tail
from . import _hard_spheres_tail as hs_tail
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import panels
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts"]

NAME = "hard_spheres"

#: Each size: ``cases`` (d, the reported grid, the second grid whose distance from the first
#: is the solver's grid error; a name of ``maxwell_kinetics.sphere_grid.GRIDS`` or the fields
#: of a ``SphereGrid``), the early ``times`` compared with the DSMC, the DSMC's ``n`` and
#: ``seeds``, the cooling-state ``window`` of the DSMC (collisions per particle, Haff's clock)
#: and whether the solver computes the cooling state (``hcs``, on both grids); the cooling
#: state's tail sampled by the DSMC in rescaled chunks (``tail_n`` particles, ``tail_seeds``
#: runs of ``tail_snapshots`` snapshots, :mod:`particles.cooling_state_sample`).  The small
#: size's second grid has the coarse grid's array shapes (no second compilation) and a smaller
#: cutoff R = 6.5: a conservative grid error.
PRESETS = {
    "small": {"restitution": 0.5, "cases": ((2, "coarse", (32, 9.0, 6.5, 32, 12)),),
              "times": (0.1, 0.2, 0.4), "n": 20_000, "seeds": 8, "window": (10, 12, 14, 16),
              "hcs": False, "tail_n": 20_000, "tail_seeds": 8, "tail_snapshots": 10},
    "default": {"restitution": 0.5, "cases": ((3, "default", "coarse"),
                                              (2, "default", "coarse")),
                "times": (0.1, 0.2, 0.4), "n": 100_000, "seeds": 16,
                "window": (10, 12, 14, 16), "hcs": True, "tail_n": 100_000,
                "tail_seeds": 16, "tail_snapshots": 40},
    "full": {"restitution": 0.5, "cases": ((3, (32, 11.0, 8.0, 11, 12), "default"),
                                           (2, "fine", "default")),
             "times": (0.1, 0.2, 0.4), "n": 100_000, "seeds": 64,
             "window": (10, 12, 14, 16, 18, 20), "hcs": True, "tail_n": 100_000,
             "tail_seeds": 64, "tail_snapshots": 80},
}

#: Points of the solver's T(t), a₂(t) curve between 0 and the last early time (figure, Haff).
_CURVE_POINTS = 33


def _grid(spec):
    """A grid name, or a ``SphereGrid`` from its fields (a tuple or list)."""
    return spec if isinstance(spec, str) else SphereGrid(*spec)


def _corrected_haff(t: np.ndarray, a2: np.ndarray, restitution: float, dimension: int):
    """T(t) of dT/dt = −ζ₀(1 + 3a₂(t)/16) T^{3/2} from T = 1, a₂(t) on the times ``t``
    (trapezoid rule): T^{−1/2} = 1 + (ζ₀/2) ∫(1 + 3a₂/16) dt."""
    zeta0 = (1.0 - restitution**2) * collision_frequency(dimension) / dimension
    rate = 1.0 + 3.0 * np.asarray(a2) / 16.0
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
    return (1.0 + 0.5 * zeta0 * integral) ** -2


def _mean_sem(x) -> list:
    """[mean, standard error over the first axis] of ``x`` (seeds)."""
    x = np.asarray(x, dtype=float)
    return [float(np.mean(x)), float(np.std(x, ddof=1) / math.sqrt(x.shape[0]))]


def _dsmc(restitution, dimension, n, seeds, times, bar):
    """T, a₂, a₃ of each seed (rows) at ``times`` (columns): the DSMC from T = 1."""
    out = np.empty((3, len(seeds), len(times)))
    for i, seed in enumerate(seeds):
        engine = hard_sphere_dsmc.SphereDSMC(n, restitution, dimension=dimension)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        for j, t in enumerate(times):
            state = engine.advance(state, float(t), rng)
            obs = sonine_coefficients(state.velocities)
            out[:, i, j] = obs["temperature"], obs["a2"], obs["a3"]
        bar.update(1)
    return out


def _solve(kernel, times, dimension, grid):
    """T, a₂, a₃, ζ on ``times`` and the last F of one solve on ``grid``."""
    sol = sphere_spectral.solve_spheres(kernel, times, dimension=dimension, grid=_grid(grid))
    return {"T": np.asarray(sol.temperature), "a2": np.asarray(sol.a2),
            "a3": np.asarray(sol.a3), "zeta": np.asarray(sol.cooling_rate),
            "F": sol.F[-1], "seconds": sol.seconds}


#: The tail's DSMC runs use the seeds from here on (independent of the early runs' 0, 1, …).
TAIL_SEED_START = 10_000


def _case(params, dimension, primary, secondary, bar) -> tuple[dict, dict]:
    """The summary row and the figure data of one dimension."""
    alpha, d = float(params["restitution"]), int(dimension)
    kernel = HardSpheres(alpha)
    early = np.asarray(params["times"], dtype=float)
    curve = np.union1d(np.linspace(0.0, early[-1], _CURVE_POINTS), early)
    at = np.searchsorted(curve, early)
    solves = [_solve(kernel, curve, d, g) for g in (primary, secondary)]
    late = window_times(alpha, d, params["window"])
    seeds = tuple(range(int(params["seeds"])))
    runs = _dsmc(alpha, d, int(params["n"]), seeds, np.concatenate([early, late]), bar)
    k = early.size
    row = {"dimension": d, "grid": primary if isinstance(primary, str) else list(primary),
           "second_grid": secondary if isinstance(secondary, str) else list(secondary),
           "times": early.tolist(), "window_collisions": list(params["window"]),
           "window_times": late.tolist(), "solver_seconds": [s["seconds"] for s in solves]}
    for j, q in enumerate(("T", "a2", "a3")):
        row[f"solver_{q}"] = solves[0][q][at].tolist()
        row[f"grid_error_{q}"] = np.abs(solves[0][q][at] - solves[1][q][at]).tolist()
        row[f"dsmc_{q}"] = [_mean_sem(runs[j][:, i]) for i in range(k)]
    # the cooling state: per seed the mean of a₂, a₃ over the window, then over the seeds
    row["dsmc_hcs_a2"] = _mean_sem(runs[1][:, k:].mean(axis=1))
    row["dsmc_hcs_a3"] = _mean_sem(runs[2][:, k:].mean(axis=1))
    row["dsmc_window_T"] = [_mean_sem(runs[0][:, k + i]) for i in range(late.size)]
    haff_early = haff_temperature(early, alpha, d)
    haff_late = haff_temperature(late, alpha, d)
    corrected = _corrected_haff(curve, solves[0]["a2"], alpha, d)
    corrected_2 = _corrected_haff(curve, solves[1]["a2"], alpha, d)
    ratio_last = runs[0][:, -1] / haff_late[-1]
    zeta0 = (1.0 - alpha**2) * collision_frequency(d) / d
    zeta_excess = solves[0]["zeta"][at] / (zeta0 * np.sqrt(solves[0]["T"][at])) - 1.0
    row.update({
        "haff_T": haff_early.tolist(), "haff_T_window": haff_late.tolist(),
        "dsmc_T_over_haff_last": _mean_sem(ratio_last),
        "corrected_haff_T": corrected[at].tolist(),
        "corrected_haff_grid_error": np.abs(corrected[at] - corrected_2[at]).tolist(),
        "solver_T_over_corrected_haff": (solves[0]["T"][at] / corrected[at]).tolist(),
        "solver_cooling_excess": zeta_excess.tolist(),
        "first_order_cooling_excess": (3.0 * solves[0]["a2"][at] / 16.0).tolist(),
        "first_sonine_a2": first_sonine_a2(alpha, d),
        "maxwell_hcs_a2": maxwell_hcs_a2(alpha, d),
        "maxwell_a2_relaxation_rate": maxwell_a2_relaxation(alpha, d),
    })
    a2_fs = row["first_sonine_a2"]
    hcs_a2, hcs_err = row["dsmc_hcs_a2"]
    row["dsmc_hcs_a2_vs_first_sonine"] = [hcs_a2 / a2_fs - 1.0, hcs_err / a2_fs]
    if params["hcs"]:
        states = [sphere_spectral.cooling_state(kernel, dimension=d, grid=_grid(g),
                                                start=s["F"])
                  for g, s in zip((primary, secondary), solves, strict=True)]
        row.update({"solver_hcs_a2": states[0].a2, "solver_hcs_a3": states[0].a3,
                    "hcs_grid_error_a2": abs(states[0].a2 - states[1].a2),
                    "hcs_grid_error_a3": abs(states[0].a3 - states[1].a3),
                    "solver_hcs_cooling_rate": states[0].cooling_rate,
                    "hcs_grid_error_cooling_rate": abs(states[0].cooling_rate
                                                       - states[1].cooling_rate),
                    "hcs_grids": 2, "hcs_seconds": [s.seconds for s in states]})
        row["tail"], tail_data = hs_tail.measure(states, kernel, d)
    else:
        row.update({"solver_hcs_a2": None, "solver_hcs_a3": None, "hcs_grid_error_a2": None,
                    "hcs_grid_error_a3": None, "solver_hcs_cooling_rate": None,
                    "hcs_grid_error_cooling_rate": None, "hcs_grids": 0, "hcs_seconds": []})
        row["tail"], tail_data = hs_tail.not_computed(d), None
    seeds = int(params["tail_seeds"])
    sample = sample_cooling_state(
        int(params["tail_n"]), alpha, dimension=d, snapshots=int(params["tail_snapshots"]),
        seeds=range(TAIL_SEED_START, TAIL_SEED_START + seeds), progress=False)
    bar.update(seeds)
    row["dsmc_tail"], dsmc_data = dsmc_tail.measure(sample, kernel)
    data = {"dimension": d, "curve_t": curve, "solver_T": solves[0]["T"],
            "solver_a2": solves[0]["a2"], "corrected_haff": corrected,
            "haff": haff_temperature(curve, alpha, d), "times": early,
            "dsmc_T": runs[0][:, :k], "dsmc_a2": runs[1][:, :k], "window_times": late,
            "dsmc_window_T": runs[0][:, k:], "haff_window": haff_late, "tail": tail_data,
            "dsmc_tail": dsmc_data}
    return row, data


def run(size=None, progress: bool | None = None, runner=None, **overrides) -> Comparison:
    """Comparison 13: the spectral solver against the DSMC of hard spheres, and the Maxwell
    model against hard spheres.

    For each case (d, grid, second grid): the solver from the unit Maxwellian on both grids,
    T(t), a₂(t), a₃(t) at the early ``times`` (and on a fine time grid for the figure); the
    DSMC, ``seeds`` runs of ``n`` particles, at the same times and then in the cooling-state
    window (``window``: collisions per particle on Haff's clock, :func:`window_times`), where
    each seed's a₂, a₃ is its mean over the window.  Uncertainties are the standard error over
    the seeds; the solver's grid error is the distance between its two grids.  With ``hcs``
    the solver's cooling state (:func:`maxwell_kinetics.sphere_spectral.cooling_state`, from
    the last early F) on both grids.  Also: the Maxwell model's exact cooling-state a₂
    (:func:`maxwell_hcs_a2`), the first Sonine a₂
    (:func:`particles.sphere_observables.first_sonine_a2`) and the DSMC's relative difference
    from it, Haff's law T = (1 + ζ₀t/2)⁻² against the DSMC at the window's last time, and
    Haff's law with the first-order cooling rate ζ₀√T(1 + 3a₂/16) integrated with the solver's
    a₂(t).

    Claims tested (:func:`verdicts`): the solver equals the DSMC at early times (T and a₂) and
    in the cooling state (a₂); the Maxwell model's cooling state differs from hard spheres';
    the first Sonine approximation against the measured a₂; Haff's law fails once a₂ ≠ 0 and
    the a₂-corrected law holds at early times.  With ``hcs``, the tail
    (:func:`._hard_spheres_tail.measure`, row ``tail``): the Maxwell model's power law against
    the fitted exponential rate A, and A against 2K/ζ* (:func:`._hard_spheres_tail.verdicts`).
    At every size, the tail sampled by the DSMC in rescaled chunks
    (:func:`particles.cooling_state_sample.sample_cooling_state`, ``tail_seeds`` runs of
    ``tail_n`` particles, ``tail_snapshots`` snapshots each; row ``dsmc_tail``,
    :func:`._hard_spheres_dsmc_tail.measure`): the Maxwell model's power law against its fitted
    A, A against 2K/ζ* with the DSMC's own ζ*, and the solver's ζ* against the DSMC's
    (:func:`._hard_spheres_dsmc_tail.verdicts`).

    Parameters
    ----------
    size : str, optional
        ``"small"``, ``"default"`` or ``"full"`` (the presets of ``PRESETS``); None (default):
        :func:`maxwell_kinetics.app.comparisons.base.default_size`.
    progress : bool or None, optional
        Show progress of the DSMC runs (None, the default: a bar on a terminal or in a
        notebook, nothing otherwise).
    runner : object, optional
        Accepted for ``reproduce``; unused (the DSMC runs are not shared with other
        comparisons).
    **overrides
        Replace single parameters of the size's preset (e.g. ``seeds=4``).

    Returns
    -------
    maxwell_kinetics.app.comparisons.base.Comparison
        ``summary``: the numbers above with their uncertainties, the parameters used and the
        wall-clock ``seconds``; ``data``: the arrays its figure is drawn from.

    Raises
    ------
    particles.validation.InvalidArgumentError
        From :func:`maxwell_kinetics.app.comparisons.base.preset`: an unknown ``size`` or an
        override that is not a parameter of the preset; from the solver or the DSMC for
        parameters out of range.
    RuntimeError
        When a spectral solve, the cooling-state march or its Newton solve fails.
    """
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    cases = params["cases"]
    rows, data = [], []
    total = len(cases) * (int(params["seeds"]) + int(params["tail_seeds"]))
    with progress_bar(total, desc="hard-sphere DSMC", unit="run", enabled=progress) as bar:
        for dimension, primary, secondary in cases:
            row, curves = _case(params, dimension, primary, secondary, bar)
            rows.append(row)
            data.append(curves)
    summary = {"parameters": jsonable(params), "rows": rows,
               "seconds": time.perf_counter() - start}
    return Comparison(NAME, with_verdicts(summary, verdicts), {"rows": rows, "curves": data})


def _worst(row, q):
    """The early time whose solver-vs-DSMC deviation of ``q`` is largest in units of what is
    allowed (3 standard errors + the grid error): its index."""
    dev = [abs(s - m[0]) / (3.0 * m[1] + g) if (3.0 * m[1] + g) > 0 else math.inf
           for s, m, g in zip(row[f"solver_{q}"], row[f"dsmc_{q}"], row[f"grid_error_{q}"],
                              strict=True)]
    return int(np.argmax(dev))


def verdicts(s: dict) -> list:
    """The verdicts of comparison 13 from its summary ``s``, per dimension d: the solver's T and
    a₂ against the DSMC's at the early times (the time of the largest deviation; 3 standard
    errors of the seeds' mean plus the grid error); the solver's cooling-state a₂ against the
    DSMC's (not measured without the solver's cooling state); the Maxwell model's cooling-state
    a₂ differs from hard spheres'; the first Sonine a₂ against the DSMC's (relative
    difference); Haff's law fails at the window's end (T below it); Haff's law with the
    first-order a₂ correction holds at the last early time; where the cooling state's tail was
    measured, :func:`._hard_spheres_tail.verdicts`."""
    out = []
    params = s.get("parameters", {})
    seeds, n = int(params.get("seeds", 0)), params.get("n", "?")
    dof = seeds - 1 if seeds >= 2 else None
    from_seeds = f"seeds: standard error of the mean over {seeds} DSMC runs of N = {n}"
    for row in s["rows"]:
        d = row["dimension"]
        body = "hard spheres" if d == 3 else "hard disks"
        grids = f"grids {row['grid']} and {row['second_grid']}"
        for q, label in (("T", "T(t)"), ("a2", "a₂(t)")):
            i = _worst(row, q)
            t = row["times"][i]
            mean, err = pair(row[f"dsmc_{q}"][i])
            out.append(judge(
                f"{body}, d = {d}: the spectral solver's {label} is the DSMC's (early times)",
                Check(f"solver {label} at t = {t:g} (the largest deviation of "
                      f"{len(row['times'])} times), grid {row['grid']}", row[f"solver_{q}"][i],
                      None, mean, "model: DSMC of the same equation", expected_sigma=err,
                      expected_dof=dof, tolerance=row[f"grid_error_{q}"][i],
                      sigma_source=f"{from_seeds}; tolerance: the solver's grid error, the "
                                   f"distance between {grids}",
                      trials=len(row["times"])),
                short=f"d={d}: solver {label} = DSMC"))
        hcs, hcs_err = pair(row["dsmc_hcs_a2"])
        window = ", ".join(f"{c:g}" for c in row["window_collisions"])
        out.append(judge(
            f"{body}, d = {d}: the solver's cooling-state a₂ is the DSMC's",
            Check("a₂ of the solver's cooling state, grid " + str(row["grid"]),
                  row["solver_hcs_a2"], None, hcs,
                  f"model: DSMC, each seed's mean a₂ at {window} collisions per particle",
                  expected_sigma=hcs_err, expected_dof=dof,
                  tolerance=row["hcs_grid_error_a2"] or 0.0,
                  sigma_source=f"{from_seeds}; tolerance: the grid error of the cooling "
                               f"state, the distance between {grids}"),
            why="the solver's cooling state is computed at the default and full sizes only",
            resolution=Check("grids on which the solver's cooling state was computed",
                             row["hcs_grids"], None, 2, "exact: two grids give the grid error",
                             relation="at_least"),
            measured_at="default", short=f"d={d}: HCS a₂ solver = DSMC"))
        out.append(judge(
            f"{body}, d = {d}: the Maxwell model's cooling state is not hard spheres' "
            f"(a₂ differs)",
            Check("a₂ of the hard-sphere cooling state (DSMC window)", hcs, hcs_err,
                  row["maxwell_hcs_a2"], "exact: the Maxwell model's closed moment equations",
                  relation="differs", dof=dof, sigma_source=from_seeds),
            short=f"d={d}: Maxwell HCS a₂ ≠ HS"))
        rel, rel_err = pair(row["dsmc_hcs_a2_vs_first_sonine"])
        a3, a3_err = pair(row["dsmc_hcs_a3"])
        out.append(judge(
            f"{body}, d = {d}: the first Sonine approximation (van Noije–Ernst) gives the "
            f"cooling state's a₂",
            Check("relative difference a₂(DSMC)/a₂(first Sonine) − 1", rel, rel_err, 0.0,
                  f"model: first Sonine approximation (van Noije–Ernst), a₂ = "
                  f"{row['first_sonine_a2']:.5f}", dof=dof,
                  sigma_source=from_seeds + ", divided by the first Sonine a₂"),
            why="the first Sonine approximation drops the higher Sonine terms (a₃ = 0) and "
                "the terms of order a₂²; the measured a₃ is not 0",
            refutation=Check("a₃ of the hard-sphere cooling state (DSMC window)", a3, a3_err,
                             0.0, "model: the first Sonine approximation's a₃ = 0",
                             relation="differs", dof=dof, sigma_source=from_seeds),
            short=f"d={d}: HCS a₂ = first Sonine"))
        ratio, ratio_err = pair(row["dsmc_T_over_haff_last"])
        out.append(judge(
            f"{body}, d = {d}: Haff's law (a₂ = 0) overestimates T once a₂ > 0",
            Check(f"T(DSMC)/T(Haff) at {row['window_collisions'][-1]:g} collisions per "
                  f"particle", ratio, ratio_err, 1.0, "exact: Haff's law of a Maxwellian",
                  relation="below", dof=dof, sigma_source=from_seeds),
            short=f"d={d}: T below Haff's"))
        last = len(row["times"]) - 1
        mean, err = pair(row["dsmc_T"][last])
        out.append(judge(
            f"{body}, d = {d}: Haff's law with the cooling rate ζ₀√T(1 + 3a₂/16) holds at "
            f"early times",
            Check(f"T at t = {row['times'][last]:g}, Haff's law integrated with the solver's "
                  f"a₂(t)", row["corrected_haff_T"][last], None, mean,
                  "model: DSMC of the same equation", expected_sigma=err, expected_dof=dof,
                  tolerance=row["corrected_haff_grid_error"][last],
                  sigma_source=f"{from_seeds}; tolerance: the distance between the law "
                               f"integrated with the a₂(t) of {grids}"),
            short=f"d={d}: Haff+3a₂/16 = DSMC T"))
        out.extend(hs_tail.verdicts(row))
        out.extend(dsmc_tail.verdicts(row))
    return out


def plot(c, ax=None):
    """Three panels: a₂(t) of the solver (lines) and the DSMC (mean ± standard error) per d;
    T/T_Haff of the solver, the a₂-corrected Haff law and the DSMC (early and window); the
    cooling-state a₂ of hard spheres (DSMC, solver) against the Maxwell model's and the first
    Sonine approximation's.  One more where the solver's tail was measured
    (:func:`._hard_spheres_tail.draw`: ln F off the axes, the fit, the predicted rate and the
    Maxwell model's state and power law), and one more where the DSMC's was
    (:func:`._hard_spheres_dsmc_tail.draw`: ln F over its shells, its fit and the Maxwell
    model on the same shells).

    Parameters
    ----------
    c : maxwell_kinetics.app.comparisons.base.Comparison
        The comparison.
    ax : sequence of matplotlib.axes.Axes, optional
        One axis per panel (3, plus one per measured tail: the solver's, the DSMC's); default
        a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    rows, curves = c.data["rows"], c.data["curves"]
    tails = [any((r.get(key) or {}).get("measured") for r in rows)
             for key in ("tail", "dsmc_tail")]
    fig, axes = panels(3 + sum(tails), ax, width=5.2, height=4.6)
    ax1, ax2, ax3 = axes[:3]
    extra = iter(axes[3:])
    if tails[0]:
        hs_tail.draw(next(extra), rows, curves)
    if tails[1]:
        dsmc_tail.draw(next(extra), rows, curves)
    for i, (row, cur) in enumerate(zip(rows, curves, strict=True)):
        d, col = row["dimension"], f"C{i}"
        ax1.plot(cur["curve_t"], cur["solver_a2"], "-", color=col, label=f"d = {d}: solver")
        a2 = np.asarray(row["dsmc_a2"])
        ax1.errorbar(row["times"], a2[:, 0], yerr=a2[:, 1], fmt="o", ms=4, capsize=2,
                     color=col, label=f"d = {d}: DSMC ± 1 s.e.")
        ax2.plot(cur["curve_t"], cur["solver_T"] / cur["haff"], "-", color=col,
                 label=f"d = {d}: solver")
        ax2.plot(cur["curve_t"], cur["corrected_haff"] / cur["haff"], ":", color=col,
                 label=f"d = {d}: Haff with 3a₂/16")
        ratio = np.concatenate([cur["dsmc_T"] / np.asarray(row["haff_T"]),
                                cur["dsmc_window_T"] / cur["haff_window"]], axis=1)
        t = np.concatenate([cur["times"], cur["window_times"]])
        ax2.errorbar(t, ratio.mean(axis=0), ratio.std(axis=0, ddof=1) / math.sqrt(len(ratio)),
                     fmt="o", ms=4, capsize=2, color=col, label=f"d = {d}: DSMC")
        x = np.array([0.0, 1.0, 2.0]) + 3.5 * i
        hcs = row["dsmc_hcs_a2"]
        values = [hcs[0], row["first_sonine_a2"], row["maxwell_hcs_a2"]]
        ax3.bar(x, values, width=0.8, yerr=[hcs[1], 0.0, 0.0], color=[col, "0.6", "0.3"],
                capsize=3)
        for xi, value in zip(x, values, strict=True):
            ax3.text(xi, value + 0.01, f"{value:.3f}", ha="center", va="bottom", fontsize=8)
        if row["solver_hcs_a2"] is not None:
            ax3.plot(x[0], row["solver_hcs_a2"], "k_", ms=18, mew=2)
        for xi, text in zip(x, ("hard\nspheres", "first\nSonine", "Maxwell\nmodel"),
                            strict=True):
            ax3.text(xi, -0.02, f"{text}\nd = {d}", ha="center", va="top", fontsize=8)
    ax1.set(xlabel="t", ylabel="a₂", title="a₂(t) from the unit Maxwellian")
    ax1.legend()
    ax2.set(xscale="symlog", xlabel="t", ylabel="T / T_Haff",
            title="cooling against Haff's law")
    ax2.axhline(1.0, color="k", lw=0.5)
    ax2.legend(loc="lower left")
    ax3.set(xticks=[], ylabel="a₂ of the cooling state",
            title="cooling state (black bar: solver)")
    ax3.set_ylim(-0.14, 1.12 * max(r["maxwell_hcs_a2"] for r in rows) + 0.02)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=13))
