"""The tail of the hard-sphere cooling state measured by the DSMC in comparison ``hard_spheres``:
further out than the solver's grids resolve (d = 3 above all), with the DSMC's own cooling rate.

Conventions (those of :mod:`._hard_spheres_tail` and :mod:`particles.cooling_state_sample`).
c = (v − u)/√T, unit variance per component; F(c) with ∫F dc = 1; ζ* = −d ln T/dτ,
τ = ∫n√T dt.  The sample: :func:`particles.cooling_state_sample.sample_cooling_state`, ``seeds``
runs of N particles, each ``snapshots`` scaled states one chunk (about one collision per
particle) apart after 16 chunks of warm-up.

Measurement (:func:`measure`).  The pooled density over shells of :data:`BIN` = 0.25 in |c|
(each shell's |c| the mean of its speeds).  The profile is resolved up to the outer edge of the
last shell before the first one holding fewer than :data:`MIN_COUNTS` = 100 speeds (10 %
Poisson error or better in every shell used).  The window rule is the solver's with the DSMC's
shells: :data:`WINDOW_BINS` = 9.5 shells wide (W = 2.375), the outermost window whose copies
moved by ± W/4 stay inside the resolved profile, accepted only from |c| ≥ 3
(:data:`._hard_spheres_tail.TAIL_START`).  The fit is :func:`maxwell_kinetics.sphere_tail.fit_tail`
(ln F = a + μ ln c − A c, every shell weighted once); its σ is the jackknife over the seeds
(seeds − 1 dof: successive snapshots are correlated, the seeds are not), and the window
systematic is the fit's.  The predicted A = 2K/ζ* uses the sample's own ζ* (its σ propagated).
The Maxwell model's state (:func:`._hard_spheres_tail.maxwell_density`) is averaged over the
same shells and fitted on the same window; its two resolutions give its numerical error.

The cause shown when the Maxwell claim fails: the collision frequency ν(c) = K⟨|c − w|⟩ of a
particle at |c| in the sampled state (the hard-sphere rate; w over the sample's speeds, their
directions uniform), at the window's ends; the Maxwell model's is the same at every c.  That
claim is judged only where its check can tell the two tails apart
(:func:`._hard_spheres_tail.tells_apart`).
"""

from __future__ import annotations

import math
import time

import numpy as np

from particles.cooling_state_sample import CoolingStateSample, shell_volume
from particles.validation import InvalidArgumentError

from ...sphere_tail import RadialProfile, fit_tail, tail_rate
from . import _hard_spheres_tail as hs_tail
from .verdicts import Check, judge

__all__ = ["BIN", "MIN_COUNTS", "WINDOW_BINS", "resolved_speed", "dsmc_profile",
           "maxwell_shells", "mean_distance_over_directions", "collision_frequency_ratio",
           "measure", "verdicts", "draw"]

#: The shells' width in |c|.
BIN = 0.25
#: The fewest speeds (pooled over the seeds) in every shell of the resolved profile.
MIN_COUNTS = 100
#: The window's width in shells.
WINDOW_BINS = 9.5

_GAUSS = np.polynomial.legendre.leggauss(8)


def resolved_speed(counts, upper) -> float:
    """The outer edge of the last shell before the first one (from |c| = 0) holding fewer than
    :data:`MIN_COUNTS` speeds.

    Parameters
    ----------
    counts : array_like
        Speeds per shell, from |c| = 0.
    upper : array_like
        The shells' outer edges.

    Returns
    -------
    float
        0 when the first shell already holds too few.
    """
    counts, upper = np.asarray(counts), np.asarray(upper, dtype=float)
    short = np.flatnonzero(counts < MIN_COUNTS)
    last = (short[0] if short.size else counts.size) - 1
    return float(upper[last]) if last >= 0 else 0.0


