"""Comparison: the driven (heated) 1D Maxwell model in its non-equilibrium steady state, kinetic
theory (:mod:`maxwell_kinetics.driven`) against the driven Ulam particles.

    ∂τP̂(k) + (1 + D k²) P̂(k) = P̂(pk) P̂(qk),   q = 1 − p

Steady state: ⟨v²⟩ = D/(pq), kurtosis 3 + 6pq/(2 − pq) (exact cumulants), tail
P ∝ exp(−|v|/√D).  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.observables import Histogram, histogram_from_counts, mean_sem_json

from ...driven import steady_state
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import panels
from .particle_runs import ParticleRuns
from .verdicts import Check, judge, pair, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts"]

NAME = "driven_steady"

PRESETS = {
    "small": {"restitutions": (0.0, 0.5), "driving": 1.0, "n": 20_000, "seeds": 16,
              "tau": 60.0, "bin_width": 0.25},
    "default": {"restitutions": (0.0, 0.5, 0.9), "driving": 1.0, "n": 100_000, "seeds": 8,
                "tau": 100.0, "bin_width": 0.2},
    "full": {"restitutions": (0.0, 0.5, 0.9), "driving": 1.0, "n": 1_000_000, "seeds": 8,
             "tau": 200.0, "bin_width": 0.1},
}




def run(size=None, progress: bool | None = None, runner=None, **overrides) -> Comparison:
    """For each r: the exact steady variance D/(pq) (with the finite-N factor (1 − 1/N)² of a
    gas of zero total momentum) and kurtosis against the particles' (mean ± standard error:
    the seed scatter for the kurtosis, the larger of the seed scatter and the pooled particles'
    error for the variance; in units of that error); the steady density P(v) against the
    pooled particle histogram (χ²/dof, binomial errors of the pooled counts, bins with ≥ 10
    counts); the tail slope of ln P on |v|/√D ∈ [3, 6], particles against the exact density on
    the same window (the asymptotic −1/√D is reported too).  The runs start from a unit
    Gaussian and are taken at τ = ``tau``: the slowest relaxation, of ⟨v²⟩, is e^{−2pqτ}
    (r = 0.9: 2pq = 0.095, e^{−9.5} at τ = 100; the small size takes r ≤ 0.5 only).

    Claim tested: the heated 1D Maxwell model has a steady state with variance D/(pq), kurtosis
    3 + 6pq/(2 − pq) and an exponential tail P ∝ e^{−|v|/√D}.  Compared: the exact steady state
    (:func:`maxwell_kinetics.driven.steady_state`) against driven Ulam particles.

    Parameters
    ----------
    size : str, optional
        ``"small"``, ``"default"`` or ``"full"`` (the presets of ``PRESETS``); None (default):
        :func:`maxwell_kinetics.app.comparisons.base.default_size`.
    progress : bool or None, optional
        Show progress of the runs and solves (None, the default: a bar on a terminal or in a
        notebook, nothing otherwise).
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
    d, n = float(params["driving"]), int(params["n"])
    seeds = tuple(range(int(params["seeds"])))
    rows, curves = [], []
    for r in params["restitutions"]:
        theory = steady_state(r, d)
        v = runner.ulam_final({"n": n, "restitution": float(r), "driving": d}, params["tau"], seeds,
                              progress=progress)
        var_exact = theory.variance * (1.0 - 1.0 / n) ** 2
        m2 = np.mean(v * v, axis=1)
        kurt = np.mean(v**4, axis=1) / m2**2
        sd = math.sqrt(theory.variance)
        width = params["bin_width"] * sd
        edges = np.arange(-8 * sd, 8 * sd + width / 2, width)
        # pooled histogram; binomial errors of the pooled counts (in the steady state of the
        # mean-field model the particles of one run are nearly independent)
        counts = np.sum([np.histogram(row, edges)[0] for row in v], axis=0)
        total = v.size
        particles_h = histogram_from_counts(edges, counts, total, 1.0)
        dens = particles_h.density
        centres = particles_h.centres
        exact = np.interp(centres, theory.velocity, theory.density)
        exact_h = Histogram(edges, centres, exact, np.zeros(centres.size),
                            np.zeros(centres.size, dtype=np.int64), 0, 1.0)
        # χ²/dof with the binomial errors of the pooled counts, bins with ≥ 10 counts
        distance = particles_h.distance(exact_h, min_count=10)
        chi2, ok = distance.chi2_dof, distance.bins
        # tail: slope of ln P on |v|/√D ∈ [3, 6], particles and theory on the same window (the
        # asymptotic slope −1/√D is reached further out: the next poles add e^{−|v|/(p√D)})
        w = np.abs(centres) / math.sqrt(d)
        tail = (w >= 3) & (w <= 6) & (counts >= 10)
        slope = float(np.polyfit(np.abs(centres[tail]), np.log(dens[tail]), 1)[0])
        slope_theory = float(np.polyfit(np.abs(centres[tail]), np.log(exact[tail]), 1)[0])
        var_p, kurt_p = mean_sem_json(m2), mean_sem_json(kurt)
        # The seed scatter of a few runs can come out small by chance (4 runs: 3 degrees of
        # freedom); the particles of one steady run are nearly independent, so the error of the
        # pooled ⟨v²⟩ is also sqrt(Var(v²) / (N R)): the larger of the two is used.
        pooled = float(np.std(v * v) / math.sqrt(v.size))
        from_seeds = (var_p[1] or 0.0) >= pooled
        var_p[1] = max(var_p[1] or 0.0, pooled)
        rows.append({
            "restitution": float(r), "variance_exact": var_exact, "variance": var_p,
            "variance_in_sigma": (var_p[0] - var_exact) / var_p[1],
            "variance_error_from": "seeds" if from_seeds else "pooled particles",
            "kurtosis_exact": theory.kurtosis, "kurtosis": kurt_p,
            "kurtosis_in_sigma": (kurt_p[0] - theory.kurtosis) / kurt_p[1],
            "density_chi2_per_dof": chi2, "bins": int(ok.sum()),
            "tail_slope": slope, "tail_slope_theory_same_window": slope_theory,
            "tail_slope_asymptotic": -1.0 / math.sqrt(d),
        })
        curves.append({"x": theory.velocity, "P": theory.density, "centres": centres,
                       "density": dens, "error": particles_h.error})
    summary = {"parameters": jsonable(params), "rows": rows,
               "seconds": time.perf_counter() - start}
    return Comparison(NAME, with_verdicts(summary, verdicts), {"curves": curves, "rows": rows})


