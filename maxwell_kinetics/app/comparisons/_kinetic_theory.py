"""Comparison 1, kinetic theory alone: G(q, τ) → f̂ with the contraction bound, the moment
hierarchy and the x⁻⁴ tail of P(x, τ).  ``run`` computes, ``plot`` draws."""

from __future__ import annotations

import math
import time

import numpy as np

from particles.validation import InvalidArgumentError

from ...exact import f_density, f_hat, rescaled_moments
from ...model import MaxwellModel
from .base import Comparison, ComparisonSpec, jsonable, preset, register
from .drawing import colors, panels
from .kinetic_predictions import kinetic_solution
from .verdicts import Check, judge, with_verdicts

__all__ = ["NAME", "PRESETS", "run", "plot", "verdicts"]

NAME = "kinetic_theory"

PRESETS = {
    "small": {"restitution": 0.5, "law": "gaussian",
              "tau": (0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0), "s": (2.2, 2.5, 2.8),
              "moments_tau_max": 100.0, "tail_window": (5.0, 15.0)},
    "default": {"restitution": 0.5, "law": "gaussian",
                "tau": (0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0),
                "s": (2.2, 2.5, 2.8), "moments_tau_max": 200.0, "tail_window": (5.0, 15.0)},
    "full": {"restitution": 0.5, "law": "gaussian",
             "tau": (0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, 3000.0,
                     10000.0),
             "s": (2.2, 2.5, 2.8), "moments_tau_max": 200.0, "tail_window": (5.0, 15.0)},
}


_GAUSSIAN_MOMENTS = [1.0, 0.0, 1.0, 0.0, 3.0, 0.0, 15.0, 0.0, 105.0]


#: The contraction bound is checked where it is at least this large: about 80x the largest
#: d_s floor of the coarse grid (1.3e-7, s = 2.8).
_BOUND_CHECKED_ABOVE = 1e-5


def run(size=None, progress: bool | None = None, runner=None, **overrides) -> Comparison:
    """Comparison 1: G(q, τ) → f̂, sup|G − f̂| and d_s(G, f̂) against τ with the contraction
    bound d_s(τ) ≤ e^{−γ(s)τ} d_s(0) (checked at the saved τ > 0 where the bound is ≥ 1e-5,
    above the solver's floor; ``max_distance_over_bound`` is the largest d_s/bound there, τ = 0
    excluded since the ratio is 1 there by construction), the moment hierarchy (multiscaling
    of M_n/M_2^{n/2}) and P(x, τ) developing the x⁻⁴ tail (fitted log-log slope on
    ``tail_window``).

    Claim tested: the 1D inelastic Maxwell gas, rescaled by its own velocity scale, approaches
    the scaling solution f̂(q) = (1 + q) e^{−q} (the density 2/(π(1 + x²)²), with an x⁻⁴ tail)
    for every r < 1, and its moments multiscale.  Compared: the kinetic solver's G(q, τ)
    against f̂ and the contraction bound, and the fitted moment growth rates against the exact
    ones.

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
        override that is not a parameter of the preset; naming ``law``, if the law is not
        ``"gaussian"`` (the moment hierarchy needs its exact moments).
    """
    start = time.perf_counter()
    params = preset(PRESETS, size, overrides)
    model = MaxwellModel(params["restitution"])
    sol = kinetic_solution(model.restitution, params["law"], params["tau"], progress=progress)
    taus = np.asarray(sol.tau)
    sup = sol.sup_error()
    q_low = 1e-4
    dist, bounds, ratio, checked_to = {}, {}, {}, {}
    for s in params["s"]:
        d = sol.fourier_distance(s, q_low=q_low)
        bound = d[0] * np.exp(-model.contraction_rate(s) * taus)
        dist[s], bounds[s] = d, bound
        # Where the bound has fallen under the solver's floor it cannot be checked: only τ with
        # bound ≥ _BOUND_CHECKED_ABOVE count (the coarse grid's d_s floors, measured at τ = 10⁴
        # for r = 0.5: 9.2e-9, 2.6e-8, 1.3e-7 for s = 2.2, 2.5, 2.8).
        # τ = 0 is left out: there d/bound = 1 by construction (the bound starts at d_s(0)).
        checked = (bound >= _BOUND_CHECKED_ABOVE) & (taus > 0)
        if checked.any():
            ratio[s] = float(np.max(d[checked] / bound[checked]))
            checked_to[s] = float(taus[checked][-1])
        else:  # no saved τ > 0 where the bound is above the floor (e.g. an override tau=(0,))
            ratio[s] = checked_to[s] = None
    # Moments: the exact hierarchy from the law's moments (Gaussian only: known in closed form).
    if params["law"] != "gaussian":
        raise InvalidArgumentError("law", params["law"], "'gaussian' (moments known exactly)")
    mt = np.linspace(0.0, params["moments_tau_max"], 201)
    resc = rescaled_moments(model, _GAUSSIAN_MOMENTS, mt)
    late = mt >= 0.5 * mt[-1]
    growth = {}
    for n in (4, 6, 8):
        slope = float(np.polyfit(mt[late], np.log(resc[late, n]), 1)[0])
        predicted = n / 2 * model.moment_rate(2) - model.moment_rate(n)
        growth[str(n)] = {"fitted": slope, "predicted": predicted}
    # Densities and tail slopes.
    x = np.geomspace(0.05, 30.0, 160)
    dens = np.array([sol.density(x, k)[1] for k in range(len(taus))])
    lo, hi = params["tail_window"]
    sel = (x >= lo) & (x <= hi)
    tails = []
    for k in range(len(taus)):
        pk = dens[k, sel]
        tails.append(float(np.polyfit(np.log(x[sel]), np.log(pk), 1)[0]) if np.all(pk > 0)
                     else None)
    f_slope = float(np.polyfit(np.log(x[sel]), np.log(f_density(x[sel])), 1)[0])
    summary = {
        "parameters": jsonable(params),
        "tau": taus.tolist(),
        "sup_error": sup.tolist(),
        "fourier_distance": {str(s): dist[s].tolist() for s in params["s"]},
        "contraction_rate": {str(s): model.contraction_rate(s) for s in params["s"]},
        "max_distance_over_bound": {str(s): ratio[s] for s in params["s"]},
        "bound_checked_where_above": _BOUND_CHECKED_ABOVE,
        "bound_checked_up_to_tau": {str(s): checked_to[s] for s in params["s"]},
        "fourier_distance_q_low": q_low,
        "moment_growth_rates": growth,
        "tail_slope": tails,
        "tail_slope_of_f": f_slope,
        "solver_seconds": sol.seconds,
        "seconds": time.perf_counter() - start,
    }
    data = {"solution": sol, "bounds": bounds, "distances": dist, "moment_tau": mt,
            "moments": resc, "x": x, "density": dens}
    return Comparison(NAME, with_verdicts(summary, verdicts), data)