def dsmc_profile(density: dict, resolved: float) -> RadialProfile:
    """The sample's shells as a :class:`maxwell_kinetics.sphere_tail.RadialProfile` (one
    'node' per shell, at its mean |c|, each shell weighted once).

    Parameters
    ----------
    density : dict
        :meth:`particles.cooling_state_sample.CoolingStateSample.density` (or a dict with its
        ``speed`` and ``density``, and ``density`` may be one seed's).
    resolved : float
        The |c| up to which the profile is complete.

    Returns
    -------
    maxwell_kinetics.sphere_tail.RadialProfile

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``density`` when no shell inside ``resolved`` holds a speed.
    """
    speed, dens = np.asarray(density["speed"], float), np.asarray(density["density"], float)
    keep = np.flatnonzero((np.asarray(density["upper"]) <= resolved + 1e-12) & (dens > 0))
    if not keep.size:
        raise InvalidArgumentError("density", "no shell holds a speed",
                                   "a sample with speeds inside the resolved profile")
    x, y = speed[keep], np.log(dens[keep])
    return RadialProfile(x, y, np.zeros_like(x), np.ones(x.size, dtype=int), BIN, 0.0,
                         float(resolved), x, y, np.arange(x.size))


def maxwell_shells(restitution: float, dimension: int, lower, upper, degree: int,
                   nodes: int) -> dict:
    """The Maxwell model's density averaged over the shells [lower, upper) (volume-weighted,
    8-point Gauss–Legendre in |c| per shell) and each shell's mean |c| under it.

    Parameters
    ----------
    restitution : float
        α.
    dimension : int
        d.
    lower, upper : array_like
        The shells' edges.
    degree, nodes : int
        The Maxwell fixed point's resolution (:func:`._hard_spheres_tail.maxwell_density`).

    Returns
    -------
    dict
        ``speed``, ``density``, ``lower`` and ``upper``.
    """
    a, b = np.asarray(lower, float), np.asarray(upper, float)
    x, w = _GAUSS
    c = 0.5 * (b - a)[:, None] * x[None, :] + 0.5 * (b + a)[:, None]
    weight = w[None, :] * 0.5 * (b - a)[:, None] * c ** (dimension - 1)
    F = hs_tail.maxwell_density(restitution, dimension, c.ravel(), degree,
                                nodes).reshape(c.shape)
    mass = np.sum(weight * F, axis=1)
    return {"speed": np.sum(weight * F * c, axis=1) / mass,
            "density": mass / np.sum(weight, axis=1),
            "lower": a, "upper": b}


def mean_distance_over_directions(c: float, s, dimension: int) -> np.ndarray:
    """⟨|c ê − s ŵ|⟩ over directions ŵ uniform on the unit sphere (d = 2: the trapezoid rule on
    2049 angles; d = 3: ((c + s)³ − |c − s|³)/(6cs)), for |c| = c > 0 and speeds s > 0.

    Parameters
    ----------
    c : float
        |c| > 0.
    s : array_like
        Speeds > 0.
    dimension : int
        d, 2 or 3.

    Returns
    -------
    numpy.ndarray
        One mean distance per speed.
    """
    s = np.asarray(s, dtype=float)
    if dimension == 3:
        return ((c + s) ** 3 - np.abs(c - s) ** 3) / (6.0 * c * s)
    theta = np.linspace(0.0, math.pi, 2049)
    dist = np.sqrt(c * c + s[:, None] ** 2 - 2.0 * c * s[:, None] * np.cos(theta)[None, :])
    return np.trapezoid(dist, theta, axis=1) / math.pi


def collision_frequency_ratio(counts, speeds, dimension: int, low: float,
                              high: float) -> float:
    """ν(high)/ν(low), ν(c) = K⟨|c − w|⟩ over a sample of speeds |w| binned as ``counts`` at
    mean speeds ``speeds`` (directions uniform: the state is isotropic).

    Parameters
    ----------
    counts : array_like
        Speeds per shell.
    speeds : array_like
        Each shell's mean |w| (ignored where a shell is empty).
    dimension : int
        d, 2 or 3.
    low, high : float
        The two |c| > 0.

    Returns
    -------
    float
    """
    counts, speeds = np.asarray(counts, float), np.asarray(speeds, float)
    full = counts > 0
    p, s = counts[full] / counts[full].sum(), speeds[full]
    low_rate, high_rate = (float(np.sum(p * mean_distance_over_directions(c, s, dimension)))
                           for c in (low, high))
    return high_rate / low_rate