def verdicts(s: dict) -> list:
    """The verdicts of the driven comparison from its summary ``s``: per r, the variance and
    the kurtosis of the particles against the exact steady state (σ over seeds: the quantile of
    Student's t with seeds − 1 degrees of freedom at the coverage of 3σ, 3.59σ for the 16
    seeds of the small size, 4.53σ for 8; the variance's σ is the larger of the seeds' and the
    pooled particles', 3σ when the pooled particles' is, see :func:`run`)."""
    out = []
    seeds = int(s.get("parameters", {}).get("seeds", 0))  # 0: not recorded
    for row in s["rows"]:
        r = row["restitution"]
        for q, label in (("variance", "variance D/(pq)"), ("kurtosis", "kurtosis")):
            value, err = pair(row[q])
            # a summary of before the record of the variance's σ: the seeds' (the fewer dof)
            pooled = q == "variance" and row.get("variance_error_from") == "pooled particles"
            where = (f"pooled particles: std(v²)/√(N·{seeds}), larger than the seeds' scatter"
                     if pooled else f"seeds: standard error over {seeds} runs")
            out.append(judge(f"driven 1D Maxwell gas: steady {label}, r = {r:g}",
                             Check(f"{q} of the driven Ulam particles", value, err,
                                   row[f"{q}_exact"], "exact: steady state",
                                   dof=None if pooled or seeds < 2 else seeds - 1,
                                   sigma_source=where, t_law=True)))
    return out


def plot(c, ax=None):
    """ln P(v) of theory (lines) and particles (points ± error) for each r; the Gaussian of the
    same variance dashed."""
    own = ax is None
    fig, (ax,) = panels(1, ax, width=6.0)
    for i, (row, cur) in enumerate(zip(c.data["rows"], c.data["curves"], strict=True)):
        keep = cur["P"] > 1e-9
        ax.semilogy(cur["x"][keep], cur["P"][keep], color=f"C{i}", lw=1,
                    label=f"r = {row['restitution']:g}: theory, kurtosis "
                          f"{row['kurtosis_exact']:.3f}")
        good = cur["density"] > 0
        ax.errorbar(cur["centres"][good], cur["density"][good], yerr=cur["error"][good], fmt=".",
                    ms=3, color=f"C{i}", label=f"particles, kurtosis {row['kurtosis'][0]:.3f}")
        var = row["variance_exact"]
        g = np.exp(-0.5 * cur["x"] ** 2 / var) / math.sqrt(2 * math.pi * var)
        ax.semilogy(cur["x"][g > 1e-9], g[g > 1e-9], "--", color=f"C{i}", lw=0.6)
    ax.set(xlabel="v", ylabel="P(v)", title="driven Maxwell model: steady state (dashed: Gaussian)")
    ax.legend(fontsize=6)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=11))