#: The coarse grid's error floor of sup_q |G − f̂|, by r: the solver started at the fixed point
#: (f̂ to 1e-12), the largest sup_q |G − f̂| over τ ∈ {10, 100, 1000} (benchmarks/README.md,
#: "error floor" table; benchmarks/solver_floor.json).  The floor grows with r; an r between
#: two entries takes the larger one's floor, an r above 0.99 the largest.
_COARSE_FLOORS = {0.0: 1.93e-8, 0.5: 7.35e-8, 0.9: 4.15e-6, 0.99: 3.72e-5}
#: The solver's floor moves with where an output falls on the comoving grid: up to 1.58 times
#: its value at τ = 10³ over τ ∈ [10³, 10⁴] (the convergence table's last column).  Allowed:
#: twice the floor.
_FLOOR_FACTOR = 2.0


def sup_floor(restitution: float) -> float:
    """The coarse grid's error floor of sup_q |G − f̂| at ``restitution`` (see
    :data:`_COARSE_FLOORS`)."""
    above = [f for r, f in _COARSE_FLOORS.items() if r >= restitution]
    return min(above) if above else max(_COARSE_FLOORS.values())


def _transient_at_last(s: dict) -> float | None:
    """sup|G − f̂| of the previous saved τ decayed to the last τ at the rate measured between
    the two before it: what remains of the approach to f̂ at the last τ (None with fewer than
    three saved τ > 0)."""
    taus, sup = s["tau"], s["sup_error"]
    if len(taus) < 4 or min(sup[-3:-1]) <= 0:
        return None
    rate = math.log(sup[-3] / sup[-2]) / (taus[-2] - taus[-3])
    return sup[-2] * math.exp(-max(rate, 0.0) * (taus[-1] - taus[-2]))
#: Relative tolerance of a fitted moment growth rate: the fit over τ ≥ τ_max/2 still carries
#: the subleading exponentials (measured 3.5e-3 for n = 4 at τ_max = 100, 4e-5 at 200).
_GROWTH_RELATIVE_TOLERANCE = 0.01
#: Tolerance of the tail slope of P(x, τ) at the last τ against f's on the same window.
_TAIL_SLOPE_TOLERANCE = 0.05