def _jackknife(density, dimension, resolved, window, shift) -> float:
    """The jackknife standard error over the seeds of the fitted A on ``window``
    (``density``: :meth:`particles.cooling_state_sample.CoolingStateSample.density`)."""
    per_seed, totals = density["seed_counts"], density["seed_samples"]
    volume = shell_volume(density["lower"], density["upper"], dimension)
    rates = []
    for i in range(per_seed.shape[0]):
        counts = per_seed.sum(axis=0) - per_seed[i]
        left = dict(density, density=counts / ((totals.sum() - totals[i]) * volume))
        rates.append(fit_tail(dsmc_profile(left, resolved), window, shift=shift).rate)
    rates = np.asarray(rates)
    m = rates.size
    return float(math.sqrt((m - 1) / m * np.sum((rates - rates.mean()) ** 2)))


def _not_measured(record: dict, reason: str) -> tuple[dict, None]:
    record.update(measured=False, reason=reason)
    return record, None


def measure(sample: CoolingStateSample, kernel) -> tuple[dict, dict | None]:
    """The tail of the sampled cooling state and the Maxwell model's on the same shells
    (module docstring).

    Parameters
    ----------
    sample : particles.cooling_state_sample.CoolingStateSample
        The DSMC's sample (at least two seeds).
    kernel : particles.sphere_kernels.HardSpheres
        Its kernel (for K and the prediction 2K/ζ*).

    Returns
    -------
    record : dict
        JSON-able: the sample's ``n``, ``seeds``, ``snapshots``, ``samples``, ``seconds``;
        ``cooling_rate``, ``a2``, ``a3`` and ``collisions_per_snapshot`` as [mean, standard
        error over the seeds]; ``predicted_rate`` 2K/ζ* and its ``predicted_error``;
        ``resolved``; ``window``, ``shift``; ``measured`` (and ``reason`` when not); when
        measured ``fit`` (:meth:`maxwell_kinetics.sphere_tail.TailFit.to_dict`), ``rate``,
        ``rate_error`` (jackknife over the seeds), ``rate_dof``, ``fit_error``,
        ``window_systematic``, ``collision_rate`` (``speeds`` of the window's first and last
        shells, ``ratio`` ν(last)/ν(first) and its ``error`` over the seeds) and ``maxwell``
        (its fit on the same shells: ``rate``, ``rate_error``, ``rate_dof``,
        ``numerical_error``, ``difference``, ``difference_systematic``).
    figure : dict or None
        The panel's arrays (None when not measured).

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``sample`` when it holds fewer than two seeds.
    RuntimeError
        When a Maxwell fixed point does not converge.
    """
    start = time.perf_counter()
    p = sample.parameters
    seeds = len(p["seeds"])
    if seeds < 2:
        raise InvalidArgumentError("sample", f"{seeds} seed", "a sample of at least two seeds")
    d, alpha = int(p["dimension"]), float(p["restitution"])
    merge = int(round(BIN / float(p["bin_width"])))
    density = sample.density(merge)
    zeta = sample.seed_values("cooling_rate")
    predicted = tail_rate(kernel, d, zeta[0])
    resolved = resolved_speed(density["counts"], density["upper"])
    width = WINDOW_BINS * BIN
    shift = 0.25 * width
    hi = resolved - shift
    lo = hi - width
    record = {"n": p["n"], "seeds": seeds, "snapshots": p["snapshots"],
              "samples": sample.samples, "sample_seconds": sample.seconds,
              "bin": BIN, "min_counts": MIN_COUNTS, "window_bins": WINDOW_BINS,
              "tail_start": hs_tail.TAIL_START, "resolved": resolved, "window": [lo, hi],
              "shift": shift, "predicted_rate": predicted,
              "predicted_error": predicted * zeta[1] / zeta[0],
              **{name: list(sample.seed_values(name))
                 for name in ("cooling_rate", "a2", "a3", "collisions_per_snapshot")}}
    if lo < hs_tail.TAIL_START:
        return _not_measured(record, (
            f"the sample's shells hold {MIN_COUNTS} speeds or more only up to |c| = "
            f"{resolved:.3g}: a window of {WINDOW_BINS:g} shells (W = {width:.3g}) moved by "
            f"±W/4 starts at {lo:.3g}, below |c| = {hs_tail.TAIL_START:g}"))
    profile = dsmc_profile(density, resolved)
    fit = fit_tail(profile, (lo, hi), shift=shift, predicted=predicted)
    jack = _jackknife(density, d, resolved, (lo, hi), shift)
    inside = np.flatnonzero((profile.speed >= lo) & (profile.speed <= hi))
    ends = profile.speed[inside[[0, -1]]]
    per_seed = density["seed_counts"]
    ratios = np.array([collision_frequency_ratio(row, density["speed"], d, *ends)
                       for row in per_seed])
    kept = np.asarray(density["upper"]) <= resolved + 1e-12
    lower, upper = density["lower"][kept], density["upper"][kept]
    maxwell_profiles = []
    for degree, nodes in hs_tail.MAXWELL_DEGREES:
        shells = maxwell_shells(alpha, d, lower, upper, degree, nodes)
        maxwell_profiles.append(dsmc_profile(shells, resolved))
    m_fits = [fit_tail(m, (lo, hi), shift=shift) for m in maxwell_profiles]
    moved = [a - b for a, b in zip(fit.moved_rates, m_fits[0].moved_rates, strict=True)]
    difference = fit.rate - m_fits[0].rate
    record.update(
        measured=True, reason="", fit=fit.to_dict(), rate=fit.rate, rate_error=jack,
        rate_dof=seeds - 1, fit_error=fit.rate_error, window_systematic=fit.window_systematic,
        collision_rate={"speeds": ends.tolist(), "ratio": float(ratios.mean()),
                        "error": float(ratios.std(ddof=1) / math.sqrt(seeds))},
        maxwell={"rate": m_fits[0].rate, "rate_error": m_fits[0].rate_error,
                 "rate_dof": m_fits[0].shells - 3,
                 "numerical_error": abs(m_fits[0].rate - m_fits[1].rate),
                 "difference": difference,
                 "difference_systematic": max(abs(m - difference) for m in moved)},
        seconds=time.perf_counter() - start)
    figure = {"speed": profile.speed, "log_density": profile.log_density,
              "maxwell_speed": maxwell_profiles[0].speed,
              "maxwell_log_density": maxwell_profiles[0].log_density}
    return record, figure


