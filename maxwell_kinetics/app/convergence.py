"""Error floor against resolution: long solves compared with the exact scaling solution.

For each restitution r and each resolution, :func:`convergence_study` integrates from the unit
Gaussian to ``tau_max`` and records sup_q |G(q, τ) − f̂(q)| at logarithmically spaced τ.  The
*floor* of a run is the median of that error over the last ``floor_points`` saved times, once it
has stopped falling: it is the discretisation error of the stationary state, since the physical
distance to f̂ decays as e^{−γτ}.  A run is *stable* when the error never rises above its floor
by more than a factor 10 after first reaching it.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from particles.validation import check_restitution

from ..grid import RESOLUTIONS, get_resolution
from ..solver import solve

__all__ = ["ConvergenceRun", "convergence_study", "order_of_accuracy", "summarize"]


@dataclass(frozen=True)
class ConvergenceRun:
    """One long solve of :func:`convergence_study`: its error trace against f̂ and its floor.

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1].
    initial : str
        Name of the initial law (a key of :func:`particles.initial.get_law`).
    resolution : str
        Name of the grid (a key of ``maxwell_kinetics.grid.RESOLUTIONS``).
    h : float
        Step of the grid in s = ln q.
    order : int
        Order of the grid's interpolation.
    tau : list of float
        Saved collisions per particle τ.
    sup_error : list of float
        sup_q |G(q, τ) − f̂(q)| at each saved τ.
    floor : float
        Median error over the last ``floor_points`` saved times (NaN by default).
    stable : bool
        False if the error is not finite or rises more than 10 times above the floor after
        first reaching it.
    seconds : float
        Wall-clock time of the solve.
    """

    restitution: float
    initial: str
    resolution: str
    h: float
    order: int
    tau: list = field(repr=False)
    sup_error: list = field(repr=False)
    floor: float = math.nan
    stable: bool = True
    seconds: float = 0.0


def _floor_and_stability(err: np.ndarray, floor_points: int) -> tuple[float, bool]:
    floor = float(np.median(err[-floor_points:]))
    reached = np.nonzero(err <= 1.5 * floor)[0]
    stable = bool(np.all(np.isfinite(err)))
    if stable and reached.size:
        stable = bool(np.all(err[reached[0]:] <= 10.0 * floor))
    return floor, stable


def convergence_study(
    restitutions=(0.0, 0.5),
    resolutions=tuple(RESOLUTIONS),
    tau_max: float = 1e4,
    initial: str = "gaussian",
    points: int = 41,
    floor_points: int = 5,
    progress: bool | None = None,
) -> list[ConvergenceRun]:
    """Run every (r, resolution) pair to ``tau_max`` and return the error traces and floors.

    Each run calls :func:`maxwell_kinetics.solver.solve` and
    :meth:`maxwell_kinetics.solution.Solution.sup_error` (the distance to the exact scaling
    solution f̂(q) = (1 + |q|) e^{−|q|}) at log-spaced τ; see the module docstring for the floor
    and the stability test.

    Parameters
    ----------
    restitutions : sequence of float, default (0.0, 0.5)
        The restitutions r.
    resolutions : sequence of str, optional
        Grid names; by default every name of ``maxwell_kinetics.grid.RESOLUTIONS``.
    tau_max : float, default 1e4
        Last saved τ (collisions per particle).
    initial : str, default "gaussian"
        Name of the initial law.
    points : int, default 41
        Number of log-spaced saved times in [1, tau_max] (duplicates after rounding dropped).
    floor_points : int, default 5
        Number of last saved times whose median error is the floor.
    progress : bool or None, optional
        The solver's progress bar (None, the default: a bar on a terminal or in a notebook,
        nothing otherwise).

    Returns
    -------
    list of ConvergenceRun
        One per (r, resolution), r-major.

    Raises
    ------
    particles.validation.InvalidArgumentError
        For a restitution out of [0, 1] or an unknown resolution (from the validators called).
    """
    taus = np.unique(np.round(np.geomspace(1.0, tau_max, points), 6))
    runs = []
    for r in restitutions:
        r = check_restitution(r)
        for name in resolutions:
            grid = get_resolution(name)
            start = time.perf_counter()
            sol = solve(r, initial, taus, grid, progress=progress)
            err = sol.sup_error()
            floor, stable = _floor_and_stability(err, floor_points)
            runs.append(
                ConvergenceRun(r, initial, grid.name, grid.h, grid.order, taus.tolist(),
                               err.tolist(), floor, stable, time.perf_counter() - start)
            )
    return runs


def order_of_accuracy(runs: list[ConvergenceRun]) -> dict[str, float]:
    """Least-squares slope of log(floor) against log(h), per restitution.

    Parameters
    ----------
    runs : list of ConvergenceRun
        Runs of :func:`convergence_study`.

    Returns
    -------
    dict of str to float
        The fitted order, keyed by ``f"{r:g}"``; restitutions with fewer than two runs are left
        out.
    """
    out = {}
    for r in sorted({run.restitution for run in runs}):
        sel = [run for run in runs if run.restitution == r]
        if len(sel) >= 2:
            h = np.log([run.h for run in sel])
            e = np.log([run.floor for run in sel])
            out[f"{r:g}"] = float(np.polyfit(h, e, 1)[0])
    return out


def summarize(runs: list[ConvergenceRun]) -> dict:
    """The runs, a table of their floors and the fitted order of accuracy (JSON-able).

    Parameters
    ----------
    runs : list of ConvergenceRun
        Runs of :func:`convergence_study`.

    Returns
    -------
    dict
        ``runs`` (each run as a dict), ``table`` (restitution, resolution, h, floor, stable,
        seconds per run) and ``order_fit`` (from :func:`order_of_accuracy`).
    """
    return {
        "runs": [asdict(run) for run in runs],
        "table": [
            {"restitution": run.restitution, "resolution": run.resolution, "h": run.h,
             "floor": run.floor, "stable": run.stable, "seconds": run.seconds}
            for run in runs
        ],
        "order_fit": order_of_accuracy(runs),
    }