def verdicts(s: dict) -> list:
    """The verdicts of comparison 1 from its summary ``s``: G → f̂ (sup error at the last τ
    within twice the coarse grid's error floor, :func:`sup_floor`; ``not measured`` where the
    approach to f̂ is still above that floor at the last τ: the small size, τ ≤ 100),
    the contraction bound, the multiscaling of the moments, and the x⁻⁴ tail."""
    r = s["parameters"]["restitution"]
    tau_last = s["tau"][-1]
    allowed = _FLOOR_FACTOR * sup_floor(r)
    floor_text = (f"the solver's error floor ({_FLOOR_FACTOR:g} × {sup_floor(r):.3g}, coarse "
                  f"grid, r = {r:g}: the solver started at f̂)")
    out = [judge(
        f"the exact scaling solution: G(q, τ) of the kinetic equation tends to "
        f"f̂(q) = (1 + |q|) e^(−|q|), r = {r:g}",
        Check(f"sup_q |G − f̂| at τ = {tau_last:g}", s["sup_error"][-1], None, 0.0,
              "exact: f̂ is the scaling solution", tolerance=allowed, relation="at_most",
              sigma_source="none (deterministic); tolerance: " + floor_text),
        why="the approach to f̂ is still above the solver's floor at the last τ",
        resolution=Check("sup|G − f̂| left of the approach at the last τ (the previous τ's, "
                         "decayed at the rate between the two before)",
                         _transient_at_last(s), None, 0.0, "exact: the floor " + floor_text,
                         tolerance=allowed, relation="at_most"),
        measured_at="default")]
    ratios = [v for v in s["max_distance_over_bound"].values() if v is not None]
    out.append(judge(
        "the Fourier distance contracts: d_s(τ) ≤ e^(−γ(s)τ) d_s(0) for s = "
        + ", ".join(s["max_distance_over_bound"]),
        Check("max over s and τ of d_s / bound", max(ratios) if ratios else None, None, 1.0,
              "exact: contraction bound (rigorous)", tolerance=1e-9, relation="at_most")))
    for n, g in s["moment_growth_rates"].items():
        out.append(judge(
            f"multiscaling (Ben-Naim & Krapivsky, Sec. Ulam's model): M_{n}/M_2^{int(n) // 2} "
            f"grows at rate n a_2/2 − a_n ≠ 0",
            Check(f"fitted growth rate of M_{n}/M_2^{int(n) // 2}", g["fitted"], None,
                  g["predicted"], "exact: moment equations",
                  tolerance=_GROWTH_RELATIVE_TOLERANCE * abs(g["predicted"]))))
    out.append(judge(
        f"P(x, τ) develops the x⁻⁴ tail of f (the exact scaling solution), r = {r:g}",
        Check(f"log-log slope of P(x, τ = {tau_last:g}) on x in "
              f"[{s['parameters']['tail_window'][0]:g}, {s['parameters']['tail_window'][1]:g}]",
              s["tail_slope"][-1], None, s["tail_slope_of_f"],
              "exact: slope of f on the same window", tolerance=_TAIL_SLOPE_TOLERANCE)))
    return out


def plot(c, ax=None):
    """Four panels (new, or the four axes ``ax``): G(q, τ) against f̂; sup|G − f̂| and d_s with
    their contraction bounds against τ; M_n/M_2^{n/2}; P(x, τ) on log axes with f and x⁻⁴."""
    d, s = c.data, c.summary
    sol = d["solution"]
    own = ax is None
    fig, axes = panels(4, ax, width=4.2)
    a0, a1, a2, a3 = axes
    q = sol.q
    show = (q > 1e-2) & (q < 20)
    cols = colors(len(sol.tau))
    for k, tau in enumerate(sol.tau):
        a0.plot(q[show], sol.G[k, show].real, color=cols[k], label=f"τ={tau:g}")
    a0.plot(q[show], f_hat(q[show]), "k--", label="f̂")
    a0.set(xscale="log", xlabel="q", ylabel="G(q, τ)", title="G → f̂")
    a0.legend(fontsize=6)
    tau = np.asarray(s["tau"])
    pos = tau > 0
    a1.semilogy(tau[pos], np.asarray(s["sup_error"])[pos], "k-o", ms=3, label="sup|G − f̂|")
    for i, (sv, dist) in enumerate(d["distances"].items()):
        a1.semilogy(tau[pos], dist[pos], "-", color=f"C{i}", label=f"d_{sv}")
        a1.semilogy(tau[pos], d["bounds"][sv][pos], ":", color=f"C{i}",
                    label=f"bound e^(−γτ) d_{sv}(0)")
    a1.set(xscale="log", xlabel="τ", ylabel="distance to f̂",
           title="distances and contraction bounds")
    a1.legend(fontsize=6)
    for n in (4, 6, 8):
        a2.semilogy(d["moment_tau"], d["moments"][:, n], label=f"M_{n}/M_2^{n // 2}")
    a2.set(xlabel="τ", ylabel="M_n / M_2^(n/2)", title="multiscaling of the moments")
    a2.legend(fontsize=7)
    x = d["x"]
    for k in range(len(sol.tau)):
        pk = d["density"][k]
        ok = pk > 1e-14
        a3.loglog(x[ok], pk[ok], color=cols[k])
    a3.loglog(x, f_density(x), "k--", label="f = 2/(π(1+x²)²)")
    a3.loglog(x, 0.05 * x**-4.0, "k:", label="x⁻⁴")
    a3.set(ylim=(1e-10, 1), xlabel="x = v/v0", ylabel="P(x, τ)", title="the x⁻⁴ tail")
    a3.legend(fontsize=7)
    if own:
        fig.tight_layout()
    return fig


COMPARISON = register(ComparisonSpec(NAME, PRESETS, run, plot, verdicts, order=1))