def verdicts(row: dict) -> list:
    """The claims of one dimension's row on the DSMC's tail (``row["dsmc_tail"]``).

    * "the Maxwell model's power-law tail is the hard-sphere tail (DSMC)": the fitted A
      against the Maxwell model's A on the same shells and window, σ the jackknife over the
      seeds (seeds − 1 dof) and the Maxwell fit's error (n − 3 dof), Student's t; tolerance the
      window systematic of the difference and the Maxwell state's numerical error; refuted
      when it fails and ν(c) = K⟨|c − w|⟩ of the sampled state differs between the window's
      ends (the Maxwell model's is the same at every c); ``not measured`` when the deviation
      its check allows is not below |2K/ζ* − A_Maxwell|
      (:func:`._hard_spheres_tail.tells_apart`);
    * "A = 2K/ζ* (DSMC)": the fitted A against 2K/ζ* with the sample's ζ*, tolerance the window
      systematic; ``not measured`` while the window starts before the crossover 2A
      (:func:`._hard_spheres_tail.beyond_crossover`: the fit measures the crossover there,
      and a noisy fit can look stable) or the window systematic exceeds the jackknife error;
    * "the solver's cooling rate ζ* is the DSMC's": tolerance the solver's grid difference of
      ζ*; ``not measured`` without the solver's cooling state.

    The first two are ``not measured`` where no window is accepted.

    Parameters
    ----------
    row : dict
        A row of the comparison's summary with ``dimension``, ``grid``, ``second_grid``, the
        solver's ``solver_hcs_cooling_rate``, ``hcs_grid_error_cooling_rate``, ``hcs_grids``
        and ``dsmc_tail``.

    Returns
    -------
    list of maxwell_kinetics.app.comparisons.verdicts.Verdict
        Empty when the row has no ``dsmc_tail``.
    """
    tail = row.get("dsmc_tail")
    if not tail:
        return []
    d = row["dimension"]
    body, name = ("hard spheres", "hard-sphere") if d == 3 else ("hard disks", "hard-disk")
    seeds, dof = tail["seeds"], tail["seeds"] - 1
    sample = (f"{seeds} DSMC runs of N = {tail['n']}, {tail['snapshots']} snapshots each "
              f"({tail['samples']:.3g} speeds)")
    measured = bool(tail.get("measured"))
    lo, hi = tail["window"]
    window = (f"|c| ∈ [{lo:.2f}, {hi:.2f}]" if lo >= hs_tail.TAIL_START
              else f"the rule's outermost window (none from |c| ≥ {hs_tail.TAIL_START:g})")
    placed = Check(f"start of the outermost window of {WINDOW_BINS:g} shells of {BIN:g} "
                   f"(each of ≥ {MIN_COUNTS} speeds up to |c| = {tail['resolved']:.2f})", lo,
                   None, hs_tail.TAIL_START, "exact: the window rule (three thermal speeds)",
                   relation="at_least")
    quantity = f"fitted A of ln F = a + μ ln c − A c, DSMC shells, {window}"
    bigger = "a larger sample than this size's"
    rate = tail.get("rate") if measured else None
    sigma = tail.get("rate_error") if measured else None
    jack = f"seeds: jackknife over the {sample}"
    if measured:
        maxwell = tail["maxwell"]
        claim = Check(
            quantity, rate, sigma, maxwell["rate"],
            "model: the Maxwell model's exact scaled state (Fourier fixed point) averaged over "
            "the same shells and fitted the same way (a pure power law gives A = 0)",
            expected_sigma=maxwell["rate_error"], dof=dof, expected_dof=maxwell["rate_dof"],
            t_law=True,
            tolerance=maxwell["difference_systematic"] + maxwell["numerical_error"],
            sigma_source=f"{jack}; the Maxwell fit's error (n − 3 dof); tolerance: the window "
                         f"systematic of the difference (windows moved by "
                         f"±{tail['shift']:.2f}), the difference of two fixed-point "
                         f"resolutions")
        rates = tail["collision_rate"]
        a, b = rates["speeds"]
        refutation = Check(
            f"collision frequency ν = K⟨|c − w|⟩ of the sampled {name} cooling state at "
            f"|c| = {b:.2f} over ν at {a:.2f}", rates["ratio"], rates["error"], 1.0,
            "exact: the Maxwell model's rate, the same at every c", relation="differs",
            dof=dof, sigma_source=f"seeds: standard error of the mean over {seeds} runs")
        why = (f"a fast particle's collision frequency grows like |c| under the hard-sphere "
               f"rate |g| (ν rises by {rates['ratio']:.3f} across the window), so the tail "
               f"falls exponentially; the Maxwell model's constant rate leaves a power law")
        resolves, why = hs_tail.maxwell_claim_resolution(claim, tail["predicted_rate"],
                                                         maxwell["rate"], why, "this sample")
    else:
        claim = Check(quantity, None, None, 0.0,
                      "model: the Maxwell model's power law (A = 0 in this fit)", dof=dof,
                      sigma_source=jack)
        refutation, why, resolves = None, tail.get("reason") or "", placed
    out = [judge(
        f"{body}, d = {d}: the Maxwell model's power-law tail c^(−d−2s*) is the {name} "
        f"cooling state's tail (measured by the DSMC)", claim, why=why, refutation=refutation,
        resolution=resolves, measured_at="default",
        short=f"d={d}: Maxwell tail = HS tail (DSMC)")]
    drift = Check(f"window systematic of the fitted A (window moved by ±{tail['shift']:.2f})",
                  tail.get("window_systematic") if measured else None, None,
                  sigma if sigma is not None else 0.0,
                  "exact: at most the jackknife error (the fit is stable under the window's "
                  "move)", relation="at_most")
    why_rate = tail.get("reason") or ""
    if measured:
        why_rate = (f"the fitted A still drifts with the window: moving it by "
                    f"±{tail['shift']:.2f} changes A by {tail['window_systematic']:.3f}, more "
                    f"than its error {sigma:.3f} (A = {rate:.3f} on {window} against "
                    f"2K/ζ* = {tail['predicted_rate']:.3f})")
        drift, why_rate = hs_tail.rate_claim_resolution(lo, tail["predicted_rate"], rate,
                                                        window, drift, why_rate)
    out.append(judge(
        f"{body}, d = {d}: the cooling state's tail is exp(−A c) with A = 2K/ζ* "
        f"(Esipov–Pöschel, van Noije–Ernst; measured by the DSMC)",
        Check(quantity, rate, sigma, tail["predicted_rate"],
              "model: A = 2K/ζ* with the DSMC's own ζ*",
              expected_sigma=tail["predicted_error"], dof=dof, expected_dof=dof,
              t_law=measured, tolerance=tail["window_systematic"] if measured else 0.0,
              sigma_source=f"{jack}; ζ*: seeds; tolerance: the window systematic (window "
                           f"moved by ±{tail['shift']:.2f})"),
        why=why_rate, resolution=drift if measured else placed,
        measured_at=bigger if measured else "default",
        short=f"d={d}: HS tail A = 2K/ζ* (DSMC)"))
    zeta, zeta_err = tail["cooling_rate"]
    solver = row.get("solver_hcs_cooling_rate")
    out.append(judge(
        f"{body}, d = {d}: the solver's cooling-state cooling rate ζ* is the DSMC's",
        Check(f"ζ* = −d ln T/dτ of the solver's cooling state, grid {row['grid']}", solver,
              None, zeta, f"model: DSMC, each run's mean over {tail['snapshots']} chunks",
              expected_sigma=zeta_err, expected_dof=dof, t_law=True,
              tolerance=row.get("hcs_grid_error_cooling_rate") or 0.0,
              sigma_source=f"seeds: standard error of the mean over {seeds} runs; tolerance: "
                           f"the grid error of ζ*, the distance between grids {row['grid']} "
                           f"and {row['second_grid']}"),
        why="the solver's cooling state is computed at the default and full sizes only",
        resolution=Check("grids on which the solver's cooling state was computed",
                         row.get("hcs_grids", 0), None, 2,
                         "exact: two grids give the grid error", relation="at_least"),
        measured_at="default", short=f"d={d}: HCS ζ* solver = DSMC"))
    return out


def draw(ax, rows, curves) -> bool:
    """The DSMC's tail panel: ln F over its shells (open squares), the fit over its window and
    the Maxwell model's state averaged over the same shells, per d.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    rows, curves : list
        The comparison's rows and figure data (``curves[i]["dsmc_tail"]``).

    Returns
    -------
    bool
        Whether a measured DSMC tail was drawn.
    """
    drawn = False
    for i, (row, cur) in enumerate(zip(rows, curves, strict=True)):
        tail, data = row.get("dsmc_tail") or {}, cur.get("dsmc_tail")
        if not tail.get("measured") or data is None:
            continue
        drawn, col, d = True, f"C{i}", row["dimension"]
        fit = tail["fit"]
        ax.plot(data["speed"], data["log_density"], "s", ms=3.5, mfc="none", color=col,
                label=f"d = {d}: DSMC ({tail['samples']:.2g} speeds)")
        lo, hi = tail["window"]
        c = np.linspace(lo, hi, 40)
        ax.plot(c, fit["amplitude"] + fit["power"] * np.log(c) - fit["rate"] * c, "-",
                color=col, lw=2.5, alpha=0.5,
                label=f"DSMC fit A = {fit['rate']:.2f} ± {tail['rate_error']:.2f} ± "
                      f"{fit['window_systematic']:.2f} (2K/ζ* = {tail['predicted_rate']:.2f})")
        ax.axvspan(lo, hi, color=col, alpha=0.05)
        ax.plot(data["maxwell_speed"], data["maxwell_log_density"], "-.", color=col, lw=1,
                label=f"d = {d}: Maxwell model on the same shells")
    if drawn:
        ax.set(xlabel="|c| (unit variance per component)", ylabel="ln F",
               title="tail of the cooling state: DSMC (shaded: windows)")
        low, high = ax.get_ylim()
        ax.set_ylim(low, high + 0.6 * (high - low))  # room for the legend above the curves
        ax.legend(loc="upper right", fontsize=7)
    return drawn
